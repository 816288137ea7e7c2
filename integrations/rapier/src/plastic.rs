//! Plastic joints in Rapier (paper §4.1): two bodies joined by a spherical impulse joint (Rapier
//! holds the anchors together) whose angular part the adapter applies after each step:
//!
//! 1. The angular impulse that would bring the relative angular velocity to the target (zero,
//!    or the damped post-bend rate, plus a correction of the drift from the rest orientation)
//!    is clamped at the joint's strength ([`clamp_to_strength`]).
//! 2. When it clamps the joint yields: the rest orientation becomes the current one, and the
//!    bend goes on at a damped rate ([`damped_bend_rate`], constant + proportional damping)
//!    while the rest orientation keeps following, so the bend does not spring back.

use dentbend::bend::{clamp_to_strength, damped_bend_rate};
use glam::{Mat3, Quat, Vec3};
use rapier3d::prelude::RigidBody;

use crate::AdapterError;

/// Share of the orientation drift corrected per step (Baumgarte), in (0, 1].
pub const DRIFT_CORRECTION: f32 = 0.2;

/// A plastic joint's rule and state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlasticJoint {
    /// Largest angular impulse the joint transmits per step, N·m·s.
    pub strength: f32,
    /// Constant damping of the post-bend rate, rad/s².
    pub damping_constant: f32,
    /// Proportional damping of the post-bend rate, 1/s.
    pub damping_proportional: f32,
    /// Rest orientation of body 2 relative to body 1 (R₁⁻¹R₂ at rest).
    pub rest: Quat,
    /// The rest orientation the joint was made with.
    pub initial_rest: Quat,
    /// Post-bend relative angular velocity still to come, world, rad/s.
    pub bend_rate: Vec3,
    /// Steps on which the impulse clamped (the joint yielded).
    pub yields: u32,
}

/// What one application of a joint rule did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointStep {
    /// Angular impulse applied to body 2 (body 1 took the opposite), world, N·m·s.
    pub impulse: Vec3,
    /// Whether the impulse clamped at the strength (the joint yielded).
    pub yielded: bool,
}

impl PlasticJoint {
    /// A joint of `strength` N·m·s, post-bend damping `damping_constant` rad/s² and
    /// `damping_proportional` 1/s, at rest in the bodies' current relative orientation `rest`.
    ///
    /// # Errors
    /// [`AdapterError::InvalidParameter`] for a non-finite or non-positive strength, negative or
    /// non-finite damping, or a non-finite rest orientation.
    pub fn new(
        strength: f32,
        damping_constant: f32,
        damping_proportional: f32,
        rest: Quat,
    ) -> Result<Self, AdapterError> {
        check("strength", strength, strength > 0.0, "must be finite and > 0")?;
        check("damping_constant", damping_constant, damping_constant >= 0.0, "must be finite and ≥ 0")?;
        let p = damping_proportional;
        check("damping_proportional", p, p >= 0.0, "must be finite and ≥ 0")?;
        if !rest.is_finite() {
            let value = format!("{rest:?}");
            return Err(AdapterError::InvalidParameter { name: "rest", value, reason: "must be finite" });
        }
        let rest = rest.normalize();
        Ok(Self {
            strength,
            damping_constant,
            damping_proportional,
            rest,
            initial_rest: rest,
            bend_rate: Vec3::ZERO,
            yields: 0,
        })
    }

    /// How far the joint has bent from the orientation it was made with, rad.
    pub fn bend_angle(&self) -> f32 {
        (self.initial_rest.inverse() * self.rest).normalize().angle_between(Quat::IDENTITY)
    }

    /// Applies the rule to `b1` and `b2` after a step of `dt` s.
    pub fn apply(&mut self, b1: &mut RigidBody, b2: &mut RigidBody, dt: f32) -> JointStep {
        let k = inverse_inertia(b1) + inverse_inertia(b2);
        let Some(k_inv) = invert(k) else { return JointStep::default() };
        let drift = rotation_vector(*b2.rotation() * (*b1.rotation() * self.rest).inverse());
        let relative = b2.angvel() - b1.angvel();
        let target = self.bend_rate - DRIFT_CORRECTION * drift / dt;
        let (impulse, yielded) = clamp_to_strength(k_inv * (target - relative), self.strength);
        b2.apply_torque_impulse(impulse, true);
        b1.apply_torque_impulse(-impulse, true);
        let after = relative + k * impulse;
        if yielded {
            self.yields += 1;
            self.rest = (b1.rotation().inverse() * *b2.rotation()).normalize();
            self.bend_rate = damped_bend_rate(after, self.damping_constant, self.damping_proportional, dt);
        } else if self.bend_rate != Vec3::ZERO {
            self.rest = (b1.rotation().inverse() * *b2.rotation()).normalize();
            self.bend_rate = damped_bend_rate(self.bend_rate, self.damping_constant, self.damping_proportional, dt);
        }
        JointStep { impulse, yielded }
    }
}

/// A body's world inverse inertia, 1/(kg·m²) (zero for fixed and kinematic bodies).
pub(crate) fn inverse_inertia(rb: &RigidBody) -> Mat3 {
    if rb.is_dynamic() { rb.mass_properties().effective_world_inv_inertia.mul_mat(Mat3::IDENTITY) } else { Mat3::ZERO }
}

