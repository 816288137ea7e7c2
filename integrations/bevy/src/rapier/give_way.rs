//! What breaking a body leaves to bevy_rapier3d: the projectile that broke it carries on.

use bevy::prelude::*;
use bevy_rapier3d::prelude::{RigidBody, Velocity};

use crate::BodyBroken;

/// The projectile that broke a body carries on with what the break left of its velocity
/// ([`BodyBroken::projectile_velocity`]): Rapier's step stopped it against the unbroken body.
pub(crate) fn give_way(mut broken: MessageReader<BodyBroken>, mut bodies: Query<(&RigidBody, &mut Velocity)>) {
    for b in broken.read() {
        if let Some((linear, angular)) = b.projectile_velocity
            && let Ok((body, mut velocity)) = bodies.get_mut(b.projectile)
            && *body == RigidBody::Dynamic
        {
            *velocity = Velocity { linear, angular };
        }
    }
}
