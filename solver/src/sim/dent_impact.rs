//! One collision's dent in world terms, with world body indices as the ids: the surfaces bodies
//! dent others with, their motions during the step, a decided dent and its record. The decision
//! itself is the damage API's ([`decide_dent_distance`](dentbend::dent::decide_dent_distance)).

use glam::Affine3A;

use super::{BodyKind, DentRecord, DentSettings, RigidBody, World};
use dentbend::dent::{BodyState, Impact, Surface, projectile_offset};

/// A body that dents others with another surface than its own: a bending body's sub-body
/// dents as the whole undented skinned mesh, named as the bending body in [`DentRecord`]s.
#[derive(Debug, Clone, Copy)]
pub struct SurfaceOverride<'a> {
    /// The world body, by index.
    pub body: usize,
    /// The surface it dents with.
    pub surface: Surface<'a>,
    /// What dents with it (in [`DentRecord`]s).
    pub name: &'a str,
}

/// What denting a step needs besides the world and the events.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepContext<'a> {
    /// Bodies that dent others with another surface than their own.
    pub surfaces: &'a [SurfaceOverride<'a>],
    /// Each body's rigid motion during the step (world at the contact → world now), by world
    /// index; bodies past the end did not move. The event's contact is carried along with it, so
    /// that a target that moved on after the contact (a plank pushed down by the ball) is dented
    /// where it was hit.
    pub motions: &'a [Affine3A],
}

impl<'a> StepContext<'a> {
    /// The surface body `index` dents others with.
    pub fn surface(&self, world: &'a World, index: usize) -> Surface<'a> {
        self.override_of(index).map_or_else(|| world.bodies()[index].surface(), |o| o.surface)
    }

    /// The name of what dents with body `index`'s surface.
    pub fn name(&self, world: &'a World, index: usize) -> &'a str {
        self.override_of(index).map_or_else(|| world.bodies()[index].name.as_str(), |o| o.name)
    }

    /// Body `index`'s override, if it has one.
    fn override_of(&self, index: usize) -> Option<&SurfaceOverride<'a>> {
        self.surfaces.iter().find(|o| o.body == index)
    }

    /// Body `index`'s motion during the step.
    pub fn motion(&self, index: usize) -> Affine3A {
        self.motions.get(index).copied().unwrap_or(Affine3A::IDENTITY)
    }
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
