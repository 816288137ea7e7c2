//! Elastic joints (paper §4.3): a spring and damper `I·θ̈ + C·θ̇ + κ(θ − θ₀) = 0` in each elastic
//! joint, integrated analytically over the step after gravity, and applied as equal and opposite
//! impulses `j = I·((θⁿ⁺¹ − θⁿ)/Δt − ωⁿ)` so the position update lands on θⁿ⁺¹.
//!
//! The bodies then move at the secant rate (θⁿ⁺¹ − θⁿ)/Δt, not at the analytic ωⁿ⁺¹; starting
//! the next step's solution from the secant would halve the spring's acceleration (a period
//! √2 too long). So each joint remembers ωⁿ⁺¹ minus the secant, and the next step starts from
//! the bodies' relative velocity (with whatever contacts and gravity did to it) plus that lag.
//!
//! Angular joints: θ is the rotation from the rest relative orientation, about the axis of its
//! rotation vector (or of the relative angular velocity when it is zero), so the spring opposes
//! the displacement. I is the effective inertia of the relative rotation about that axis with
//! the anchors held together: the inverse of `u·K·u`, K the Schur complement of the joint's
//! linear rows in its 6×6 response. For two bodies joined at their centres of mass (or free
//! bodies whose joint force vanishes by symmetry) K = I₁⁻¹ + I₂⁻¹, the paper's
//! `(I₁ + I₂)⁻¹·I₁·I₂`; otherwise the anchor reaction adds to it (a body hinged on a static base
//! turns with its inertia about the anchor). The angular impulse goes with the anchor reaction
//! it needs, so the point joint is not disturbed. Relative spin across the axis is damped by the
//! same C (exact exponential decay), so damping does not depend on the axis choice. The world's
//! `angular_damping` slows the spring a little more, as it does every spin.
//!
//! Prismatic joints: θ is the anchors' offset along the axis, I the reduced mass
//! `(m₁⁻¹ + m₂⁻¹)⁻¹`, and the impulse acts through both centres of mass (it turns neither body).

use glam::{DVec3, Vec3};

use super::system::{self, Frame, Matrix, Mobility, Motion};
use super::{Joint, JointKind, rotation_vector};
use crate::sim::solver::SolverBody;
use crate::sim::{RigidBody, WorldSettings};
use dentbend::bend::JointRule;
use dentbend::bend::spring;

/// Below this the spring's displacement (rad or m) or speed (rad/s or m/s) counts as none.
const TINY: f32 = 1e-9;

/// Applies every elastic joint's spring impulse to the step's velocities `solver`.
pub(crate) fn apply_springs(
    joints: &mut [Joint],
    bodies: &[RigidBody],
    solver: &mut [SolverBody],
    settings: &WorldSettings,
) {
    if !joints
        .iter()
        .any(|j| matches!(j.kind, JointKind::Bend(JointRule::Elastic { .. }) | JointKind::ElasticPrismatic { .. }))
    {
        return;
    }
    let mob = system::mobilities(bodies, settings);
    let mut v: Vec<Motion> = solver.iter().map(|b| Motion { linear: b.linear, angular: b.angular }).collect();
    for joint in joints.iter_mut() {
        if !system::joint_takes_impulses(joint, &mob) {
            continue;
        }
        let (ma, mb) = (&mob[joint.a], &mob[joint.b]);
        let f = system::frame(joint, bodies, &mob, &v, None, 0.0);
        match joint.kind {
            JointKind::Bend(JointRule::Elastic { stiffness, damping }) => {
                angular_spring(joint, &f, (ma, mb), &mob, &mut v, stiffness, damping, settings.dt);
            }
            JointKind::ElasticPrismatic { stiffness, damping, .. } => {
                prismatic_spring(joint, &f, (ma, mb), &mut v, stiffness, damping, settings.dt);
            }
            _ => {}
        }
    }
    for (b, m) in solver.iter_mut().zip(&v) {
        b.linear = m.linear;
        b.angular = m.angular;
    }
}

