//! Dentable colliders: a step's impacts → hits → dents ([`dentbend::damage::Damage`]) → collider
//! refits, all or nothing.
//!
//! A dentable collider's mesh is in the collider's own frame (m); its pose is the collider's
//! pose at the start of the step. Tri-mesh targets are refitted in place, convex colliders
//! of dynamic bodies get a new hull. Both bodies of a pair may dent (Jacobi: both maps from
//! the undented surfaces).

use std::time::Instant;

use dentbend::damage::{AppliedDent, Damage, DentBackend, DentedTarget, Hit, TargetSet};
use dentbend::dent::{BodyState, DentSettings, Impact, Surface, changed_vertices};
use dentbend::fracture::FractureSettings;
use dentbend::mesh::TriMesh;
use dentbend::record::{BodyDamage, DamageFile, DamageRecorder, DentForm, Projectiles, RecordForms, replay_body};
use glam::{Affine3A, Vec3};
use rapier3d::prelude::{Collider, ColliderHandle, ColliderSet, RigidBodySet};
use rayon::prelude::*;
use rustc_hash::FxHashMap as HashMap;

use crate::fracture::{self, BrokenCollider, PreparedFracture};
use crate::refit::{Refit, ShapeKind, prepare_refit, rebuild_trimesh, shape_kind};
use crate::{AdapterError, BodyStates, Contact};

/// What one [`Dentables::process`] call did.
#[derive(Debug, Clone, Default)]
pub struct DentReport {
    /// Every dent made (target and projectile are colliders).
    pub dents: Vec<AppliedDent<ColliderHandle>>,
    /// Colliders refitted, with the vertices that moved (ascending; a refined mesh's new
    /// vertices included).
    pub refitted: Vec<(ColliderHandle, Vec<u32>)>,
    /// Contacts left out because a collider or body they name was removed after the step.
    pub skipped: Vec<Contact>,
    /// Dentable or projectile colliders no longer in the collider set, forgotten.
    pub forgotten: Vec<ColliderHandle>,
    /// Breakable colliders that broke, with the bodies made of their pieces.
    pub fractures: Vec<BrokenCollider>,
    /// Seconds spent deciding and computing the dents (wall clock).
    pub dent_seconds: f64,
    /// Seconds spent refitting colliders (wall clock).
    pub collider_seconds: f64,
}

/// The dentable colliders of a Rapier world, and the surfaces of the others that hit them.
#[derive(Debug)]
pub struct Dentables {
    targets: TargetSet<ColliderHandle>,
    kinds: HashMap<ColliderHandle, ShapeKind>,
    surfaces: HashMap<ColliderHandle, TriMesh>,
    damage: Damage<ColliderHandle>,
    recorder: DamageRecorder<ColliderHandle>,
    step: u64,
}

impl Default for Dentables {
    fn default() -> Self {
        Self {
            targets: TargetSet::default(),
            kinds: HashMap::default(),
            surfaces: HashMap::default(),
            damage: Damage::default(),
            recorder: DamageRecorder::new(RecordForms::EDITS),
            step: 0,
        }
    }
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
    /// [`AdapterError::UnknownCollider`]; [`AdapterError::Refit`] naming the fix for a shape
    /// that is neither a tri-mesh nor convex (a primitive, a compound, a height field), for a
    /// convex collider on a body that is not dynamic (its hull cannot follow a dent inward),
    /// and for a collider that was not built from `mesh` (another mesh, a scaled shape, a
    /// dented mesh given back without [`restore`](Self::restore)); invalid settings; nothing
    /// changes then.
    pub fn insert(
        &mut self,
        colliders: &ColliderSet,
        bodies: &RigidBodySet,
        handle: ColliderHandle,
        mesh: TriMesh,
        settings: DentSettings,
    ) -> Result<(), AdapterError> {
        let collider = colliders.get(handle).ok_or(AdapterError::UnknownCollider(handle))?;
        let kind = dentable_kind(handle, collider, bodies)?;
        check_built_from(handle, collider, kind, &mesh)?;
        if kind == ShapeKind::TriMesh {
            // A tri-mesh holds the mesh's vertices one for one; a hull was compared above (a
            // throwaway hull here would cost as much as a dent's refit).
            prepare_refit(handle, collider, kind, &mesh, &[])?;
        }
        self.targets.insert(handle, mesh, crate::to_affine(collider.position()), settings)?;
        self.kinds.insert(handle, kind);
        self.surfaces.remove(&handle);
        Ok(())
    }

