//! A joint's plastic or elastic rule with its state (paper §4.1), for two bodies of any engine:
//! the engine holds the joint's anchors together (a spherical joint), and once per step the rule
//! reads the two bodies' rotations, angular velocities and world inverse inertias
//! ([`JointBodies`]) and gives the angular impulse for body 2 (body 1 takes the opposite).
//!
//! - **Plastic** ([`PlasticJoint`]): the impulse that would bring the relative angular velocity
//!   to the target (zero, or the damped post-bend rate, plus a correction of the drift from the
//!   rest orientation) is clamped at the joint's strength. When it clamps the joint yields: the
//!   rest orientation becomes the current one and the bend goes on at a damped rate
//!   (constant + proportional damping) while the rest keeps following, so the bend stays.
//! - **Elastic** ([`ElasticJoint`]): a torsional spring I·θ̈ + C·θ̇ + κθ = 0 on the deflection θ
//!   of body 2 from its rest orientation relative to body 1, integrated analytically over the
//!   step on three orthogonal axes, each with the pair's effective inertia about it.

use glam::{Mat3, Quat, Vec3};

use super::joint_rules::{clamp_to_strength, damped_bend_rate, effective_inertia, spring, spring_impulse};
use super::{BendError, JointRule};

/// Two jointed bodies as a joint rule reads them, world frame: index 0 is body 1 (the parent),
/// index 1 body 2 (the child).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointBodies {
    /// Each body's orientation.
    pub rotations: [Quat; 2],
    /// Each body's angular velocity, rad/s.
    pub angular_velocities: [Vec3; 2],
    /// Each body's world inverse inertia, 1/(kg·m²): zero for a fixed or kinematic body, and
    /// zero rows and columns about axes it cannot turn about.
    pub inverse_inertias: [Mat3; 2],
}

/// What one application of a joint rule gives.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointStep {
    /// Angular impulse for body 2 (body 1 takes the opposite), world, N·m·s.
    pub impulse: Vec3,
    /// Whether the impulse clamped at the strength (a plastic joint yielded).
    pub yielded: bool,
}

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

impl PlasticJoint {
    /// Share of the orientation drift corrected per step (Baumgarte), in (0, 1].
    pub const DRIFT_CORRECTION: f32 = 0.2;

    /// A joint of `strength` N·m·s, post-bend damping `damping_constant` rad/s² and
    /// `damping_proportional` 1/s, at rest in the bodies' relative orientation `rest`.
    ///
    /// # Errors
    /// [`BendError::InvalidParameter`] for a non-finite or non-positive strength, negative or
    /// non-finite damping, or a non-finite rest orientation.
    pub fn new(strength: f32, damping_constant: f32, damping_proportional: f32, rest: Quat) -> Result<Self, BendError> {
        JointRule::Plastic { strength, damping_constant, damping_proportional }.validate()?;
        let rest = checked_rest(rest)?;
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

    /// The rule over a step of `dt` s on `bodies` as they are now: the impulse to apply, and
    /// the state advanced (yields, rest orientation, post-bend rate).
    pub fn step(&mut self, bodies: &JointBodies, dt: f32) -> JointStep {
        let [r1, r2] = bodies.rotations;
        let k = bodies.inverse_inertias[0] + bodies.inverse_inertias[1];
        let Some(k_inv) = invert(k) else { return JointStep::default() };
        let drift = rotation_vector(r2 * (r1 * self.rest).inverse());
        let relative = bodies.angular_velocities[1] - bodies.angular_velocities[0];
        let target = self.bend_rate - Self::DRIFT_CORRECTION * drift / dt;
        let (impulse, yielded) = clamp_to_strength(k_inv * (target - relative), self.strength);
        let after = relative + k * impulse;
        if yielded {
            self.yields += 1;
            self.rest = (r1.inverse() * r2).normalize();
            self.bend_rate = damped_bend_rate(after, self.damping_constant, self.damping_proportional, dt);
        } else if self.bend_rate != Vec3::ZERO {
            self.rest = (r1.inverse() * r2).normalize();
            self.bend_rate = damped_bend_rate(self.bend_rate, self.damping_constant, self.damping_proportional, dt);
        }
        JointStep { impulse, yielded }
    }
}

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
    /// [`BendError::InvalidParameter`] for a non-finite or non-positive stiffness, a negative
    /// or non-finite damping, or a non-finite rest.
    pub fn new(stiffness: f32, damping: f32, rest: Quat) -> Result<Self, BendError> {
        JointRule::Elastic { stiffness, damping }.validate()?;
        Ok(Self { stiffness, damping, rest: checked_rest(rest)? })
    }

