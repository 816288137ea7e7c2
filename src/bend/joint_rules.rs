//! The plastic and elastic joint rules of paper §4 as engine-neutral math: what any rigid-body
//! solver's joint needs to bend and stay bent, or to spring back, whatever its own joint
//! representation. [`JointState`](super::JointState) steps them on any engine's two bodies (the
//! Rapier adapter and the Bevy plug-in use it); dentbend-solver's `sim::joints` applies them
//! inside its own solver.
//!
//! - Plastic: the joint's angular impulse accumulated over a step is clamped onto the sphere of
//!   radius `strength` ([`clamp_to_strength`]); when it clamps the joint bends, and its rest
//!   relative orientation becomes the current one. After the hit the relative angular speed
//!   decays by `(constant + proportional·ω)·dt` a step ([`damped_bend_rate`]), never reversing.
//! - Elastic: `I·θ̈ + C·θ̇ + κ(θ − θ₀) = 0` integrated analytically over the step ([`spring`]),
//!   applied as equal and opposite angular impulses `I·((θⁿ⁺¹ − θⁿ)/Δt − ωⁿ)`
//!   ([`spring_impulse`]), with I the pair's effective inertia about the spring's axis
//!   ([`effective_inertia`]).

use glam::{Mat3, Vec3};

use super::BendError;

/// How a bendable body's joints turn: the one rule every engine's bendable joints apply.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointRule {
    /// Plastic (paper §4.1): rigid until the angular impulse that keeps it rigid for a step
    /// passes `strength`; then it bends and stays bent, the bend damped after the hit.
    Plastic {
        /// Largest angular impulse transmitted in one step before it bends, N·m·s (finite,
        /// > 0).
        strength: f32,
        /// Constant part of the post-bend damping, rad/s² (finite, ≥ 0).
        damping_constant: f32,
        /// Proportional part of the post-bend damping, 1/s (finite, ≥ 0).
        damping_proportional: f32,
    },
    /// Elastic (paper §4.3): a torsional spring and damper pull the joint back to its rest
    /// orientation.
    Elastic {
        /// Spring constant, N·m/rad (finite, > 0).
        stiffness: f32,
        /// Damping coefficient, N·m·s/rad (finite, ≥ 0).
        damping: f32,
    },
}

impl JointRule {
    /// Plastic joints of `strength` N·m·s with the paper's Figure 14 post-bend damping
    /// (0.5 rad/s² + 10/s).
    pub fn plastic(strength: f32) -> Self {
        Self::Plastic { strength, damping_constant: 0.5, damping_proportional: 10.0 }
    }

    /// Checks every value.
    ///
    /// # Errors
    /// [`BendError::InvalidParameter`] naming the value.
    pub fn validate(&self) -> Result<(), BendError> {
        let check = |name: &'static str, v: f32, strict: bool| {
            let ok = v.is_finite() && if strict { v > 0.0 } else { v >= 0.0 };
            let reason = if strict { "must be finite and > 0" } else { "must be finite and >= 0" };
            if ok { Ok(()) } else { Err(BendError::InvalidParameter { name, value: v.to_string(), reason }) }
        };
        match *self {
            Self::Plastic { strength, damping_constant, damping_proportional } => {
                check("strength", strength, true)?;
                check("damping_constant", damping_constant, false)?;
                check("damping_proportional", damping_proportional, false)
            }
            Self::Elastic { stiffness, damping } => {
                check("stiffness", stiffness, true)?;
                check("damping", damping, false)
            }
        }
    }
}

/// The accumulated angular impulse `wanted` (N·m·s) clamped onto the sphere of radius `strength`
/// (N·m·s): the impulse the joint may take, and whether it clamped (the joint bends).
pub(crate) fn clamp_to_strength(wanted: Vec3, strength: f32) -> (Vec3, bool) {
    let length = wanted.length();
    if length <= strength || length == 0.0 { (wanted, false) } else { (wanted * (strength / length), true) }
}

/// The relative angular velocity (rad/s) a plastic joint keeps one step of `dt` s after turning
/// at `turning` rad/s: its speed ω loses `(damping_constant + damping_proportional·ω)·dt`
/// (rad/s per s and 1/s), never reversing; same direction.
pub fn damped_bend_rate(turning: Vec3, damping_constant: f32, damping_proportional: f32, dt: f32) -> Vec3 {
    let speed = turning.length();
    let damped = (speed - (damping_constant + damping_proportional * speed) * dt).max(0.0);
    if damped > 0.0 && speed > 0.0 { turning * (damped / speed) } else { Vec3::ZERO }
}

