//! The joints' plastic or elastic rule ([`JointState`], written once in dentbend) applied to
//! two Rapier bodies: their rotations, angular velocities and world inverse inertias go in, and
//! the rule's angular impulse goes to body 2 (the opposite to body 1). Rapier's spherical joint
//! holds the anchors together.

use dentbend::bend::{JointBodies, JointState, JointStep};
use glam::Mat3;
use rapier3d::prelude::RigidBody;

/// Applies `rule` to `b1` (parent) and `b2` (child) over a step of `dt` s: the rule's angular
/// impulse goes to `b2` and its opposite to `b1`, waking both when it is not zero.
pub fn apply_joint(rule: &mut JointState, b1: &mut RigidBody, b2: &mut RigidBody, dt: f32) -> JointStep {
    let bodies = JointBodies {
        rotations: [*b1.rotation(), *b2.rotation()],
        angular_velocities: [b1.angvel(), b2.angvel()],
        inverse_inertias: [inverse_inertia(b1), inverse_inertia(b2)],
    };
    let step = rule.step(&bodies, dt);
    if step.impulse != glam::Vec3::ZERO {
        b2.apply_torque_impulse(step.impulse, true);
        b1.apply_torque_impulse(-step.impulse, true);
    }
    step
}

/// A body's world inverse inertia, 1/(kg·m²) (zero for fixed and kinematic bodies).
fn inverse_inertia(rb: &RigidBody) -> Mat3 {
    if rb.is_dynamic() { rb.mass_properties().effective_world_inv_inertia.mul_mat(Mat3::IDENTITY) } else { Mat3::ZERO }
}

#[cfg(test)]
mod tests {
    use dentbend::bend::JointRule;
    use glam::{Quat, Vec3};
    use rapier3d::prelude::{ColliderBuilder, ColliderSet, RigidBodyBuilder, RigidBodySet};

    use super::*;

    #[test]
    fn a_strong_plastic_joint_stops_two_rapier_bodies_relative_spin() {
        // Two unit cubes of 1 kg, body 2 spinning at 2 rad/s about z: stopping it takes
        // I·ω = (1/12 kg·m², the pair's reduced inertia) · 2 = 1/6 N·m·s.
        let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
        let b1 = bodies.insert(RigidBodyBuilder::dynamic());
        let b2 = bodies.insert(RigidBodyBuilder::dynamic().angvel(Vec3::new(0.0, 0.0, 2.0)));
        for b in [b1, b2] {
            colliders.insert_with_parent(ColliderBuilder::cuboid(0.5, 0.5, 0.5).density(1.0), b, &mut bodies);
        }
        let mut rule = JointState::new(JointRule::plastic(1.0), Quat::IDENTITY).unwrap();
        let (Some(r1), Some(r2)) = bodies.get_pair_mut(b1, b2) else { panic!("two bodies") };
        let step = apply_joint(&mut rule, r1, r2, 1.0 / 60.0);
        assert!(!step.yielded && (step.impulse.z + 1.0 / 6.0).abs() < 1e-5, "{step:?}");
        assert!((r2.angvel() - r1.angvel()).length() < 1e-5);
        assert!(((r1.angvel() + r2.angvel()).z - 2.0).abs() < 1e-5, "equal and opposite");
    }
}
