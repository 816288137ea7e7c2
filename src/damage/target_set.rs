//! A ready-made store of dentable bodies keyed by the caller's ids, for callers whose engine
//! keeps no triangle meshes of its own (a Rapier world, a hand-written solver): it holds each
//! target's mesh, pose and settings, answers [`DentTargets`], and takes a [`DamagePlan`](super::DamagePlan)'s meshes.

use std::collections::{HashMap, HashSet};
use std::hash::Hash;

use glam::Affine3A;

use super::{BodyFracture, DentTargets, DentedTarget, TargetView};
use crate::dent::{DentError, DentSettings, radius_about_origin};
use crate::fracture::{FractureError, FractureSettings, check_mesh_closed};
use crate::mesh::TriMesh;

/// One dentable body.
#[derive(Debug, Clone)]
struct Entry {
    mesh: TriMesh,
    to_world: Affine3A,
    settings: DentSettings,
    radius: f32,
    fracture: Option<FractureSettings>,
}

/// Dentable bodies (mesh, pose, settings) and other known bodies, by the caller's ids.
#[derive(Debug, Clone)]
pub struct TargetSet<K> {
    targets: HashMap<K, Entry>,
    others: HashSet<K>,
}

impl<K> Default for TargetSet<K> {
    fn default() -> Self {
        Self { targets: HashMap::new(), others: HashSet::new() }
    }
}

impl<K: Copy + Eq + Hash> TargetSet<K> {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds (or replaces) dentable body `key` with `mesh` (its own coordinates, m), mesh → world
    /// transform `to_world` (rigid) and `settings`.
    ///
    /// # Errors
    /// Invalid settings or a non-finite transform; the set is unchanged then.
    pub fn insert(
        &mut self,
        key: K,
        mesh: TriMesh,
        to_world: Affine3A,
        settings: DentSettings,
    ) -> Result<(), DentError> {
        settings.validate()?;
        check_pose(to_world)?;
        let radius = radius_about_origin(&mesh);
        self.others.remove(&key);
        self.targets.insert(key, Entry { mesh, to_world, settings, radius, fracture: None });
        Ok(())
    }

    /// Adds body `key`, which hits others but does not dent.
    pub fn insert_rigid(&mut self, key: K) {
        if !self.targets.contains_key(&key) {
            self.others.insert(key);
        }
    }

    /// Removes body `key`; returns its mesh when it was dentable.
    pub fn remove(&mut self, key: K) -> Option<TriMesh> {
        self.others.remove(&key);
        self.targets.remove(&key).map(|e| e.mesh)
    }

    /// Moves dentable body `key` to `to_world` (call each step before planning).
    ///
    /// # Errors
    /// A non-finite transform, or an unknown key; nothing changes then.
    pub fn set_pose(&mut self, key: K, to_world: Affine3A) -> Result<(), DentError> {
        check_pose(to_world)?;
        let entry =
            self.targets.get_mut(&key).ok_or_else(|| crate::dent::invalid("key", "?", "is not a dentable body"))?;
        entry.to_world = to_world;
        Ok(())
    }

    /// Makes dentable body `key` breakable with `settings` (`None`: never breaks).
    ///
    /// # Errors
    /// An unknown key, invalid settings, or a mesh that is not closed (it bounds no solid to
    /// break; [`FractureError::OpenMesh`]); nothing changes then.
    pub fn set_fracture(&mut self, key: K, settings: Option<FractureSettings>) -> Result<(), FractureError> {
        let entry = self.targets.get_mut(&key).ok_or_else(|| FractureError::InvalidParameter {
            name: "key",
            value: "?".into(),
            reason: "is not a dentable body: insert it first",
        })?;
        if let Some(settings) = &settings {
            settings.validate()?;
            check_mesh_closed(&entry.mesh)?;
        }
        entry.fracture = settings;
        Ok(())
    }

    /// Takes a plan's fracture (after its [`apply`](Self::apply)): the body's rest becomes its
    /// mesh, or the body is removed when the pattern took it whole. The pieces are the
    /// caller's to add (with [`insert`](Self::insert) under ids of its own, to dent them too).
    pub fn apply_fracture(&mut self, fracture: &BodyFracture<K>) {
        match &fracture.rest {
            Some(rest) => {
                if let Some(entry) = self.targets.get_mut(&fracture.body) {
                    entry.radius = radius_about_origin(rest);
                    entry.mesh = rest.clone();
                }
            }
            None => {
                self.targets.remove(&fracture.body);
            }
        }
    }

    /// Dentable body `key`'s mesh, its own coordinates.
    pub fn mesh(&self, key: K) -> Option<&TriMesh> {
        self.targets.get(&key).map(|e| &e.mesh)
    }

    /// Dentable body `key`'s mesh → world transform.
    pub fn pose(&self, key: K) -> Option<Affine3A> {
        self.targets.get(&key).map(|e| e.to_world)
    }

    /// Dentable body `key`'s settings.
    pub fn settings(&self, key: K) -> Option<&DentSettings> {
        self.targets.get(&key).map(|e| &e.settings)
    }

    /// Takes a plan's new meshes ([`DamagePlan::targets`](super::DamagePlan::targets)) and returns each body's moved
    /// vertices, for the caller's collider refits (rebuild instead where the plan's target says
    /// [`topology_changed`](DentedTarget::topology_changed): it was refined). Dents of bodies no
    /// longer in the set are dropped.
    pub fn apply(&mut self, dented: Vec<DentedTarget<K>>) -> Vec<(K, Vec<u32>)> {
        let mut moved = Vec::with_capacity(dented.len());
        for target in dented {
            if let Some(entry) = self.targets.get_mut(&target.key) {
                entry.mesh = target.mesh;
                moved.push((target.key, target.moved));
            }
        }
        moved
    }
}

impl<K: Copy + Eq + Hash> DentTargets<K> for TargetSet<K> {
    fn contains(&self, key: K) -> bool {
        self.targets.contains_key(&key) || self.others.contains(&key)
    }

    fn target(&self, key: K) -> Option<TargetView<'_>> {
        let e = self.targets.get(&key)?;
        Some(TargetView {
            mesh: &e.mesh,
            to_world: e.to_world,
            settings: &e.settings,
            radius: e.radius,
            fracture: e.fracture.as_ref(),
        })
    }
}

fn check_pose(to_world: Affine3A) -> Result<(), DentError> {
    if to_world.is_finite() { Ok(()) } else { Err(crate::dent::invalid("to_world", to_world, "must be finite")) }
}
