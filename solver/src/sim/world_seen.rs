//! What a body's contacts depend on, kept with a detection so that detecting again after a few
//! edits ([`World::redetect`](super::World::redetect)) can tell which bodies changed.

use glam::{Quat, Vec3};
use parry3d::shape::SharedShape;

use crate::sim::{BodyKind, RigidBody};

/// What a body's contacts depend on, as it was when they were found: its collider, pose,
/// velocities (its reach within the step), kind, sleep and whether it is simulated.
#[derive(Debug, Clone)]
pub(crate) struct Seen {
    /// Holding the collider keeps it alive, so an edit that replaces or changes it (a change
    /// copies a shared collider first) gives another one: the pointers differ.
    shape: SharedShape,
    /// Centre of mass, world, m.
    position: Vec3,
    orientation: Quat,
    /// m/s.
    linear_velocity: Vec3,
    /// rad/s.
    angular_velocity: Vec3,
    kind: BodyKind,
    asleep: bool,
    /// Not condensed into a cluster (or a cluster's proxy).
    simulated: bool,
}

impl Seen {
    pub(crate) fn of(body: &RigidBody) -> Self {
        Self {
            shape: body.shape.clone(),
            position: body.position,
            orientation: body.orientation,
            linear_velocity: body.linear_velocity,
            angular_velocity: body.angular_velocity,
            kind: body.kind,
            asleep: body.activity.asleep,
            simulated: body.is_simulated(),
        }
    }

    /// Whether `body` is still as seen (same collider object, bit for bit the same motion).
    pub(crate) fn matches(&self, body: &RigidBody) -> bool {
        std::sync::Arc::ptr_eq(&self.shape.0, &body.shape.0)
            && self.position == body.position
            && self.orientation == body.orientation
            && self.linear_velocity == body.linear_velocity
            && self.angular_velocity == body.angular_velocity
            && self.kind == body.kind
            && self.asleep == body.activity.asleep
            && self.simulated == body.is_simulated()
    }
}
