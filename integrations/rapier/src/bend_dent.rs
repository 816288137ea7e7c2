//! Denting a bendable body's parent mesh (paper §4, last paragraph): skin the rest mesh to the
//! pieces' poses at the start of the step, dent the skinned mesh like a plain body's (any
//! [`DentBackend`]), map each moved vertex's displacement back to the rest frame through the
//! inverse of its blended linear part, and give every piece owning a moved vertex the convex
//! hull of its new sub-mesh. The weights and the level set are kept (a dent of millimetres
//! moves the surface by less than a cell); Rapier recomputes each refitted piece's mass from its
//! new hull.

use dentbend::damage::{Damage, DentBackend, Hit, TargetSet};
use dentbend::dent::{BodyState, DentSettings, Impact, Refine, Surface};
use dentbend::mesh::TriMesh;
use glam::{Affine3A, Vec3};
use rapier3d::prelude::{ColliderHandle, SharedShape};

use crate::{AdapterError, Bendable, BodyStates, Contact, PhysicsWorld};

/// The key of the parent mesh in the dent planning (projectiles are keyed by their colliders).
fn parent_key() -> ColliderHandle {
    ColliderHandle::invalid()
}

/// A contact on a piece: (piece body, piece collider, projectile collider, projectile surface,
/// point, normal into the piece, impulse N·s).
type Side<'s> = (rapier3d::prelude::RigidBodyHandle, ColliderHandle, ColliderHandle, &'s TriMesh, Vec3, Vec3, f32);

/// A bendable body's denting: its settings and progressive state.
#[derive(Debug, Clone)]
pub(crate) struct BendDent {
    settings: DentSettings,
    damage: Damage<ColliderHandle>,
    step: u64,
}

/// What denting a bendable body did.
#[derive(Debug, Clone, Default)]
pub struct BendDentReport {
    /// Dents made (target: the hit piece's collider).
    pub dents: Vec<dentbend::damage::AppliedDent<ColliderHandle>>,
    /// Rest vertices that moved, ascending.
    pub moved: Vec<u32>,
    /// Pieces whose colliders were refitted.
    pub refitted: Vec<ColliderHandle>,
    /// Seconds spent on the pieces' new hulls (wall clock).
    pub collider_seconds: f64,
}

impl Bendable {
    /// Makes the parent mesh dentable with `settings` (never refined, whatever
    /// `settings.params.refine` says: skin weights and pieces belong to its vertices).
    ///
    /// # Errors
    /// Invalid settings.
    pub fn set_dentable(&mut self, mut settings: DentSettings) -> Result<(), AdapterError> {
        settings.validate()?;
        // Never refined: skin weights and pieces belong to the rest mesh's vertices.
        settings.params.refine = Refine::Off;
        self.dent = Some(BendDent { settings, damage: Damage::new(), step: 0 });
        Ok(())
    }

