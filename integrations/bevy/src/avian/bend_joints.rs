//! The bendable bodies' joint rules applied to Avian's bodies just before each step: the rule
//! reads the two bones' rotations, angular velocities and world inverse inertias, and its
//! angular impulse changes their angular velocities (I⁻¹·j to the child, −I⁻¹·j to the parent).
//! Avian's spherical joint holds the anchors together.

use avian3d::math::SymmetricTensor;
use avian3d::prelude::{AngularVelocity, ComputedAngularInertia, Physics, PhysicsTime, RigidBody, Rotation};
use bevy::prelude::*;
use dentbend::bend::JointBodies;

use crate::bend::Bends;

/// What a bone's rule reads and writes.
type BoneData = (&'static RigidBody, &'static Rotation, &'static ComputedAngularInertia, &'static mut AngularVelocity);

/// Applies every bendable body's joint rules over the coming step: `time` is the schedule's
/// clock, scaled by Avian's relative speed; nothing while Avian's clock is paused (no step).
pub(crate) fn apply_joint_rules(
    mut bends: ResMut<Bends>,
    (time, physics): (Res<Time>, Res<Time<Physics>>),
    mut bones: Query<BoneData>,
) {
    let dt = time.delta_secs() * physics.relative_speed();
    if physics.is_paused() || dt <= 0.0 || !dt.is_finite() {
        return;
    }
    for rig in bends.rigs.values_mut() {
        for joint in &mut rig.joints {
            let pair = [rig.pieces[joint.parent], rig.pieces[joint.child]];
            let Ok([(kind1, r1, i1, mut w1), (kind2, r2, i2, mut w2)]) = bones.get_many_mut(pair) else { continue };
            let inverse_inertias = [world_inverse_inertia(kind1, r1, i1), world_inverse_inertia(kind2, r2, i2)];
            let bodies = JointBodies { rotations: [r1.0, r2.0], angular_velocities: [w1.0, w2.0], inverse_inertias };
            let step = joint.rule.step(&bodies, dt);
            w2.0 += inverse_inertias[1] * step.impulse;
            w1.0 -= inverse_inertias[0] * step.impulse;
        }
    }
}

/// A body's inverse inertia in world axes, 1/(kg·m²); zero for a body that takes no impulse.
fn world_inverse_inertia(kind: &RigidBody, rotation: &Rotation, inertia: &ComputedAngularInertia) -> Mat3 {
    if !kind.is_dynamic() {
        return Mat3::ZERO;
    }
    let axes = Mat3::from_quat(rotation.0);
    let local: SymmetricTensor = inertia.inverse();
    axes * local.to_mat3() * axes.transpose()
}
