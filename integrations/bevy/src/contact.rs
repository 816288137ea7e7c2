//! The contact hook: any contact source (bevy_rapier3d through this crate, another physics
//! engine, a game's own collision code) writes [`DentContact`] messages; the plug-in decides
//! and makes the dents.

use bevy::prelude::*;
use dentbend::dent::BodyState;
use dentbend::glam::Affine3A;

/// One side of a contact: the entity (with [`Dentable`](crate::Dentable) or
/// [`DentProjectile`](crate::DentProjectile) to take part), where its mesh was and how it moved.
#[derive(Debug, Clone, Copy)]
pub struct DentBody {
    /// The entity carrying the mesh.
    pub entity: Entity,
    /// Mesh coordinates → world at the start of the step (rigid).
    pub pose: Affine3A,
    /// Its body's state at the start of the step ([`BodyState::FIXED`] for static geometry).
    pub state: BodyState,
}

/// An impact between two bodies, world coordinates at the start of the step.
#[derive(Message, Debug, Clone, Copy)]
pub struct DentContact {
    /// The first body.
    pub a: DentBody,
    /// The second body.
    pub b: DentBody,
    /// Contact point, world, m.
    pub point: Vec3,
    /// Contact normal, world, from `a` towards `b` (need not be unit, must be non-zero).
    pub normal: Vec3,
    /// Whether this is the impact's first step; later steps of a push only dent progressive
    /// targets.
    pub started: bool,
}
