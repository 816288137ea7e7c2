//! Joint pre-stabilization (Weinstein–Teran–Fedkiw 2006), run after the contact phase and before
//! the position update: impulses on the step's new velocities such that, once positions are
//! integrated with them, every joint holds — the anchors coincide and the relative orientation is
//! the target (a plastic joint's angular impulse clamped at its strength, paper §4.1).
//!
//! The joints' predicted errors are a nonlinear function of the velocities (the position update
//! turns the levers), solved by damped Newton (Levenberg–Marquardt) iterations:
//! 1. predict every jointed body's pose after the position update exactly as `World::step`
//!    integrates it (velocity plus contact pseudo-velocity, damped spin, first-order quaternion
//!    step) and linearize each joint's errors there, with the exact derivative of that
//!    quaternion step (so large spins do not throw the Newton step off);
//! 2. solve that linear system for the joint impulses, acting at the predicted anchors (which
//!    keeps the system symmetric and solvable), exactly for each group of connected joints (see
//!    `solve`; plastic joints clamp their accumulated angular impulse there) — a linear solve per
//!    Newton step converges where Gauss–Seidel over nonlinear joint solves can run away;
//! 3. predict again; if the summed squared errors grew, go back and take a more damped step.
//!
//! Errors left when the budget is spent are taken up by the next step. Drift a joint already has
//! at the start of the step is closed at most at the world's `joint_correction_speed` and
//! `joint_correction_spin`; the rest is left for the following steps (see [`Prediction::slack`]).

use glam::Vec3;

use super::solve::{self, Rows};
use super::system::{self, Frame, Mobility, Motion};
use super::{Joint, batches, poststabilize, rotation_vector};
use crate::sim::solver::SolverBody;
use crate::sim::{RigidBody, WorldSettings};

/// Most Newton iterations of a pre-stabilization pass that must leave the joints holding.
pub(crate) const NEWTON: usize = 8;
/// Most tries of one Newton iteration, each more damped than the last.
const RETRIES: usize = 8;
/// A joint whose predicted anchors are this close holds, m (plus 1e-6 of the anchor's distance
/// from the origin, f32's resolution there).
const LINEAR_TOLERANCE: f64 = 1e-6;
/// A joint whose predicted relative orientation is this close to its target holds, rad.
const ANGULAR_TOLERANCE: f64 = 1e-6;

/// Pre-stabilizes `joints` on the step's velocities `solver` and contact pseudo-velocities
/// `pseudo` (linear, angular), both changed in place. The pseudo-velocities are first made to
/// respect the joints at velocity level, so the contact position correction moves jointed bodies
/// together; the real impulses then remove the joints' predicted errors. With `fresh` false it
/// continues the step's pre-stabilization after more contact sweeps (the accumulated impulses,
/// which plastic joints clamp, and the pseudo-velocities carry on). Each group takes at most
/// `newton_budget` Newton iterations ([`NEWTON`] for a pass that must leave the joints holding;
/// one where more contact sweeps follow and change the velocities anyway). Returns how many
/// groups of joints did not hold already and took Newton steps.
pub(crate) fn prestabilize(
    joints: &mut [Joint],
    bodies: &[RigidBody],
    solver: &mut [SolverBody],
    pseudo: &mut [(Vec3, Vec3)],
    settings: &WorldSettings,
    fresh: bool,
    newton_budget: usize,
) -> usize {
    if joints.is_empty() {
        return 0;
    }
    let mob = system::mobilities(bodies, settings);
    let mut extra: Vec<Motion> = pseudo.iter().map(|&(linear, angular)| Motion { linear, angular }).collect();
    if fresh && extra.iter().any(|m| m.linear != Vec3::ZERO || m.angular != Vec3::ZERO) {
        poststabilize::hold_velocities(joints, bodies, &mob, &mut extra, false);
        for (p, e) in pseudo.iter_mut().zip(&extra) {
            *p = (e.linear, e.angular);
        }
    }
    let mut v: Vec<Motion> = solver.iter().map(|b| Motion { linear: b.linear, angular: b.angular }).collect();
    if fresh {
        for joint in joints.iter_mut() {
            joint.accumulated = Vec3::ZERO;
            joint.clamped = false;
        }
    }
    let dt = settings.dt;
    let groups = solve::groups(joints, |k| system::joint_takes_impulses(&joints[k], &mob), &mob);
    if groups.is_empty() {
        return 0;
    }
    let stepped = batches::in_batches(joints, &groups, &mob, &mut v, |local, local_groups, v| {
        let slack = slack(local, bodies, &mob, settings);
        let step = Prediction { bodies, mob: &mob, extra: &extra, slack: &slack, dt };
        let mut rows: Vec<Option<Rows>> = (0..local.len()).map(|_| None).collect();
        local_groups.iter().filter(|group| newton(local, group, &step, v, &mut rows, newton_budget)).count()
    });
    for (b, m) in solver.iter_mut().zip(&v) {
        b.linear = m.linear;
        b.angular = m.angular;
    }
    stepped
}

