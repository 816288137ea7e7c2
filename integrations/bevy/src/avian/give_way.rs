//! What breaking a body leaves to Avian: the projectile that broke it carries on.

use avian3d::prelude::{AngularVelocity, LinearVelocity, RigidBody};
use bevy::prelude::*;

use crate::BodyBroken;

/// The projectile that broke a body carries on with what the break left of its velocity
/// ([`BodyBroken::projectile_velocity`]): Avian's step stopped it against the unbroken body.
pub(crate) fn give_way(
    mut broken: MessageReader<BodyBroken>,
    mut bodies: Query<(&RigidBody, &mut LinearVelocity, &mut AngularVelocity)>,
) {
    for b in broken.read() {
        if let Some((linear, angular)) = b.projectile_velocity
            && let Ok((body, mut v, mut w)) = bodies.get_mut(b.projectile)
            && body.is_dynamic()
        {
            (v.0, w.0) = (linear, angular);
        }
    }
}