    /// Makes dentable collider `handle` breakable with `settings` (`None`: never breaks): a hit
    /// whose energy passes its toughness, or dents adding up past its dent limit, break it
    /// along its pattern placed at the hit ([`DentReport::fractures`]).
    ///
    /// # Errors
    /// [`AdapterError::Fracture`] for a collider that does not dent, invalid settings or a mesh
    /// that is not closed; nothing changes then.
    pub fn set_fracture(
        &mut self,
        handle: ColliderHandle,
        settings: Option<FractureSettings>,
    ) -> Result<(), AdapterError> {
        self.targets.set_fracture(handle, settings).map_err(|error| AdapterError::Fracture { collider: handle, error })
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

    /// Forgets collider `handle` (colliders removed from Rapier are forgotten by the next
    /// [`process`](Self::process) anyway); returns its mesh when it was dentable. Its recorded
    /// damage stays in [`damage_file`](Self::damage_file).
    pub fn remove(&mut self, handle: ColliderHandle) -> Option<TriMesh> {
        self.kinds.remove(&handle);
        self.surfaces.remove(&handle);
        self.damage.forget(handle);
        self.targets.remove(handle)
    }

    /// Records dentable collider `handle`'s damage from now on, as the body `name` of
    /// [`damage_file`](Self::damage_file): its mesh now is the base a restore starts from.
    ///
    /// # Errors
    /// [`AdapterError::Refit`] when `handle` does not dent.
    pub fn record_damage(&mut self, handle: ColliderHandle, name: impl Into<String>) -> Result<(), AdapterError> {
        let mesh = self.targets.mesh(handle).ok_or_else(|| not_dentable(handle))?;
        self.recorder.track(handle, name, mesh);
        Ok(())
    }

    /// Every recorded collider's damage (exact mesh edits, whatever backend dented), for a save
    /// file ([`DamageFile::to_json`] with dentbend's `io` feature).
    pub fn damage_file(&self) -> DamageFile {
        self.recorder.file()
    }

    /// Gives dentable collider `handle` the damage `body` recorded (saved from a collider
    /// inserted with the mesh this one has now): replays it on the mesh, refits the collider
    /// (rebuilds a tri-mesh whose faces changed) and, when the collider's damage is recorded,
    /// continues its record from `body`. Returns the vertices that moved.
    ///
    /// # Errors
    /// [`AdapterError::Record`] when the damage was recorded on another mesh or does not
    /// replay, [`AdapterError::Refit`]; nothing changes then.
    pub fn restore(
        &mut self,
        colliders: &mut ColliderSet,
        handle: ColliderHandle,
        body: &BodyDamage,
    ) -> Result<Vec<u32>, AdapterError> {
        let now = self.targets.mesh(handle).ok_or_else(|| not_dentable(handle))?;
        let restored = replay_body(body, now, DentForm::Edits, &Projectiles::new())?.mesh;
        let moved = changed_vertices(now, &restored);
        let topology_changed = now.faces() != restored.faces();
        let collider = colliders.get(handle).ok_or(AdapterError::UnknownCollider(handle))?;
        let refit = match self.kinds[&handle] {
            ShapeKind::TriMesh if topology_changed => rebuild_trimesh(handle, collider, &restored)?,
            kind => prepare_refit(handle, collider, kind, &restored, &moved)?,
        };
        self.damage.forget(handle);
        if self.recorder.body(handle).is_some() {
            self.recorder.resume(handle, body.clone());
        }
        let refinement = Default::default();
        self.targets.apply(vec![DentedTarget {
            key: handle,
            mesh: restored,
            moved: moved.clone(),
            refinement,
            topology_changed,
        }]);
        commit(colliders, handle, refit);
        Ok(moved)
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

    /// Whether the adapter dents collider `handle` or dents with it.
    pub fn knows(&self, handle: ColliderHandle) -> bool {
        self.kinds.contains_key(&handle) || self.surfaces.contains_key(&handle)
    }

    /// Every collider the adapter dents or dents with: the dentable ones and the projectiles.
    pub fn known(&self) -> impl Iterator<Item = ColliderHandle> + '_ {
        self.kinds.keys().chain(self.surfaces.keys()).copied()
    }

    /// Dents the dentable colliders hit in `contacts` (one step's impacts, world coordinates at
    /// the start of the step, with the bodies' states then in `states`), on `backend`, then
    /// refits their colliders and moves dynamic projectiles into their dents when the
    /// target's settings ask for it. Contacts naming a collider or body removed since the step
    /// are skipped and reported (one on a moving body, or one the adapter dents or dents with;
    /// a fixed collider it does not know, removed after the step, is named as unknown);
    /// dentable and projectile colliders no longer in `colliders` are forgotten.
    ///
    /// # Errors
    /// A contact with NaN/∞ or a zero normal, a collider or body that was never known, a
    /// failed dent or refit: the error names it and no mesh, collider or body changed.
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
        let (live, skipped) = live_contacts(contacts, states, bodies, colliders, |h| self.knows(h));
        let forgotten: Vec<ColliderHandle> =
            self.kinds.keys().chain(self.surfaces.keys()).copied().filter(|&h| !colliders.contains(h)).collect();
        let sides = self.sides(&live, states, bodies, colliders)?;
        // Poses are bookkeeping, refreshed on every call: setting them changes no mesh.
        for side in &sides {
            self.targets.set_pose(side.target, side.target_pose)?;
        }
        let (targets, surfaces) = (&self.targets, &self.surfaces);
        let hits: Vec<Hit<'_, ColliderHandle>> = sides.iter().filter_map(|s| hit(targets, surfaces, s)).collect();
        if hits.is_empty() {
            // Nothing to dent; progressive dents gone stale end at the next hit's planning.
            self.step = step;
            self.forget(&forgotten);
            let dent_seconds = started.elapsed().as_secs_f64();
            return Ok(DentReport { dent_seconds, skipped, forgotten, ..DentReport::default() });
        }
        let mut damage = self.damage.clone();
        let plan = damage.plan(targets, &hits, step, backend)?;
        let dent_seconds = started.elapsed().as_secs_f64();

        let refit_start = Instant::now();
        let broken = |key| plan.fractures.iter().any(|f| f.body == key);
        let refittable: Vec<&DentedTarget<ColliderHandle>> = plan.targets.iter().filter(|t| !broken(t.key)).collect();
        // Tri-mesh refits of an unchanged topology are checked here and applied in place, while
        // the others (hulls, rebuilt tri-meshes) are made on the pool from copies of their
        // colliders (a shape is shared, not copied); undone if anything below fails.
        let mut in_place: Vec<(&DentedTarget<ColliderHandle>, Refit)> = Vec::new();
        let mut others: Vec<(&DentedTarget<ColliderHandle>, Collider)> = Vec::new();
        for t in &refittable {
            let collider = colliders.get(t.key).ok_or(AdapterError::UnknownCollider(t.key))?;
            match self.kinds[&t.key] {
                ShapeKind::TriMesh if !t.topology_changed => {
                    in_place.push((t, prepare_refit(t.key, collider, ShapeKind::TriMesh, &t.mesh, &t.moved)?));
                }
                _ => others.push((t, collider.clone())),
            }
        }
        let kinds = &self.kinds;
        let prepare = |(t, collider): &(&DentedTarget<ColliderHandle>, Collider)| {
            // A refined mesh has new vertices and faces: its tri-mesh collider is rebuilt.
            match kinds[&t.key] {
                ShapeKind::TriMesh => rebuild_trimesh(t.key, collider, &t.mesh),
                kind => prepare_refit(t.key, collider, kind, &t.mesh, &t.moved),
            }
            .map(|refit| (t.key, refit))
        };
        let (made, ()) = rayon::join(
            || others.par_iter().map(prepare).collect::<Result<Vec<_>, _>>(),
            || in_place.iter().for_each(|(t, refit)| commit(colliders, t.key, refit.clone())),
        );
        // Whatever fails from here puts the in-place refits back.
        let undo = |colliders: &mut ColliderSet| undo_in_place(colliders, targets, &in_place);
        let refits = made.inspect_err(|_| undo(colliders))?;
        let mut refitted: Vec<(ColliderHandle, Vec<u32>)> =
            refittable.iter().map(|t| (t.key, t.moved.clone())).collect();
        let fractures: Vec<PreparedFracture> = plan
            .fractures
            .iter()
            .map(|f| fracture::prepare(colliders, self.kinds[&f.body], f))
            .collect::<Result<_, _>>()
            .inspect_err(|_| undo(colliders))?;
        let refit_seconds = refit_start.elapsed().as_secs_f64();
        // The record comes last of what may fail: it fails (recording nothing) on a mesh changed
        // behind the recorder's back; nothing after it can.
        let record_start = Instant::now();
        self.recorder.record(targets, &hits, &plan).inspect_err(|_| undo(colliders))?;

        // Everything checked: commit.
        let commit_start = Instant::now();
        self.damage = damage;
        self.step = step;
        self.targets.apply(plan.targets);
        self.forget(&forgotten);
        let dent_seconds =
            dent_seconds + commit_start.elapsed().as_secs_f64() + (commit_start - record_start).as_secs_f64();
        let commit_start = Instant::now();
        for (key, refit) in refits {
            commit(colliders, key, refit);
        }
        move_projectiles(&plan.dents, bodies, colliders);
        let mut broken = Vec::with_capacity(fractures.len());
        for (prepared, fracture) in fractures.into_iter().zip(plan.fractures) {
            self.targets.apply_fracture(&fracture);
            let (made, pieces) = prepared.commit(bodies, colliders, fracture);
            if made.whole {
                self.remove(made.collider);
            } else {
                refitted.push((
                    made.collider,
                    (0..self.targets.mesh(made.collider).map_or(0, |m| m.vertex_count() as u32)).collect(),
                ));
            }
            for (collider, mesh) in pieces {
                self.targets.insert_rigid(collider);
                self.surfaces.insert(collider, mesh);
            }
            broken.push(made);
        }
        let collider_seconds = refit_seconds + commit_start.elapsed().as_secs_f64();
        Ok(DentReport {
            dents: plan.dents,
            refitted,
            skipped,
            forgotten,
            fractures: broken,
            dent_seconds,
            collider_seconds,
        })
    }