#[allow(clippy::too_many_arguments)] // one call site; a struct would only rename the arguments
fn angular_spring(
    joint: &mut Joint,
    f: &Frame,
    (ma, mb): (&Mobility, &Mobility),
    mob: &[Mobility],
    v: &mut [Motion],
    stiffness: f32,
    damping: f32,
    dt: f32,
) {
    let displacement = rotation_vector((f.qb * (f.qa * joint.target).inverse()).normalize());
    let turning = v[joint.b].angular - v[joint.a].angular;
    let (axis, theta) = if displacement.length() > TINY {
        (displacement.normalize(), displacement.length())
    } else if turning.length() > TINY {
        (turning.normalize(), 0.0)
    } else {
        return;
    };
    let axes = [Vec3::X, Vec3::Y, Vec3::Z];
    let m = system::response(ma, mb, f, &axes);
    let omega = turning.dot(axis);
    let Some((inertia, j, l)) = effective(&m, axis) else {
        return;
    };
    let start = f64::from(omega + (f.qa * joint.spring_lag).dot(axis));
    let (next, rate) =
        spring(f64::from(theta), start, inertia, f64::from(stiffness), f64::from(damping), f64::from(dt));
    let secant = (next - f64::from(theta)) / f64::from(dt);
    joint.spring_lag = f.qa.inverse() * (axis * (rate - secant) as f32);
    let change = secant - f64::from(omega);
    let (mut linear, mut angular) = (j * change as f32, l * change as f32);
    // Damping of the relative spin across the spring's axis.
    let across = turning - axis * omega;
    if damping > 0.0 && across.length() > TINY {
        let w = across.normalize();
        if let Some((inertia, j, l)) = effective(&m, w) {
            let speed = f64::from(across.length());
            let change = speed * ((-f64::from(damping) * f64::from(dt) / inertia).exp() - 1.0);
            linear += j * change as f32;
            angular += l * change as f32;
        }
    }
    system::apply(v, mob, joint, f, linear, angular);
}

/// The effective inertia about unit `axis` with the anchors held (kg·m²), and the impulses
/// (linear at the anchors, angular) that change the relative angular velocity by 1 rad/s along
/// `axis` without moving the anchors apart; `None` when the joint cannot turn.
fn effective(m: &Matrix, axis: Vec3) -> Option<(f64, Vec3, Vec3)> {
    let u = axis.as_dvec3();
    // Anchor reaction to an angular impulse u: M_ll·j = −M_la·u.
    let mut rhs = [0.0; 6];
    for (r, value) in rhs.iter_mut().enumerate().take(3) {
        *value = -(m[r][3] * u.x + m[r][4] * u.y + m[r][5] * u.z);
    }
    let x = system::solve(m, &rhs, [true, true, true, false, false, false])?;
    let turn = |r: usize| (0..3).map(|c| m[r][c] * x[c]).sum::<f64>() + m[r][3] * u.x + m[r][4] * u.y + m[r][5] * u.z;
    let along = DVec3::new(turn(3), turn(4), turn(5)).dot(u);
    if !(along.is_finite() && along > 0.0) {
        return None;
    }
    let inertia = 1.0 / along;
    let j = Vec3::new(x[0] as f32, x[1] as f32, x[2] as f32) * inertia as f32;
    Some((inertia, j, axis * inertia as f32))
}

fn prismatic_spring(
    joint: &mut Joint,
    f: &Frame,
    (ma, mb): (&Mobility, &Mobility),
    v: &mut [Motion],
    stiffness: f32,
    damping: f32,
    dt: f32,
) {
    let inverse_mass = ma.inverse_mass + mb.inverse_mass;
    if inverse_mass <= 0.0 {
        return;
    }
    let axis = (f.qa * joint.axis_local).normalize();
    let (va, vb) = (v[joint.a], v[joint.b]);
    let offset = (f.anchor_b - f.anchor_a).dot(axis);
    let speed = (vb.linear + vb.angular.cross(f.rb) - va.linear - va.angular.cross(f.ra)).dot(axis);
    let mass = 1.0 / f64::from(inverse_mass);
    let start = f64::from(speed + joint.spring_lag.x);
    let (next, rate) = spring(f64::from(offset), start, mass, f64::from(stiffness), f64::from(damping), f64::from(dt));
    let secant = (next - f64::from(offset)) / f64::from(dt);
    joint.spring_lag = Vec3::new((rate - secant) as f32, 0.0, 0.0);
    let impulse = axis * ((mass * (secant - f64::from(speed))) as f32);
    v[joint.a].linear -= impulse * ma.inverse_mass;
    v[joint.b].linear += impulse * mb.inverse_mass;
}
