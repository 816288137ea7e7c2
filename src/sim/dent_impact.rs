//! One collision's dent in world terms: whether a hit dents its target and how deep
//! ([`decide_dent`]), with world body indices as the ids; the contact then takes the exact form
//! every dent job is made from ([`LocalContact`](crate::dent::LocalContact): its crop of the
//! projectile and its job). A bending body's sub-body hit dents its skinned mesh with them.

use glam::Affine3A;

use super::{BodyKind, CollisionEvent, DentRecord, DentSettings, RigidBody, SimError, World};
use crate::dent::{BodyState, Impact, Surface, decide_dent_distance, projectile_offset};
use crate::mesh::TriMesh;

/// A surface as it dents others: a mesh and its mesh → world transform (rigid).
#[derive(Debug, Clone, Copy)]
pub struct DentSurface<'a> {
    /// The surface, in its own coordinates, m.
    pub mesh: &'a TriMesh,
    /// Mesh coordinates → world.
    pub to_world: Affine3A,
    /// Name of what dents with it (in [`DentRecord`]s).
    pub name: &'a str,
}

impl<'a> DentSurface<'a> {
    /// World body `index`'s own surface (its mesh at its body transform).
    pub fn of_body(world: &'a World, index: usize) -> Self {
        let body = &world.bodies()[index];
        Self { mesh: body.mesh(), to_world: body.transform(), name: &body.name }
    }

    /// `overrides`' surface for body `index` when it has one (a bending body's sub-body dents
    /// others with the whole skinned mesh), else the body's own.
    pub fn lookup(world: &'a World, index: usize, overrides: &[(usize, DentSurface<'a>)]) -> Self {
        overrides.iter().find(|(k, _)| *k == index).map_or_else(|| Self::of_body(world, index), |(_, s)| *s)
    }

    /// The surface in world coordinates.
    pub fn world_mesh(&self) -> TriMesh {
        self.surface().world_mesh()
    }

    /// The surface as the damage API takes it.
    pub fn surface(&self) -> Surface<'a> {
        Surface { mesh: self.mesh, to_world: self.to_world }
    }
}

/// What denting a step needs besides the world and the events.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepContext<'a> {
    /// Bodies that dent others with another surface than their own (a bending body's
    /// sub-bodies: the whole undented skinned mesh), by world index.
    pub surfaces: &'a [(usize, DentSurface<'a>)],
    /// Each body's rigid motion during the step (world at the contact → world now), by world
    /// index; bodies past the end did not move. See `DentTarget::motion`.
    pub motions: &'a [Affine3A],
}

impl<'a> StepContext<'a> {
    /// The surface body `index` dents others with.
    pub fn surface(&self, world: &'a World, index: usize) -> DentSurface<'a> {
        DentSurface::lookup(world, index, self.surfaces)
    }

    /// Body `index`'s motion during the step.
    pub fn motion(&self, index: usize) -> Affine3A {
        self.motions.get(index).copied().unwrap_or(Affine3A::IDENTITY)
    }
}

/// A dentable surface that a collision hit.
#[derive(Debug, Clone, Copy)]
pub struct DentTarget<'a> {
    /// World body hit (the event's body; for the energy model's effective mass).
    pub body: usize,
    /// Name of the dented thing (in errors and [`DentRecord`]s).
    pub name: &'a str,
    /// How it dents.
    pub settings: &'a DentSettings,
    /// Radius of a ball about the mesh's origin holding the mesh, m (bounds how far from the
    /// impact the projectile can matter).
    pub radius: f32,
    /// The target's rigid motion during the step that made the event (world at the contact →
    /// world now): the event's contact is carried along with it, so that a target that moved
    /// on after the contact (a plank pushed down by the ball) is dented where it was hit. The
    /// identity for a target that did not move.
    pub motion: Affine3A,
}

/// A dent decided from a collision, world coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DecidedDent {
    /// World body hit.
    pub target: usize,
    /// World body that hit it.
    pub projectile: usize,
    /// The contact, normal into the target, projectile's velocity relative to the target.
    pub impact: Impact,
    /// Dent distance earned, m.
    pub dent_distance: f32,
}

impl DecidedDent {
    /// The record of this dent of `target` by `projectile` (names) made with `dent_distance` (m)
    /// at `step`.
    pub fn record(&self, target: &str, projectile: &str, dent_distance: f32, step: u64) -> DentRecord {
        DentRecord {
            step,
            target: target.to_owned(),
            projectile: projectile.to_owned(),
            point: self.impact.point,
            normal: self.impact.normal,
            relative_velocity: self.impact.relative_velocity,
            dent_distance,
            volume_change: 0.0,
            cavity_volume: 0.0,
        }
    }

    /// Moves a dynamic projectile into the dent (by the dent distance along the normal) when
    /// `settings` ask for it.
    pub fn move_projectile(&self, world: &mut World, settings: &DentSettings) {
        let projectile = &mut world.bodies_mut()[self.projectile];
        if projectile.kind == BodyKind::Dynamic {
            projectile.position += projectile_offset(settings, &self.impact, self.dent_distance);
        }
    }
}

/// Body `index`'s state for the dent decision (fixed and kinematic bodies take no impulse).
pub fn body_state(body: &RigidBody) -> BodyState {
    let dynamic = body.kind == BodyKind::Dynamic;
    BodyState {
        center_of_mass: body.position,
        linear_velocity: body.linear_velocity,
        angular_velocity: body.angular_velocity,
        inverse_mass: if dynamic { body.inverse_mass } else { 0.0 },
        inverse_inertia: if dynamic { body.inverse_inertia_world() } else { glam::Mat3::ZERO },
        restitution: body.surface.restitution,
    }
}

/// Whether `target` (body a or b of `event`) dents from `event`, whose other body dents it with
/// `projectile`: its normal speed is above the threshold (or, with a hardness, the energy lost
/// makes a dent), and how deep ([`decide_dent_distance`]). The impact is the event's contact
/// carried by `target.motion`.
///
/// # Errors
/// [`SimError::Invalid`] when `target.body` is neither body of the event; [`SimError::Dent`]
/// (naming the target) for a bad impact or projectile.
pub fn decide_dent(
    world: &World,
    event: &CollisionEvent,
    target: &DentTarget<'_>,
    projectile: &DentSurface<'_>,
) -> Result<Option<DecidedDent>, SimError> {
    let other = if target.body == event.a { event.b } else { event.a };
    // Into the target, and the projectile's velocity relative to it, carried with the target.
    let Some(impact) = event.impact_on(target.body, target.motion) else {
        let body = target.body.to_string();
        return Err(SimError::Invalid { what: "dent target".into(), value: body, reason: "is not hit" });
    };
    let bodies = world.bodies();
    let (target_state, projectile_state) = (body_state(&bodies[target.body]), body_state(&bodies[other]));
    let distance =
        decide_dent_distance(target.settings, &impact, &target_state, &projectile_state, &projectile.surface())
            .map_err(|error| SimError::Dent { body: target.name.to_owned(), error })?;
    Ok(distance.map(|dent_distance| DecidedDent { target: target.body, projectile: other, impact, dent_distance }))
}
