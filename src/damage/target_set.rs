//! A ready-made store of dentable bodies keyed by the caller's ids, for callers whose engine
//! keeps no triangle meshes of its own (a Rapier world, a hand-written solver): it holds each
//! target's mesh, pose and settings, answers [`DentTargets`], and takes a [`DamagePlan`](super::DamagePlan)'s meshes.

use std::collections::{HashMap, HashSet};
use std::hash::Hash;

use glam::Affine3A;

use super::{DentTargets, DentedTarget, TargetView};
use crate::dent::{DentError, DentSettings, radius_about_origin};
use crate::mesh::TriMesh;

/// One dentable body.
#[derive(Debug, Clone)]
struct Entry {
    mesh: TriMesh,
    to_world: Affine3A,
    settings: DentSettings,
    radius: f32,
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
        self.targets.insert(key, Entry { mesh, to_world, settings, radius });
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

    /// Dentable body `key`'s mesh, its own coordinates.
    pub fn mesh(&self, key: K) -> Option<&TriMesh> {
        self.targets.get(&key).map(|e| &e.mesh)
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
        Some(TargetView { mesh: &e.mesh, to_world: e.to_world, settings: &e.settings, radius: e.radius })
    }
}

fn check_pose(to_world: Affine3A) -> Result<(), DentError> {
    if to_world.is_finite() { Ok(()) } else { Err(crate::dent::invalid("to_world", to_world, "must be finite")) }
}
