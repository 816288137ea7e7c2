//! Dentable colliders: a step's impacts → hits → dents ([`dentbend::dent::Damage`]) → collider
//! refits, all or nothing.
//!
//! A dentable collider's mesh is in the collider's own frame (m); its pose is the collider's
//! pose at the start of the step. Tri-mesh targets are refitted in place, convex colliders
//! of dynamic bodies get a new hull. Both bodies of a pair may dent (Jacobi: both maps from
//! the undented surfaces).

use std::collections::HashMap;
use std::time::Instant;

use dentbend::dent::{AppliedDent, BodyState, Damage, DentBackend, DentSettings, Hit, Impact, Surface, TargetSet};
use dentbend::mesh::TriMesh;
use glam::{Affine3A, Vec3};
use rapier3d::prelude::{ColliderHandle, ColliderSet, RigidBodySet};

use crate::refit::{Refit, ShapeKind, prepare_refit, rebuild_trimesh, shape_kind};
use crate::{AdapterError, BodyStates, Contact};

/// What one [`Dentables::process`] call did.
#[derive(Debug, Clone, Default)]
pub struct DentReport {
    /// Every dent made (target and projectile are colliders).
    pub dents: Vec<AppliedDent<ColliderHandle>>,
    /// Colliders refitted, with the number of vertices that moved.
    pub refitted: Vec<(ColliderHandle, usize)>,
    /// Seconds spent deciding and computing the dents (wall clock).
    pub dent_seconds: f64,
    /// Seconds spent refitting colliders (wall clock).
    pub collider_seconds: f64,
}

/// The dentable colliders of a Rapier world, and the surfaces of the others that hit them.
#[derive(Debug, Default)]
pub struct Dentables {
    targets: TargetSet<ColliderHandle>,
    kinds: HashMap<ColliderHandle, ShapeKind>,
    surfaces: HashMap<ColliderHandle, TriMesh>,
    damage: Damage<ColliderHandle>,
    step: u64,
}

impl Dentables {
    /// No dentable collider.
    pub fn new() -> Self {
        Self::default()
    }

    /// Makes collider `handle` dentable with `mesh` (its vertices in the collider's frame, m:
    /// the mesh the collider was built from, see [`trimesh_collider`](crate::trimesh_collider)
    /// and [`convex_collider`](crate::convex_collider)) and `settings`.
    ///
    /// # Errors
    /// [`AdapterError::UnknownCollider`], [`AdapterError::Refit`] for a shape that is neither a
    /// tri-mesh nor convex (or a tri-mesh of another vertex count), or invalid settings; nothing
    /// changes then.
    pub fn insert(
        &mut self,
        colliders: &ColliderSet,
        handle: ColliderHandle,
        mesh: TriMesh,
        settings: DentSettings,
    ) -> Result<(), AdapterError> {
        let collider = colliders.get(handle).ok_or(AdapterError::UnknownCollider(handle))?;
        let kind = shape_kind(collider).ok_or_else(|| AdapterError::Refit {
            collider: handle,
            reason: "only tri-mesh and convex colliders can dent".into(),
        })?;
        prepare_refit(handle, collider, kind, &mesh, &[])?;
        self.targets.insert(handle, mesh, crate::to_affine(collider.position()), settings)?;
        self.kinds.insert(handle, kind);
        self.surfaces.remove(&handle);
        Ok(())
    }

    /// Gives collider `handle`, which does not dent, the surface `mesh` (collider frame, m) it
    /// dents others with. Colliders with neither a surface nor a dentable mesh dent nothing.
    ///
    /// # Errors
    /// [`AdapterError::UnknownCollider`].
    pub fn insert_projectile(
        &mut self,
        colliders: &ColliderSet,
        handle: ColliderHandle,
        mesh: TriMesh,
    ) -> Result<(), AdapterError> {
        colliders.get(handle).ok_or(AdapterError::UnknownCollider(handle))?;
        self.targets.insert_rigid(handle);
        self.surfaces.insert(handle, mesh);
        Ok(())
    }

    /// Forgets collider `handle` (call when removing it from Rapier); returns its mesh when
    /// it was dentable.
    pub fn remove(&mut self, handle: ColliderHandle) -> Option<TriMesh> {
        self.kinds.remove(&handle);
        self.surfaces.remove(&handle);
        self.damage.forget(handle);
        self.targets.remove(handle)
    }

    /// Dentable collider `handle`'s current mesh (collider frame, m).
    pub fn mesh(&self, handle: ColliderHandle) -> Option<&TriMesh> {
        self.targets.mesh(handle)
    }

    /// The surface collider `handle` dents others with (collider frame, m): its dentable mesh
    /// or its projectile surface.
    pub fn surface(&self, handle: ColliderHandle) -> Option<&TriMesh> {
        self.targets.mesh(handle).or_else(|| self.surfaces.get(&handle))
    }

    /// Whether collider `handle` dents.
    pub fn is_dentable(&self, handle: ColliderHandle) -> bool {
        self.kinds.contains_key(&handle)
    }