/// What the joints' predicted errors depend on besides the velocities.
struct Prediction<'a> {
    bodies: &'a [RigidBody],
    mob: &'a [Mobility],
    /// Contact pseudo-velocities, added in the position update.
    extra: &'a [Motion],
    /// Per joint (by index), the drift it has now beyond what this step may close (world axes:
    /// linear m, angular rad): the predicted errors are measured from it, not from zero.
    slack: &'a [(Vec3, Vec3)],
    dt: f32,
}

/// Per joint of `joints`, its drift now (anchors apart, relative orientation off target) beyond
/// what one step closes at the world's correction speeds.
fn slack(joints: &[Joint], bodies: &[RigidBody], mob: &[Mobility], settings: &WorldSettings) -> Vec<(Vec3, Vec3)> {
    let (reach, turn) = (settings.joint_correction_speed * settings.dt, settings.joint_correction_spin * settings.dt);
    let drift = |joint: &Joint| {
        // dt = 0: the frame now (no velocity is read).
        let f = system::frame(joint, bodies, mob, &[], None, 0.0);
        let linear = f.anchor_b - f.anchor_a;
        let angular = if joint.kind.locks_rotation() { deviation(joint, &f) } else { Vec3::ZERO };
        (linear - linear.clamp_length_max(reach), angular - angular.clamp_length_max(turn))
    };
    joints.iter().map(drift).collect()
}

/// Relative orientation of a locking joint off its target in `f`, world axes, rad.
fn deviation(joint: &Joint, f: &Frame) -> Vec3 {
    rotation_vector((f.qb * (f.qa * joint.target).inverse()).normalize())
}

/// Damped Newton iterations on one group of joints (see the module notes): each group converges,
/// damps and retries on its own, so a hard group costs only its own solves. `rows` is scratch
/// space indexed by joint. Returns whether the group did not hold already.
fn newton(
    joints: &mut [Joint],
    group: &[usize],
    step: &Prediction,
    v: &mut [Motion],
    rows: &mut [Option<Rows>],
    budget: usize,
) -> bool {
    let mut moved: Vec<usize> = group.iter().flat_map(|&k| [joints[k].a, joints[k].b]).collect();
    moved.sort_unstable();
    moved.dedup();
    let mut now = measure(joints, group, step, v);
    let already_held = now.worst < 1.0;
    if already_held {
        return false;
    }
    let layout = solve::Layout::new(joints, group, step.mob);
    let mut damping = 0.0;
    for _ in 0..budget {
        if now.worst < 1.0 {
            break;
        }
        for &k in group {
            rows[k] = linearize(&joints[k], step, step.slack[k], v);
        }
        let start: Vec<Motion> = moved.iter().map(|&i| v[i]).collect();
        let start_impulse: Vec<(Vec3, bool)> =
            group.iter().map(|&k| (joints[k].accumulated, joints[k].clamped)).collect();
        let mut accepted = false;
        for _ in 0..RETRIES {
            solve::solve_group(&layout, joints, rows, step.mob, v, true, damping);
            let after = measure(joints, group, step, v);
            if after.merit < now.merit {
                now = after;
                damping = if damping > 1e-6 { damping * 0.1 } else { 0.0 };
                accepted = true;
                break;
            }
            // The step made the errors grow: back to the start, shorter (more damped) step.
            for (&i, &m) in moved.iter().zip(&start) {
                v[i] = m;
            }
            for (&k, &(accumulated, clamped)) in group.iter().zip(&start_impulse) {
                joints[k].accumulated = accumulated;
                joints[k].clamped = clamped;
            }
            damping = if damping == 0.0 { 1e-3 } else { damping * 10.0 };
        }
        if !accepted {
            break;
        }
    }
    true
}

