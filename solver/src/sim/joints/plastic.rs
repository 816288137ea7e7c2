//! Plastic joints (paper §4.1): rigid until the angular impulse needed to keep them rigid within a
//! step exceeds their strength; then they bend.
//!
//! - Pre-stabilization: the joint is first solved as rigid (with its group); its angular impulse
//!   is added to the step's accumulated angular impulse, and if that passes the strength it is
//!   clamped onto the strength sphere (the angular impulse is decided first). The linear
//!   impulses are then solved anew given the clamped angular one, so the bones never detach.
//!   Over the Newton iterations of a step the accumulated impulse stays within the strength.
//! - After the position update, a joint that clamped (or is still bending) takes its current
//!   relative orientation as its new target — the plastic deformation — and reports a
//!   [`BendEvent`].
//! - Post-stabilization then holds a damped relative angular velocity instead of zero: the
//!   relative angular speed ω loses `(damping_constant + damping_proportional·ω)·dt` per step,
//!   never reversing, so a bend goes on briefly after the hit. While that lasts, pre-stabilization
//!   lets the joint keep turning at that rate (still within its strength).

use glam::Vec3;

use super::system::{self, Matrix};
use super::{BendEvent, Joint, JointKind, angle_between};
use crate::sim::{RigidBody, WorldSettings};
use dentbend::bend::JointRule;
use dentbend::bend::damped_bend_rate;

/// Solves a plastic joint's rows (`held`) for `rhs`, clamping the accumulated angular impulse
/// (`accumulated` plus this solution's, N·m·s) at `strength`. Returns the solution (linear
/// impulse along the basis, angular impulse) and whether it clamped; `None` when singular.
pub(crate) fn clamped_solve(
    m: &Matrix,
    rhs: &[f64; 6],
    held: [bool; 6],
    accumulated: Vec3,
    strength: f32,
) -> Option<([f64; 6], bool)> {
    let x = system::solve(m, rhs, held)?;
    let wanted = accumulated.as_dvec3() + glam::DVec3::new(x[3], x[4], x[5]);
    let strength = f64::from(strength);
    let length = wanted.length();
    if length <= strength {
        return Some((x, false));
    }
    let angular = wanted * (strength / length) - accumulated.as_dvec3();
    let angular = [angular.x, angular.y, angular.z];
    // The linear rows given the clamped angular impulse.
    let mut rest = *rhs;
    for (r, value) in rest.iter_mut().enumerate() {
        *value -= (0..3).map(|c| m[r][c + 3] * angular[c]).sum::<f64>();
    }
    let mut linear_rows = held;
    linear_rows[3..].fill(false);
    let mut x = system::solve(m, &rest, linear_rows)?;
    x[3..].copy_from_slice(&angular);
    Some((x, true))
}

/// After the position update: plastic joints that clamped this step or are still bending take
/// their current relative orientation as the new target (one [`BendEvent`] each when it moved),
/// and get the damped relative angular velocity post-stabilization will hold (at most the
/// world's `max_turn` per step: a bend never runs away).
pub(crate) fn after_step(joints: &mut [Joint], bodies: &[RigidBody], settings: &WorldSettings) -> Vec<BendEvent> {
    let dt = settings.dt;
    let mut bends = Vec::new();
    for (index, joint) in joints.iter_mut().enumerate() {
        let JointKind::Bend(JointRule::Plastic { damping_constant, damping_proportional, .. }) = joint.kind else {
            continue;
        };
        if !joint.clamped && !joint.is_bending() {
            continue;
        }
        let (Some(relative), Some(a), Some(b)) =
            (joint.relative_orientation(bodies), bodies.get(joint.a), bodies.get(joint.b))
        else {
            continue;
        };
        let angle = angle_between(joint.target, relative);
        joint.target = relative;
        if angle > 0.0 {
            bends.push(BendEvent { joint: index, angle, total_angle: joint.bend_angle() });
        }
        let turning = settings.limit_spin(b.angular_velocity - a.angular_velocity);
        let rate = damped_bend_rate(turning, damping_constant, damping_proportional, dt);
        joint.bend_rate = if rate == Vec3::ZERO { Vec3::ZERO } else { a.orientation.inverse() * rate };
    }
    bends
}