/// `m⁻¹`, or `None` when `m` is singular or not finite.
pub(crate) fn invert(m: Mat3) -> Option<Mat3> {
    let det = m.determinant();
    (det.is_finite() && det.abs() > 1e-12 * m.to_cols_array().iter().fold(0.0f32, |a, x| a.max(x.abs())).powi(3))
        .then(|| m.inverse())
        .filter(|inv| inv.is_finite())
}

/// The rotation vector (axis × angle, angle in [0, π]) of unit quaternion `q`, rad.
pub(crate) fn rotation_vector(q: Quat) -> Vec3 {
    let q = if q.w < 0.0 { -q } else { q };
    q.normalize().to_scaled_axis()
}

fn check(name: &'static str, value: f32, ok: bool, reason: &'static str) -> Result<(), AdapterError> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(AdapterError::InvalidParameter { name, value: value.to_string(), reason })
    }
}

#[cfg(test)]
mod tests {
    use glam::{Quat, Vec3};
    use rapier3d::prelude::{ColliderBuilder, ColliderSet, RigidBodyBuilder, RigidBodyHandle, RigidBodySet};

    use super::PlasticJoint;

    const DT: f32 = 1.0 / 60.0;

    /// Two unit cubes of 1 kg (inertia 1/6 kg·m² about every axis), body 2 spinning about z at
    /// `spin` rad/s relative to body 1.
    fn pair(spin: f32) -> (RigidBodySet, RigidBodyHandle, RigidBodyHandle) {
        let mut bodies = RigidBodySet::new();
        let mut colliders = ColliderSet::new();
        let b1 = bodies.insert(RigidBodyBuilder::dynamic());
        let b2 = bodies.insert(RigidBodyBuilder::dynamic().angvel(Vec3::new(0.0, 0.0, spin)));
        for b in [b1, b2] {
            colliders.insert_with_parent(ColliderBuilder::cuboid(0.5, 0.5, 0.5).density(1.0), b, &mut bodies);
        }
        (bodies, b1, b2)
    }

    #[test]
    fn a_strong_joint_stops_the_relative_spin_and_does_not_bend() {
        // Stopping 2 rad/s takes I·ω = (1/12 kg·m², the pair's reduced inertia) · 2 = 1/6 N·m·s.
        let (mut bodies, b1, b2) = pair(2.0);
        let mut joint = PlasticJoint::new(1.0, 0.5, 10.0, Quat::IDENTITY).unwrap();
        let (Some(r1), Some(r2)) = bodies.get_pair_mut(b1, b2) else { panic!() };
        let step = joint.apply(r1, r2, DT);
        assert!(!step.yielded);
        assert!((step.impulse.z + 1.0 / 6.0).abs() < 1e-5, "{}", step.impulse);
        assert!((r2.angvel() - r1.angvel()).length() < 1e-5);
        // Equal and opposite: the total angular velocity (equal inertias) is kept.
        assert!(((r1.angvel() + r2.angvel()).z - 2.0).abs() < 1e-5);
        assert_eq!(joint.rest, Quat::IDENTITY);
    }

    #[test]
    fn a_weak_joint_yields_takes_the_current_orientation_and_keeps_bending_at_a_damped_rate() {
        let (mut bodies, b1, b2) = pair(2.0);
        // The current orientation, 0.3 rad apart: a weak joint yields and rests there.
        let bent = Quat::from_rotation_z(0.3);
        bodies.get_mut(b2).unwrap().set_rotation(bent, true);
        let mut joint = PlasticJoint::new(0.05, 0.5, 10.0, Quat::IDENTITY).unwrap();
        let (Some(r1), Some(r2)) = bodies.get_pair_mut(b1, b2) else { panic!() };
        let step = joint.apply(r1, r2, DT);
        assert!(step.yielded && joint.yields == 1);
        assert!((step.impulse.length() - 0.05).abs() < 1e-6, "clamped at the strength: {}", step.impulse);
        assert!(joint.rest.angle_between(bent) < 1e-5, "rest {:?}", joint.rest);
        assert!((joint.bend_angle() - 0.3).abs() < 1e-4);
        // The relative spin left after the clamped impulse, 2 − 0.05·12 = 1.4 rad/s, goes on
        // damped: 1.4 − (0.5 + 10·1.4)/60.
        let expected = 1.4 - (0.5 + 10.0 * 1.4) * DT;
        assert!((joint.bend_rate.z - expected).abs() < 1e-4, "{} vs {expected}", joint.bend_rate);
        // While the post-bend rate lasts, the rest orientation follows the bodies.
        r2.set_rotation(Quat::from_rotation_z(0.32), true);
        joint.apply(r1, r2, DT);
        assert!((joint.bend_angle() - 0.32).abs() < 1e-4);
        assert!(joint.bend_rate.z < expected);
    }

    #[test]
    fn bad_parameters_are_named() {
        assert!(PlasticJoint::new(0.0, 0.5, 10.0, Quat::IDENTITY).is_err());
        assert!(PlasticJoint::new(f32::NAN, 0.5, 10.0, Quat::IDENTITY).is_err());
        assert!(PlasticJoint::new(1.0, -1.0, 10.0, Quat::IDENTITY).is_err());
        assert!(PlasticJoint::new(1.0, 0.5, f32::INFINITY, Quat::IDENTITY).is_err());
        assert!(PlasticJoint::new(1.0, 0.5, 10.0, Quat::from_xyzw(f32::NAN, 0.0, 0.0, 1.0)).is_err());
    }
}
