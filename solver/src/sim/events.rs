//! What a step reports about each colliding pair: the input of denting (paper Algorithm 1,
//! lines 10–12) and of anything else a user hangs on collisions.

use glam::{Affine3A, Vec3};
use serde::Serialize;

use super::BendEvent;
use dentbend::dent::Impact;

/// A pair of bodies that collided during a step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CollisionEvent {
    /// Index of body a in the world (for a cluster, the member hit).
    pub a: usize,
    /// Index of body b (> a).
    pub b: usize,
    /// Contact point, world, m (the impulse-weighted centre of the pair's closing contact points).
    pub point: Vec3,
    /// Unit contact normal, from a towards b.
    pub normal: Vec3,
    /// Velocity of b's material point relative to a's at the contact before the step, including
    /// rotation (v + ω × r on both bodies), m/s.
    pub relative_velocity: Vec3,
    /// Closing speed along the normal before the step, m/s (≥ 0).
    pub normal_speed: f32,
    /// Total impulse the step applied to b (a received the opposite), N·s.
    pub impulse: Vec3,
}

impl CollisionEvent {
    /// The same collision seen from b: bodies swapped, normal, relative velocity and impulse
    /// reversed.
    pub fn swapped(&self) -> Self {
        Self {
            a: self.b,
            b: self.a,
            normal: -self.normal,
            relative_velocity: -self.relative_velocity,
            impulse: -self.impulse,
            ..*self
        }
    }

    /// The contact as body `target` (a or b) is dented by it, carried by `motion` (the target's
    /// rigid motion since the contact, world then → world now): normal into the target, the other
    /// body's velocity relative to it. `None` when `target` is neither body.
    pub fn impact_on(&self, target: usize, motion: Affine3A) -> Option<Impact> {
        let sign = match target {
            t if t == self.a => 1.0f32,
            t if t == self.b => -1.0,
            _ => return None,
        };
        let impact =
            Impact { point: self.point, normal: -sign * self.normal, relative_velocity: sign * self.relative_velocity };
        Some(impact.transformed(motion))
    }
}

/// What one [`World::step`](super::World::step) did.
#[derive(Debug, Clone, Default)]
pub struct StepReport {
    /// Colliding pairs (closing contacts), in pair order.
    pub events: Vec<CollisionEvent>,
    /// Plastic joints that bent, in joint order.
    pub bends: Vec<BendEvent>,
    /// Body pairs whose boxes overlapped.
    pub broad_pairs: usize,
    /// Contact points solved.
    pub contact_points: usize,
    /// Wall time of the step, s.
    pub seconds: f64,
}