    /// The current deflection of body 2 from rest relative to body 1, world rotation vector,
    /// rad.
    pub fn deflection(&self, bodies: &JointBodies) -> Vec3 {
        let [r1, r2] = bodies.rotations;
        rotation_vector(r2 * (r1 * self.rest).inverse())
    }

    /// The spring over a step of `dt` s on `bodies` as they are now: the impulse to apply.
    pub fn step(&self, bodies: &JointBodies, dt: f32) -> JointStep {
        let [inv1, inv2] = bodies.inverse_inertias;
        let theta = self.deflection(bodies);
        let omega = bodies.angular_velocities[1] - bodies.angular_velocities[0];
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
        JointStep { impulse, yielded: false }
    }
}

/// A joint's angular rule with its state (rest orientation, accumulated bend).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointState {
    /// Plastic.
    Plastic(PlasticJoint),
    /// Elastic.
    Elastic(ElasticJoint),
}

impl JointState {
    /// `rule` at rest in the relative orientation `rest` (child in parent).
    ///
    /// # Errors
    /// [`BendError::InvalidParameter`] for a rule with bad values or a non-finite rest.
    pub fn new(rule: JointRule, rest: Quat) -> Result<Self, BendError> {
        Ok(match rule {
            JointRule::Plastic { strength, damping_constant, damping_proportional } => {
                Self::Plastic(PlasticJoint::new(strength, damping_constant, damping_proportional, rest)?)
            }
            JointRule::Elastic { stiffness, damping } => Self::Elastic(ElasticJoint::new(stiffness, damping, rest)?),
        })
    }

    /// Net plastic bend since the joint was made, rad (0 for elastic joints).
    pub fn bend_angle(&self) -> f32 {
        match self {
            Self::Plastic(p) => p.bend_angle(),
            Self::Elastic(_) => 0.0,
        }
    }

    /// The rule over a step of `dt` s on `bodies` as they are now: the angular impulse for
    /// body 2 (body 1 takes the opposite), the state advanced.
    pub fn step(&mut self, bodies: &JointBodies, dt: f32) -> JointStep {
        match self {
            Self::Plastic(p) => p.step(bodies, dt),
            Self::Elastic(e) => e.step(bodies, dt),
        }
    }
}

/// `rest` normalized, refused when not finite.
fn checked_rest(rest: Quat) -> Result<Quat, BendError> {
    if !rest.is_finite() {
        let value = format!("{rest:?}");
        return Err(BendError::InvalidParameter { name: "rest", value, reason: "must be finite" });
    }
    Ok(rest.normalize())
}

/// `m⁻¹`, or `None` when `m` is singular or not finite.
fn invert(m: Mat3) -> Option<Mat3> {
    let det = m.determinant();
    (det.is_finite() && det.abs() > 1e-12 * m.to_cols_array().iter().fold(0.0f32, |a, x| a.max(x.abs())).powi(3))
        .then(|| m.inverse())
        .filter(|inv| inv.is_finite())
}