    /// The dentable colliders.
    pub fn handles(&self) -> impl Iterator<Item = ColliderHandle> + '_ {
        self.kinds.keys().copied()
    }

    /// Dents the dentable colliders hit in `contacts` (one step's impacts, world coordinates at
    /// the start of the step, with the bodies' states then in `states`), on `backend`, then
    /// refits their colliders and moves dynamic projectiles into their dents when the
    /// target's settings ask for it.
    ///
    /// # Errors
    /// A contact with NaN/∞ or a zero normal, a collider or body that is unknown or was
    /// removed, a failed dent or refit: the error names it and no mesh, collider or body
    /// changed.
    pub fn process(
        &mut self,
        contacts: &[Contact],
        states: &BodyStates,
        bodies: &mut RigidBodySet,
        colliders: &mut ColliderSet,
        backend: &mut dyn DentBackend<ColliderHandle>,
    ) -> Result<DentReport, AdapterError> {
        let started = Instant::now();
        let step = self.step + 1;
        let sides = self.sides(contacts, states, bodies, colliders)?;
        // Poses are bookkeeping, refreshed on every call: setting them changes no mesh.
        for side in &sides {
            self.targets.set_pose(side.target, side.target_pose)?;
        }
        let targets = &self.targets;
        let hits: Vec<Hit<'_, ColliderHandle>> = sides.iter().filter_map(|s| self.hit(s)).collect();
        if hits.is_empty() {
            // Nothing to dent; progressive dents gone stale end at the next hit's planning.
            self.step = step;
            return Ok(DentReport { dent_seconds: started.elapsed().as_secs_f64(), ..DentReport::default() });
        }
        let mut damage = self.damage.clone();
        let plan = damage.plan(targets, &hits, step, backend)?;
        let dent_seconds = started.elapsed().as_secs_f64();

        let refit_start = Instant::now();
        let mut refits = Vec::with_capacity(plan.targets.len());
        for t in &plan.targets {
            let collider = colliders.get(t.key).ok_or(AdapterError::UnknownCollider(t.key))?;
            // A refined mesh has new vertices and faces: its tri-mesh collider is rebuilt.
            let refit = match self.kinds[&t.key] {
                ShapeKind::TriMesh if t.topology_changed => rebuild_trimesh(t.key, collider, &t.mesh)?,
                kind => prepare_refit(t.key, collider, kind, &t.mesh, &t.moved)?,
            };
            refits.push((t.key, refit, t.moved.len()));
        }
        let refit_seconds = refit_start.elapsed().as_secs_f64();

        // Everything checked: commit.
        let commit_start = Instant::now();
        self.damage = damage;
        self.step = step;
        self.targets.apply(plan.targets);
        let dent_seconds = dent_seconds + commit_start.elapsed().as_secs_f64();
        let commit_start = Instant::now();
        let mut refitted = Vec::with_capacity(refits.len());
        for (key, refit, moved) in refits {
            commit(colliders, key, refit);
            refitted.push((key, moved));
        }
        move_projectiles(&plan.dents, bodies, colliders);
        let collider_seconds = refit_seconds + commit_start.elapsed().as_secs_f64();
        Ok(DentReport { dents: plan.dents, refitted, dent_seconds, collider_seconds })
    }

    /// Every (target, projectile) side of `contacts` whose target dents and whose projectile
    /// has a surface, validated.
    fn sides(
        &self,
        contacts: &[Contact],
        states: &BodyStates,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
    ) -> Result<Vec<Side>, AdapterError> {
        let mut sides = Vec::new();
        for c in contacts {
            c.validate()?;
            let side = |h| states.collider_state(h, bodies, colliders).map(|(pose, state)| (h, pose, state));
            let (a, b) = (side(c.collider1)?, side(c.collider2)?);
            for (target, projectile, into_target) in [(a, b, -c.normal), (b, a, c.normal)] {
                let progressive = self.targets.settings(target.0).is_some_and(|s| s.progressive);
                let surface = self.is_dentable(projectile.0) || self.surfaces.contains_key(&projectile.0);
                if self.is_dentable(target.0) && surface && (c.started || progressive) {
                    sides.push(Side {
                        target: target.0,
                        projectile: projectile.0,
                        target_pose: target.1,
                        projectile_pose: projectile.1,
                        target_state: target.2,
                        projectile_state: projectile.2,
                        point: c.point,
                        normal: into_target,
                    });
                }
            }
        }
        Ok(sides)
    }

    /// The hit of `side`; `None` when its impact separates by more than rounding.
    fn hit(&self, side: &Side) -> Option<Hit<'_, ColliderHandle>> {
        let mesh = self.targets.mesh(side.projectile).or_else(|| self.surfaces.get(&side.projectile))?;
        let impact = Impact::from_contact(side.point, side.normal, &side.target_state, &side.projectile_state).ok()?;
        Some(Hit {
            target: side.target,
            projectile: side.projectile,
            impact,
            target_state: side.target_state,
            projectile_state: side.projectile_state,
            projectile_surface: Surface { mesh, to_world: side.projectile_pose },
        })
    }
}

/// One side of a contact: the target, what hit it, and both states.
#[derive(Debug, Clone, Copy)]
struct Side {
    target: ColliderHandle,
    projectile: ColliderHandle,
    target_pose: Affine3A,
    projectile_pose: Affine3A,
    target_state: BodyState,
    projectile_state: BodyState,
    point: Vec3,
    normal: Vec3,
}

fn commit(colliders: &mut ColliderSet, key: ColliderHandle, refit: Refit) {
    if let Some(collider) = colliders.get_mut(key) {
        refit.commit(collider);
    }
}

/// Moves each dynamic projectile by its dent's offset (world, m).
fn move_projectiles(dents: &[AppliedDent<ColliderHandle>], bodies: &mut RigidBodySet, colliders: &ColliderSet) {
    for dent in dents.iter().filter(|d| d.projectile_offset != Vec3::ZERO) {
        let Some(body) = colliders.get(dent.projectile).and_then(|c| c.parent()) else { continue };
        if let Some(rb) = bodies.get_mut(body)
            && rb.is_dynamic()
        {
            let t = rb.translation() + dent.projectile_offset;
            rb.set_translation(t, true);
        }
    }
}
