//! Elastic joints in Rapier (paper §4.1): a torsional spring I·θ̈ + C·θ̇ + κθ = 0 on the
//! deflection θ of body 2 from its rest orientation relative to body 1, integrated
//! analytically over the step ([`spring`]) on three orthogonal axes, each with the pair's
//! effective inertia I = (I₁⁻¹ + I₂⁻¹)⁻¹ about it; the impulse
//! j = I((θⁿ⁺¹ − θⁿ)/Δt − ωⁿ) ([`spring_impulse`]) goes to body 2 and −j to body 1. Rapier's
//! spherical joint holds the anchors together.

use dentbend::bend::{effective_inertia, spring, spring_impulse};
use glam::{Quat, Vec3};
use rapier3d::prelude::RigidBody;

use crate::AdapterError;
use crate::plastic::{JointStep, inverse_inertia, rotation_vector};

/// An elastic joint's spring and rest orientation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElasticJoint {
    /// Stiffness κ, N·m/rad.
    pub stiffness: f32,
    /// Damping C, N·m·s/rad.
    pub damping: f32,
    /// Rest orientation of body 2 relative to body 1 (R₁⁻¹R₂).
    pub rest: Quat,
}

impl ElasticJoint {
    /// A spring of `stiffness` N·m/rad and `damping` N·m·s/rad at rest in `rest`.
    ///
    /// # Errors
    /// [`AdapterError::InvalidParameter`] for a non-finite or non-positive stiffness, a negative
    /// or non-finite damping, or a non-finite rest.
    pub fn new(stiffness: f32, damping: f32, rest: Quat) -> Result<Self, AdapterError> {
        let bad = |name, value: f32, reason| AdapterError::InvalidParameter { name, value: value.to_string(), reason };
        if !(stiffness.is_finite() && stiffness > 0.0) {
            return Err(bad("stiffness", stiffness, "must be finite and > 0"));
        }
        if !(damping.is_finite() && damping >= 0.0) {
            return Err(bad("damping", damping, "must be finite and ≥ 0"));
        }
        if !rest.is_finite() {
            return Err(bad("rest", f32::NAN, "must be finite"));
        }
        Ok(Self { stiffness, damping, rest: rest.normalize() })
    }

    /// Current deflection of `b2` from rest relative to `b1`, world rotation vector, rad.
    pub fn deflection(&self, b1: &RigidBody, b2: &RigidBody) -> Vec3 {
        rotation_vector(*b2.rotation() * (*b1.rotation() * self.rest).inverse())
    }

    /// Applies the spring to `b1` and `b2` over a step of `dt` s.
    pub fn apply(&self, b1: &mut RigidBody, b2: &mut RigidBody, dt: f32) -> JointStep {
        let (inv1, inv2) = (inverse_inertia(b1), inverse_inertia(b2));
        let theta = self.deflection(b1, b2);
        let omega = b2.angvel() - b1.angvel();
        let first = theta.try_normalize().or_else(|| omega.try_normalize()).unwrap_or(Vec3::X);
        let (second, third) = first.any_orthonormal_pair();
        let mut impulse = Vec3::ZERO;
        for axis in [first, second, third] {
            let Some(inertia) = effective_inertia(inv1, inv2, axis) else { continue };
            let (x, v) = (f64::from(theta.dot(axis)), f64::from(omega.dot(axis)));
            let (k, c, i, h) = (f64::from(self.stiffness), f64::from(self.damping), f64::from(inertia), f64::from(dt));
            let (next, _) = spring(x, v, i, k, c, h);
            impulse += axis * spring_impulse(i, x, next, v, h) as f32;
        }
        b2.apply_torque_impulse(impulse, true);
        b1.apply_torque_impulse(-impulse, true);
        JointStep { impulse, yielded: false }
    }
}