    /// Forgets colliders removed from Rapier.
    fn forget(&mut self, gone: &[ColliderHandle]) {
        for &h in gone {
            self.remove(h);
        }
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
}

/// `contacts` split into those whose colliders and bodies are all still there and those that
/// name one removed since the step.
pub(crate) fn live_contacts(
    contacts: &[Contact],
    states: &BodyStates,
    bodies: &RigidBodySet,
    colliders: &ColliderSet,
    known: impl Fn(ColliderHandle) -> bool,
) -> (Vec<Contact>, Vec<Contact>) {
    let present = |h: ColliderHandle| match states.collider(h, bodies, colliders) {
        // A collider whose body was removed without it is left without a parent: its recorded
        // parent is gone.
        Ok(c) => c.parent().or(states.collider_parent(h)).is_none_or(|b| bodies.contains(b)),
        Err(AdapterError::RemovedBody(_) | AdapterError::RemovedCollider(_)) => false,
        // A fixed collider the adapter knows is not recorded: gone, it was removed.
        Err(AdapterError::UnknownCollider(_)) if known(h) => false,
        // Never known: kept, so that the error names it.
        Err(_) => true,
    };
    contacts.iter().partition(|c| present(c.collider1) && present(c.collider2))
}

/// The refit kind of a collider that may dent, or why it may not (with the fix).
fn dentable_kind(
    handle: ColliderHandle,
    collider: &Collider,
    bodies: &RigidBodySet,
) -> Result<ShapeKind, AdapterError> {
    let refused = |reason: String| AdapterError::Refit { collider: handle, reason };
    let Some(kind) = shape_kind(collider) else {
        let shape = collider.shape().shape_type();
        let part =
            if collider.shape().as_compound().is_some() { " (give each part a collider of its own)" } else { "" };
        return Err(refused(format!(
            "a {shape:?} collider cannot dent: only tri-mesh and convex colliders follow a mesh; build it from the \
             mesh with trimesh_collider(&mesh) (fixed and kinematic bodies) or convex_collider(&mesh) (dynamic \
             bodies){part}"
        )));
    };
    let dynamic = collider.parent().and_then(|b| bodies.get(b)).is_some_and(|b| b.is_dynamic());
    if kind == ShapeKind::Convex && !dynamic {
        return Err(refused(
            "a convex collider on a fixed or kinematic body cannot follow a dent: its hull stays over the crater; \
             build it with trimesh_collider(&mesh)"
                .into(),
        ));
    }
    Ok(kind)
}

/// Checks that `collider` was built from `mesh` as it is: a tri-mesh with its vertices, or a
/// hull with its bounds (a scale or another mesh would leave the collider off the surface). A
/// dented mesh given back to a hull built undented is caught only when the dent changed the
/// hull's bounds; for a tri-mesh, always.
fn check_built_from(
    handle: ColliderHandle,
    collider: &Collider,
    kind: ShapeKind,
    mesh: &TriMesh,
) -> Result<(), AdapterError> {
    let refused = |what: String| AdapterError::Refit {
        collider: handle,
        reason: format!(
            "{what}: the collider was not built from this mesh (scaled, or another mesh); build it with \
             trimesh_collider(&mesh) or convex_collider(&mesh) from the mesh given here, and to continue from saved \
             damage insert the undamaged mesh and call Dentables::restore"
        ),
    };
    let (lo, hi) = mesh.bounds();
    let extent = lo.abs().max(hi.abs()).max_element();
    // f32 rounding of an exact copy is zero; a few ulps of the mesh's extent leave room for a
    // shape that stores its vertices through another type.
    let tolerance = 4.0 * f32::EPSILON * extent.max(1e-6);
    match kind {
        ShapeKind::TriMesh => {
            let Some(shape) = collider.shape().as_trimesh() else { return Ok(()) };
            if let Some((k, (a, b))) = shape
                .vertices()
                .iter()
                .zip(mesh.positions())
                .enumerate()
                .find(|(_, (a, b))| (**a - **b).abs().max_element() > tolerance)
            {
                return Err(refused(format!("collider vertex {k} is at {a}, the mesh's at {b}")));
            }
        }
        ShapeKind::Convex => {
            let aabb = collider.shape().compute_local_aabb();
            let off = (aabb.mins - lo).abs().max((aabb.maxs - hi).abs()).max_element();
            if off > tolerance.max(1e-5 * extent) {
                return Err(refused(format!(
                    "the collider's hull spans {:?}..{:?}, the mesh {lo}..{hi}",
                    aabb.mins, aabb.maxs
                )));
            }
        }
    }
    Ok(())
}

fn not_dentable(handle: ColliderHandle) -> AdapterError {
    AdapterError::Refit { collider: handle, reason: "not a dentable collider (Dentables::insert it first)".into() }
}

/// The hit of `side`, the projectile's surface from `targets` or `surfaces`; `None` when its
/// impact separates by more than rounding.
fn hit<'a>(
    targets: &'a TargetSet<ColliderHandle>,
    surfaces: &'a HashMap<ColliderHandle, TriMesh>,
    side: &Side,
) -> Option<Hit<'a, ColliderHandle>> {
    let mesh = targets.mesh(side.projectile).or_else(|| surfaces.get(&side.projectile))?;
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