/// The rotation vector (axis × angle, angle in [0, π]) of unit quaternion `q`, rad.
fn rotation_vector(q: Quat) -> Vec3 {
    let q = if q.w < 0.0 { -q } else { q };
    q.normalize().to_scaled_axis()
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f32 = 1.0 / 60.0;

    /// Two unit cubes of 1 kg (inertia 1/6 kg·m² about every axis), body 2 at `rotation`,
    /// spinning about z at `spin` rad/s relative to body 1.
    fn pair(rotation: Quat, spin: f32) -> JointBodies {
        JointBodies {
            rotations: [Quat::IDENTITY, rotation],
            angular_velocities: [Vec3::ZERO, Vec3::new(0.0, 0.0, spin)],
            inverse_inertias: [Mat3::from_diagonal(Vec3::splat(6.0)); 2],
        }
    }

    /// `bodies` after body 2 takes `impulse` and body 1 the opposite.
    fn after(mut bodies: JointBodies, impulse: Vec3) -> JointBodies {
        bodies.angular_velocities[1] += bodies.inverse_inertias[1] * impulse;
        bodies.angular_velocities[0] -= bodies.inverse_inertias[0] * impulse;
        bodies
    }

    #[test]
    fn a_strong_joint_stops_the_relative_spin_and_does_not_bend() {
        // Stopping 2 rad/s takes I·ω = (1/12 kg·m², the pair's reduced inertia) · 2 = 1/6 N·m·s.
        let bodies = pair(Quat::IDENTITY, 2.0);
        let mut joint = PlasticJoint::new(1.0, 0.5, 10.0, Quat::IDENTITY).unwrap();
        let step = joint.step(&bodies, DT);
        assert!(!step.yielded);
        assert!((step.impulse.z + 1.0 / 6.0).abs() < 1e-5, "{}", step.impulse);
        let moved = after(bodies, step.impulse);
        assert!((moved.angular_velocities[1] - moved.angular_velocities[0]).length() < 1e-5);
        // Equal and opposite: the total angular velocity (equal inertias) is kept.
        assert!(((moved.angular_velocities[0] + moved.angular_velocities[1]).z - 2.0).abs() < 1e-5);
        assert_eq!(joint.rest, Quat::IDENTITY);
    }

    #[test]
    fn a_weak_joint_yields_takes_the_current_orientation_and_keeps_bending_at_a_damped_rate() {
        // The current orientation, 0.3 rad apart: a weak joint yields and rests there.
        let bent = Quat::from_rotation_z(0.3);
        let mut joint = PlasticJoint::new(0.05, 0.5, 10.0, Quat::IDENTITY).unwrap();
        let step = joint.step(&pair(bent, 2.0), DT);
        assert!(step.yielded && joint.yields == 1);
        assert!((step.impulse.length() - 0.05).abs() < 1e-6, "clamped at the strength: {}", step.impulse);
        assert!(joint.rest.angle_between(bent) < 1e-5, "rest {:?}", joint.rest);
        assert!((joint.bend_angle() - 0.3).abs() < 1e-4);
        // The relative spin left after the clamped impulse, 2 − 0.05·12 = 1.4 rad/s, goes on
        // damped: 1.4 − (0.5 + 10·1.4)/60.
        let expected = 1.4 - (0.5 + 10.0 * 1.4) * DT;
        assert!((joint.bend_rate.z - expected).abs() < 1e-4, "{} vs {expected}", joint.bend_rate);
        // While the post-bend rate lasts, the rest orientation follows the bodies.
        let moved = after(pair(Quat::from_rotation_z(0.32), 2.0), step.impulse);
        joint.step(&moved, DT);
        assert!((joint.bend_angle() - 0.32).abs() < 1e-4);
        assert!(joint.bend_rate.z < expected);
    }

    #[test]
    fn a_spring_pulls_a_deflected_body_back_and_a_fixed_pair_takes_nothing() {
        let mut joint = JointState::new(JointRule::Elastic { stiffness: 50.0, damping: 1.0 }, Quat::IDENTITY).unwrap();
        let bodies = pair(Quat::from_rotation_z(0.2), 0.0);
        let step = joint.step(&bodies, DT);
        // Pulled back towards rest: an impulse about −z, never a yield.
        assert!(step.impulse.z < 0.0 && !step.yielded, "{}", step.impulse);
        assert_eq!(joint.bend_angle(), 0.0);
        let fixed = JointBodies { inverse_inertias: [Mat3::ZERO; 2], ..bodies };
        assert_eq!(joint.step(&fixed, DT).impulse, Vec3::ZERO);
    }

    #[test]
    fn bad_parameters_are_named() {
        assert!(PlasticJoint::new(0.0, 0.5, 10.0, Quat::IDENTITY).is_err());
        assert!(PlasticJoint::new(f32::NAN, 0.5, 10.0, Quat::IDENTITY).is_err());
        assert!(PlasticJoint::new(1.0, -0.5, 10.0, Quat::IDENTITY).is_err());
        assert!(ElasticJoint::new(-1.0, 0.5, Quat::IDENTITY).is_err());
        assert!(ElasticJoint::new(1.0, 0.5, Quat::from_xyzw(f32::NAN, 0.0, 0.0, 1.0)).is_err());
    }
}