/// A joint's rows linearized at velocities `v`: predicted errors (beyond its `slack`) per unit
/// `dt` (the velocity change that removes them); `None` when neither body takes impulses.
fn linearize(joint: &Joint, step: &Prediction, slack: (Vec3, Vec3), v: &[Motion]) -> Option<Rows> {
    let (mob, dt) = (step.mob, step.dt);
    if !system::joint_takes_impulses(joint, mob) {
        return None;
    }
    let (ma, mb) = (&mob[joint.a], &mob[joint.b]);
    let frame = system::frame(joint, step.bodies, mob, v, Some(step.extra), dt);
    let basis = system::linear_basis(joint, frame.qa);
    let (error, tolerance) = errors(joint, &frame, &basis, slack, dt);
    let per_step = 1.0 / f64::from(dt);
    Some(Rows {
        frame,
        basis,
        error: error.map(|e| e * per_step),
        tolerance: tolerance.map(|t| t * per_step),
        matrix: system::response(ma, mb, &frame, &basis),
    })
}

/// The rows' predicted errors (m, rad) beyond the joint's `slack` (linear, angular; see
/// [`Prediction::slack`]) and their tolerances in `frame`.
fn errors(joint: &Joint, f: &Frame, basis: &[Vec3; 3], slack: (Vec3, Vec3), dt: f32) -> ([f64; 6], [f64; 6]) {
    let linear = f.anchor_b - f.anchor_a - slack.0;
    let angular = if joint.kind.locks_rotation() {
        // A plastic joint still bending after a hit keeps turning at its damped rate.
        // The turn the position update's first-order quaternion step makes at the bend rate:
        // 2·atan(ω·dt/2), not ω·dt. Asking for ω·dt would need a faster spin than the rate,
        // which the next step's rate then measures: a fast bend fed itself up to max_turn.
        let rate = f.qa * joint.bend_rate;
        let keep_turning = rate.normalize_or_zero() * (2.0 * (0.5 * rate.length() * dt).atan());
        deviation(joint, f) - keep_turning - slack.1
    } else {
        Vec3::ZERO
    };
    let far = f64::from(f.anchor_a.abs().max_element().max(f.anchor_b.abs().max_element()));
    let lin_tol = LINEAR_TOLERANCE * (1.0 + far);
    let tolerance = [lin_tol, lin_tol, lin_tol, ANGULAR_TOLERANCE, ANGULAR_TOLERANCE, ANGULAR_TOLERANCE];
    (system::rows(linear, angular, basis), tolerance)
}

/// The rows a joint is held to now: a plastic joint that clamped gives up its angular rows.
fn held(joint: &Joint) -> [bool; 6] {
    let mut held = system::held_rows(joint);
    if joint.clamped {
        held[3..].fill(false);
    }
    held
}

/// How far the joints are from holding after the position update.
#[derive(Debug, Clone, Copy)]
struct Errors {
    /// Largest row error over all joints' held rows, in tolerances (< 1: all hold).
    worst: f64,
    /// Sum of the squared row errors in tolerances (what a Newton step must reduce).
    merit: f64,
}

fn measure(joints: &[Joint], group: &[usize], step: &Prediction, v: &[Motion]) -> Errors {
    let mut out = Errors { worst: 0.0, merit: 0.0 };
    // Every joint of a group has rows (see `solve::groups`).
    for &k in group {
        let joint = &joints[k];
        let frame = system::frame(joint, step.bodies, step.mob, v, Some(step.extra), step.dt);
        let basis = system::linear_basis(joint, frame.qa);
        let (error, tolerance) = errors(joint, &frame, &basis, step.slack[k], step.dt);
        let held = held(joint);
        for r in (0..6).filter(|&r| held[r]) {
            let e = error[r].abs() / tolerance[r];
            out.worst = out.worst.max(e);
            out.merit += e * e;
        }
    }
    out
}