/// Puts back the tri-mesh colliders `in_place` refitted, to their meshes in `targets` (those
/// from before the dents).
fn undo_in_place(
    colliders: &mut ColliderSet,
    targets: &TargetSet<ColliderHandle>,
    in_place: &[(&DentedTarget<ColliderHandle>, Refit)],
) {
    for (t, _) in in_place {
        let Some(before) = targets.mesh(t.key) else { continue };
        let positions: Vec<Vec3> = t.moved.iter().map(|&v| before.positions()[v as usize]).collect();
        commit(colliders, t.key, Refit::Vertices(t.moved.clone(), positions));
    }
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

#[cfg(test)]
mod tests {
    use dentbend::mesh;
    use rapier3d::prelude::ColliderBuilder;

    use super::*;
    use crate::trimesh_collider;

    /// A refit applied in place and undone leaves the tri-mesh collider as it was: its vertices
    /// bit for bit, and its bounding box (the tree refits from them).
    #[test]
    fn a_refit_applied_in_place_is_undone_exactly() {
        let block = mesh::subdivided_box(Vec3::new(1.0, 0.5, 0.4), [8, 4, 4]).unwrap();
        let mut colliders = ColliderSet::new();
        let key = colliders.insert(trimesh_collider(&block).unwrap());
        colliders.insert(ColliderBuilder::ball(0.1));
        let shape_of = |c: &ColliderSet| {
            let t = c[key].shape().as_trimesh().unwrap();
            (t.vertices().to_vec(), t.local_aabb())
        };
        let before = shape_of(&colliders);
        let mut targets = TargetSet::new();
        targets.insert(key, block.clone(), Affine3A::IDENTITY, DentSettings::new(1.0, 0.01, 0.05)).unwrap();
        // Every vertex with y > 0.2 pushed 5 cm down: the box's top caves in.
        let moved: Vec<u32> =
            (0..block.vertex_count() as u32).filter(|&v| block.positions()[v as usize].y > 0.2).collect();
        let mut dented = block.positions().to_vec();
        moved.iter().for_each(|&v| dented[v as usize].y -= 0.05);
        let mut dented_mesh = block.clone();
        dented_mesh.set_positions(dented).unwrap();
        let target =
            DentedTarget { key, mesh: dented_mesh, moved, refinement: Default::default(), topology_changed: false };
        let refit = prepare_refit(key, &colliders[key], ShapeKind::TriMesh, &target.mesh, &target.moved).unwrap();
        commit(&mut colliders, key, refit.clone());
        assert_ne!(shape_of(&colliders), before, "the refit moved the collider");
        undo_in_place(&mut colliders, &targets, &[(&target, refit)]);
        assert_eq!(shape_of(&colliders), before);
    }
}