    /// Dents the parent mesh by the `contacts` on its pieces whose other collider has a
    /// surface (`surface` gives it, collider frame), on `backend`. No-op unless
    /// [`set_dentable`](Self::set_dentable) was called.
    ///
    /// # Errors
    /// A removed body or collider, a failed dent or hull; nothing changed then.
    pub fn dent_parent<'s>(
        &mut self,
        world: &mut PhysicsWorld,
        states: &BodyStates,
        contacts: &[Contact],
        surface: impl Fn(ColliderHandle) -> Option<&'s TriMesh>,
        backend: &mut dyn DentBackend<ColliderHandle>,
    ) -> Result<BendDentReport, AdapterError> {
        let Some(dent) = &self.dent else { return Ok(BendDentReport::default()) };
        let mut sides: Vec<Side<'s>> = Vec::new();
        let progressive = dent.settings.progressive;
        for c in contacts.iter().filter(|c| c.started || progressive) {
            for (mine, other, normal) in [(c.collider1, c.collider2, -c.normal), (c.collider2, c.collider1, c.normal)] {
                if let Some(piece) = self.pieces.iter().find(|p| p.collider == mine)
                    && let Some(mesh) = surface(other)
                {
                    // One impact of a projectile on the parent mesh, even when it touches
                    // several pieces (near a joint): the contact that pushed most.
                    match sides.iter().position(|s: &Side<'_>| s.2 == other) {
                        Some(i) if sides[i].6 >= c.impulse => {}
                        Some(i) => sides[i] = (piece.body, mine, other, mesh, c.point, normal, c.impulse),
                        None => sides.push((piece.body, mine, other, mesh, c.point, normal, c.impulse)),
                    }
                }
            }
        }
        if sides.is_empty() {
            return Ok(BendDentReport::default());
        }
        let transforms = self.pre_step_transforms(states)?;
        let skinned = self.skin_with(&transforms)?;
        let mut targets = TargetSet::new();
        targets.insert(parent_key(), skinned.clone(), Affine3A::IDENTITY, dent.settings.clone())?;
        let mut hits = Vec::with_capacity(sides.len());
        for &(body, _, other, mesh, point, normal, _) in &sides {
            let target_state = states.body(body, &world.bodies)?;
            let collider = states.collider(other, &world.bodies, &world.colliders)?;
            let projectile_state = match collider.parent() {
                Some(b) => states.body(b, &world.bodies)?,
                None => BodyState::FIXED,
            };
            let pose = states.collider_pose(other).unwrap_or_else(|| crate::to_affine(collider.position()));
            targets.insert_rigid(other);
            let Ok(impact) = Impact::from_contact(point, normal, &target_state, &projectile_state) else { continue };
            hits.push(Hit {
                target: parent_key(),
                projectile: other,
                impact,
                target_state,
                projectile_state,
                projectile_surface: Surface { mesh, to_world: pose },
            });
        }
        let mut damage = dent.damage.clone();
        let step = dent.step + 1;
        let plan = damage.plan(&targets, &hits, step, backend)?;
        let Some(dented) = plan.targets.into_iter().find(|t| t.key == parent_key()) else {
            if let Some(d) = &mut self.dent {
                (d.damage, d.step) = (damage, step);
            }
            return Ok(BendDentReport::default());
        };
        let rig = |e: dentbend::bend::BendError| AdapterError::Rig(e.to_string());
        let rest = self
            .rig
            .rest_after_pose_dent(self.rig.rest(), &skinned, &dented.mesh, &dented.moved, &transforms)
            .map_err(rig)?;
        let refit_start = std::time::Instant::now();
        let refits = self.refits(&rest, &dented.moved)?;
        let mut collider_seconds = refit_start.elapsed().as_secs_f64();

        // Checked: commit.
        let commit_start = std::time::Instant::now();
        let mut report = BendDentReport { moved: dented.moved.clone(), ..BendDentReport::default() };
        for (collider, shape) in refits {
            if let Some(c) = world.colliders.get_mut(collider) {
                c.set_shape(shape);
                report.refitted.push(collider);
            }
        }
        collider_seconds += commit_start.elapsed().as_secs_f64();
        report.collider_seconds = collider_seconds;
        self.rig.set_rest(rest).map_err(rig)?;
        if let Some(d) = &mut self.dent {
            (d.damage, d.step) = (damage, step);
        }
        let piece_of = |point: Vec3| sides.iter().find(|s| s.4 == point).map(|s| s.1).unwrap_or_else(parent_key);
        report.dents = plan
            .dents
            .into_iter()
            .map(|d| dentbend::damage::AppliedDent { target: piece_of(d.impact.point), ..d })
            .collect();
        Ok(report)
    }

    /// Each bone's transform at the start of the step (its piece's recorded pose).
    fn pre_step_transforms(&self, states: &BodyStates) -> Result<Vec<Affine3A>, AdapterError> {
        let mut out = vec![Affine3A::IDENTITY; self.pieces.len()];
        for p in &self.pieces {
            let pose = states.body_pose(p.body).ok_or(AdapterError::NotRecorded(p.body))?;
            out[p.bone] = crate::to_affine(&pose);
        }
        Ok(out)
    }

    /// New hulls for the pieces owning a vertex of `moved`, from `rest`.
    fn refits(&self, rest: &TriMesh, moved: &[u32]) -> Result<Vec<(ColliderHandle, SharedShape)>, AdapterError> {
        let rig = |e: dentbend::bend::BendError| AdapterError::Rig(e.to_string());
        let bones = self.rig.bones_owning(moved);
        let mut out = Vec::new();
        for p in self.pieces.iter().filter(|p| bones.contains(&p.bone)) {
            let (sub, _) = self.rig.sub_bodies().sub_mesh(rest, p.bone).map_err(rig)?;
            let hull = crate::convex_shape(&sub).ok_or_else(|| AdapterError::Refit {
                collider: p.collider,
                reason: "no convex hull of the dented sub-body".into(),
            })?;
            out.push((p.collider, hull));
        }
        Ok(out)
    }
}