/// The effective inertia (kg·m²) of two bodies' relative rotation about unit `axis`, given their
/// world inverse inertias (1/(kg·m²)): `1 / (u·(I₁⁻¹ + I₂⁻¹)·u)`, the paper's `(I₁ + I₂)⁻¹I₁I₂`
/// about that axis. `None` when neither body can turn about it.
pub(crate) fn effective_inertia(inverse_a: Mat3, inverse_b: Mat3, axis: Vec3) -> Option<f32> {
    let k = axis.dot((inverse_a + inverse_b) * axis);
    (k > 0.0 && k.is_finite()).then(|| 1.0 / k)
}

/// The angular impulse (N·m·s, about the spring's axis, applied +j to body b and −j to body a)
/// that makes a spring of effective `inertia` move from `theta` to `theta_next` (rad) in `dt` s
/// when it turns at `omega` rad/s now: `I·((θⁿ⁺¹ − θⁿ)/Δt − ωⁿ)`.
pub(crate) fn spring_impulse(inertia: f64, theta: f64, theta_next: f64, omega: f64, dt: f64) -> f64 {
    inertia * ((theta_next - theta) / dt - omega)
}

/// The free motion of `inertia·x″ + damping·x′ + stiffness·x = 0` from (x, x′) = (`x0`, `v0`)
/// after time `t` (s): the closed forms of the under-, critically and over-damped cases.
/// Returns (x, x′) at `t`.
pub fn spring(x0: f64, v0: f64, inertia: f64, stiffness: f64, damping: f64, t: f64) -> (f64, f64) {
    let gamma = damping / (2.0 * inertia);
    let natural2 = stiffness / inertia;
    let disc = gamma * gamma - natural2;
    // Relative width of the critical band, where the under/over-damped forms lose precision.
    let critical = disc.abs() <= 1e-9 * natural2.max(gamma * gamma);
    if critical {
        let decay = (-gamma * t).exp();
        let b = v0 + gamma * x0;
        (decay * (x0 + b * t), decay * (v0 - gamma * b * t))
    } else if disc < 0.0 {
        let wd = (-disc).sqrt();
        let (s, c) = (wd * t).sin_cos();
        let decay = (-gamma * t).exp();
        let x = decay * (x0 * c + (v0 + gamma * x0) / wd * s);
        let v = decay * (v0 * c - (natural2 * x0 + gamma * v0) / wd * s);
        (x, v)
    } else {
        let root = disc.sqrt();
        let (r1, r2) = (-gamma + root, -gamma - root);
        let c1 = (v0 - r2 * x0) / (r1 - r2);
        let c2 = x0 - c1;
        let (e1, e2) = ((r1 * t).exp(), (r2 * t).exp());
        (c1 * e1 + c2 * e2, c1 * r1 * e1 + c2 * r2 * e2)
    }
}

#[cfg(test)]
mod tests {
    use super::spring;

    /// Each closed form solves the equation: it starts at (x0, v0), its velocity is the
    /// derivative of its position, and x″ (central differences, h = 1e-4 s, error ~h²·ω⁴·x)
    /// equals −(C·x′ + κ·x)/I within 1e-3 of κ·|x0|/I; just under and just over critical
    /// damping agree with the critical form within 1e-6.
    #[test]
    fn closed_forms_solve_the_spring_equation() {
        let (inertia, stiffness, x0, v0) = (0.2, 30.0, 0.1, -0.7);
        let critical = 2.0 * f64::sqrt(stiffness * inertia);
        let scale = stiffness * x0 / inertia;
        for damping in [0.0, 0.3 * critical, critical, 3.0 * critical] {
            let at = |t: f64| spring(x0, v0, inertia, stiffness, damping, t);
            assert!((at(0.0).0 - x0).abs() < 1e-12 && (at(0.0).1 - v0).abs() < 1e-12, "C = {damping}");
            let h = 1e-4;
            for t in [0.01, 0.0167, 0.1, 0.5] {
                let ((xm, _), (x, v), (xp, _)) = (at(t - h), at(t), at(t + h));
                assert!(((xp - xm) / (2.0 * h) - v).abs() < 1e-4 * scale, "C = {damping}, t = {t}: velocity");
                let accel = (xp - 2.0 * x + xm) / (h * h);
                let wanted = -(damping * v + stiffness * x) / inertia;
                assert!((accel - wanted).abs() < 1e-3 * scale, "C = {damping}, t = {t}: {accel} vs {wanted}");
            }
        }
        for t in [0.0167, 0.2] {
            let exact = spring(x0, v0, inertia, stiffness, critical, t);
            for near in [critical * (1.0 - 1e-7), critical * (1.0 + 1e-7)] {
                let (x, v) = spring(x0, v0, inertia, stiffness, near, t);
                assert!((x - exact.0).abs() < 1e-6 && (v - exact.1).abs() < 1e-6, "near critical at t = {t}");
            }
        }
    }
}
