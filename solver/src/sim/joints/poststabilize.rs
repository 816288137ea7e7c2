//! Joint post-stabilization (Weinstein–Teran–Fedkiw 2006), run after the position update:
//! impulses that remove the relative velocity of the anchors and, for joints that lock rotation,
//! the relative angular velocity — except a bending plastic joint, which keeps its damped rate
//! (paper §4.1), and elastic angular joints, whose rotation is the spring's. The rows are linear
//! in the velocities, so one exact solve per group of connected joints (see `solve`) does it.

use glam::Vec3;

use super::solve::{self, Rows};
use super::system::{self, Mobility, Motion};
use super::{BendEvent, Joint, batches, damped_bends, plastic};
use crate::sim::{BodyKind, RigidBody, WorldSettings};

/// Velocity error below which a joint holds, m/s and rad/s.
const TOLERANCE: f64 = 1e-5;

/// Everything joints do after the position update: plastic joints take their bends (reported),
/// then post-stabilization on the bodies' velocities. (Jointed groups were brought to one sleep
/// state at the start of the step, and nothing sleeps or wakes between there and here.)
pub(crate) fn poststabilize(
    joints: &mut [Joint],
    bodies: &mut [RigidBody],
    settings: &WorldSettings,
) -> Vec<BendEvent> {
    if joints.is_empty() {
        return Vec::new();
    }
    let bends = plastic::after_step(joints, bodies, settings);
    let mob = system::mobilities(bodies, settings);
    let mut v: Vec<Motion> =
        bodies.iter().map(|b| Motion { linear: b.linear_velocity, angular: b.angular_velocity }).collect();
    hold_velocities(joints, bodies, &mob, &mut v, true);
    for (body, m) in bodies.iter_mut().zip(&v) {
        if body.kind == BodyKind::Dynamic && !body.activity.asleep && body.is_simulated() {
            body.linear_velocity = m.linear;
            body.angular_velocity = settings.limit_spin(m.angular);
        }
    }
    bends
}

/// Makes the velocities `v` respect the joints to first order: zero relative anchor velocity
/// across the held directions and, where rotation is locked, zero relative angular velocity (or,
/// with `bending`, a bending plastic joint's damped rate, as much of it as adds no energy: see
/// `damped_bends`). Also used on the contact pseudo-velocities. The rows are linear in the
/// velocities, so one solve is exact. Groups are solved in parallel batches.
pub(crate) fn hold_velocities(
    joints: &mut [Joint],
    bodies: &[RigidBody],
    mob: &[Mobility],
    v: &mut [Motion],
    bending: bool,
) {
    let groups = solve::groups(joints, |k| system::joint_takes_impulses(&joints[k], mob), mob);
    batches::in_batches(joints, &groups, mob, v, |local, local_groups, v| {
        let rows_at = |joints: &[Joint], v: &[Motion], bend: bool| -> Vec<Option<Rows>> {
            joints.iter().map(|joint| velocity_rows(joint, bodies, mob, v, bend)).collect()
        };
        if bending && local.iter().any(Joint::is_bending) {
            damped_bends::hold_bending(local, local_groups, rows_at, bodies, mob, v);
        } else {
            solve::solve_rows(local, local_groups, &rows_at(local, v, false), mob, v, false, 0.0);
        }
        0
    });
}

/// A joint's velocity rows: relative anchor velocity, relative angular velocity minus the wanted.
fn velocity_rows(joint: &Joint, bodies: &[RigidBody], mob: &[Mobility], v: &[Motion], bending: bool) -> Option<Rows> {
    if !system::joint_takes_impulses(joint, mob) {
        return None;
    }
    let (ma, mb) = (&mob[joint.a], &mob[joint.b]);
    let frame = system::frame(joint, bodies, mob, v, None, 0.0);
    let basis = system::linear_basis(joint, frame.qa);
    let (va, vb) = (v[joint.a], v[joint.b]);
    let relative = vb.linear + vb.angular.cross(frame.rb) - va.linear - va.angular.cross(frame.ra);
    let turning = vb.angular - va.angular;
    let wanted = if bending { frame.qa * joint.bend_rate } else { Vec3::ZERO };
    Some(Rows {
        frame,
        basis,
        error: system::rows(relative, turning - wanted, &basis),
        tolerance: [TOLERANCE; 6],
        matrix: system::response(ma, mb, &frame, &basis),
    })
}
