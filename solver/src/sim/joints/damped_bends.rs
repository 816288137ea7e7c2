//! Post-stabilization of joint groups with a bending plastic joint, without adding energy.
//!
//! A bending joint's post-stabilization target is its damped relative angular velocity (paper
//! §4.1): damping, which can only take kinetic energy away. On its own, or in an open chain,
//! the target is one the joints can meet together and holding it does take energy away. In a
//! closed loop — a tetrahedron of struts pinned at its balls, several of them bent — the joints'
//! targets, each measured on its own joint, need not fit together: no velocities turn every
//! joint at its rate and keep every anchor together. The group's solve then finds the
//! (least-squares) impulses for a target that does not exist, and those can be arbitrarily
//! large: one step of a pile of bent tetrahedra gained hundreds of joules there, and launched a
//! tetrahedron lying on the floor.
//!
//! So a group with a bending joint is solved twice from the same velocities: with every joint
//! rigid (zero targets: a projection, which never adds energy) and with the bend targets. The
//! solution is linear in the targets, so scaling them all by s ∈ [0, 1] blends the two solutions
//! and the group's kinetic energy is a convex quadratic in s: the group keeps the largest
//! fraction s of its bend targets whose kinetic energy is no more than before the
//! post-stabilization (s = 1 where the targets fit, as for a lone bending joint), and its bending
//! joints keep s times their rates for the next step. Where the targets did not fit, the
//! least-squares solve also let the anchors part; a last projection (bending joints held as ball
//! joints, which adds no energy either) puts them back together.
//!
//! This is no cap on energy that the physics would add: damping, and the projections of
//! post-stabilization (Weinstein–Teran–Fedkiw 2006), only ever remove kinetic energy, so a
//! group that gains any is solving for a motion that does not exist.

use super::solve::{self, Rows};
use super::system::{self, Mobility, Motion};
use super::{Joint, JointKind};
use crate::sim::RigidBody;

/// Relative slack of the energy comparison (round-off of f32 velocities summed in f64): a group
/// whose targets fit loses energy to damping, far more than this.
const ROUND_OFF: f64 = 1e-6;

/// Holds `groups` of `joints` on velocities `v` as post-stabilization does (`rows_at(joints, v,
/// bend)` gives every joint's rows at `v`, with the bend targets or with zero ones), keeping of
/// each group's bend targets the largest fraction that adds no kinetic energy, and the anchors
/// together; bending joints' rates are scaled to what was kept.
pub(super) fn hold_bending(
    joints: &mut [Joint],
    groups: &[Vec<usize>],
    rows_at: impl Fn(&[Joint], &[Motion], bool) -> Vec<Option<Rows>>,
    bodies: &[RigidBody],
    mob: &[Mobility],
    v: &mut [Motion],
) {
    let start = v.to_vec();
    solve::solve_rows(joints, groups, &rows_at(joints, v, true), mob, v, false, 0.0);
    let bending: Vec<Vec<usize>> =
        groups.iter().filter(|group| group.iter().any(|&k| joints[k].is_bending())).cloned().collect();
    if bending.is_empty() {
        return;
    }
    let mut rigid = start.clone();
    solve::solve_rows(joints, &bending, &rows_at(joints, &start, false), mob, &mut rigid, false, 0.0);
    for group in &bending {
        let s = keep_energy(joints, group, bodies, mob, (&start, &rigid), v);
        for &k in group {
            joints[k].bend_rate *= s as f32;
        }
    }
    hold_anchors(joints, &bending, rows_at, mob, v);
}

/// Blends `group`'s bodies' velocities in `v` (solved with the bend targets) towards `rigid`
/// (solved with zero targets, both from `start`) just enough that their kinetic energy is no more
/// than at `start`; returns the fraction s of the bend targets kept.
fn keep_energy(
    joints: &[Joint],
    group: &[usize],
    bodies: &[RigidBody],
    mob: &[Mobility],
    (start, rigid): (&[Motion], &[Motion]),
    v: &mut [Motion],
) -> f64 {
    let mut moved: Vec<usize> =
        group.iter().flat_map(|&k| [joints[k].a, joints[k].b]).filter(|&i| system::takes_impulses(&mob[i])).collect();
    moved.sort_unstable();
    moved.dedup();
    let difference: Vec<Motion> = moved
        .iter()
        .map(|&i| Motion { linear: v[i].linear - rigid[i].linear, angular: v[i].angular - rigid[i].angular })
        .collect();
    let energy = |at: &dyn Fn(usize) -> Motion| -> f64 {
        (0..moved.len()).map(|n| f64::from(bodies[moved[n]].kinetic_energy_at(at(n).linear, at(n).angular))).sum()
    };
    let before = energy(&|n| start[moved[n]]);
    let held = energy(&|n| rigid[moved[n]]);
    let bent = energy(&|n| v[moved[n]]);
    // KE(s) = held + b·s + c·s², c the kinetic energy of the difference.
    let c = energy(&|n| difference[n]);
    let b = bent - held - c;
    let s = kept_fraction(before * (1.0 + ROUND_OFF), held, b, c);
    if s < 1.0 {
        for (&i, d) in moved.iter().zip(&difference) {
            let r = rigid[i];
            v[i] = Motion { linear: r.linear + d.linear * s as f32, angular: r.angular + d.angular * s as f32 };
        }
    }
    s
}

/// Holds the anchors of `groups`' joints (and the orientation of those not bending) once more:
/// where the bend targets did not fit, their least-squares solve left the anchors parting, and
/// the bones must never detach. The bending joints are held as ball joints here, so this is a
/// projection of the velocities, which adds no energy; it changes nothing where the targets fit.
fn hold_anchors(
    joints: &mut [Joint],
    groups: &[Vec<usize>],
    rows_at: impl Fn(&[Joint], &[Motion], bool) -> Vec<Option<Rows>>,
    mob: &[Mobility],
    v: &mut [Motion],
) {
    let bending: Vec<(usize, JointKind)> =
        groups.iter().flatten().filter(|&&k| joints[k].is_bending()).map(|&k| (k, joints[k].kind)).collect();
    for &(k, _) in &bending {
        joints[k].kind = JointKind::Ball;
    }
    let rows = rows_at(joints, v, false);
    solve::solve_rows(joints, groups, &rows, mob, v, false, 0.0);
    for (k, kind) in bending {
        joints[k].kind = kind;
    }
}

/// The largest s in [0, 1] with `held` + `b`·s + `c`·s² ≤ `limit` (`c` ≥ 0); 0 when even s = 0
/// passes the limit.
fn kept_fraction(limit: f64, held: f64, b: f64, c: f64) -> f64 {
    if held + b + c <= limit {
        return 1.0;
    }
    if held > limit || c <= 0.0 {
        return 0.0;
    }
    // The larger root of c·s² + b·s + (held − limit) = 0; held ≤ limit puts it at s ≥ 0, and
    // KE(1) > limit below 1.
    let root = (-b + (b * b + 4.0 * c * (limit - held)).sqrt()) / (2.0 * c);
    root.clamp(0.0, 1.0)
}

#[cfg(test)]
#[path = "damped_bends_recorded.rs"]
mod recorded;

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::kept_fraction;
    use super::recorded;
    use crate::sim::joints::poststabilize::hold_velocities;
    use crate::sim::joints::system::{Motion, mobilities};
    use crate::sim::joints::{Joint, JointKind, poststabilize};
    use crate::sim::{BodyDesc, RigidBody, WorldSettings};
    use dentbend::bend::JointRule;

    /// The fraction kept is where the quadratic meets the limit: all of it when s = 1 is within
    /// it, none when s = 0 is not, and the root in between otherwise.
    #[test]
    fn the_fraction_kept_meets_the_limit() {
        assert_eq!(kept_fraction(10.0, 5.0, 1.0, 1.0), 1.0);
        assert_eq!(kept_fraction(4.0, 5.0, 1.0, 1.0), 0.0);
        // 2 + 0·s + 8·s² = 4 at s = 0.5.
        assert!((kept_fraction(4.0, 2.0, 0.0, 8.0) - 0.5).abs() < 1e-12);
        // 1 − 2·s + 10·s² = 1 at s = 0.2 (the energy dips first, then passes the limit).
        assert!((kept_fraction(1.0, 1.0, -2.0, 10.0) - 0.2).abs() < 1e-12);
    }

    const STRENGTH: f32 = 0.5;
    const PLASTIC: JointKind =
        JointKind::Bend(JointRule::Plastic { strength: STRENGTH, damping_constant: 1.0, damping_proportional: 6.0 });

    /// Bars 0.5 m × 5 cm × 5 cm (steel-like density 1,000 kg/m³) centred at `centres`, along
    /// `axes`, spinning at `spins` (rad/s).
    fn bars(centres: &[Vec3], axes: &[Vec3], spins: &[Vec3]) -> Vec<RigidBody> {
        let mesh = dentbend::mesh::subdivided_box(Vec3::new(0.5, 0.05, 0.05), [1, 1, 1]).unwrap();
        centres
            .iter()
            .zip(axes)
            .zip(spins)
            .enumerate()
            .map(|(k, ((&at, &axis), &spin))| {
                let mut desc = BodyDesc::new(format!("bar{k}"), mesh.clone()).at(at);
                desc.orientation = glam::Quat::from_rotation_arc(Vec3::X, axis);
                desc.angular_velocity = spin;
                desc.density = 1000.0;
                RigidBody::new(desc).unwrap()
            })
            .collect()
    }

    fn kinetic(bodies: &[RigidBody]) -> f64 {
        bodies.iter().map(|b| f64::from(b.kinetic_energy())).sum()
    }

    /// Largest relative velocity of the anchors of `joints`, m/s.
    fn worst_anchor_speed(joints: &[Joint], bodies: &[RigidBody]) -> f32 {
        joints
            .iter()
            .map(|j| {
                let (pa, pb) = j.anchors(bodies).unwrap();
                (bodies[j.b].velocity_at(pb) - bodies[j.a].velocity_at(pa)).length()
            })
            .fold(0.0, f32::max)
    }

    /// A closed square of four bars joined at its corners by plastic joints, every joint bending
    /// (it clamped this step) with the bars spinning every which way: no velocities keep all four
    /// corners together and turn every joint at its damped rate, so holding the rates as given
    /// would take impulses out of nothing. Post-stabilization keeps what of the rates it can
    /// without adding kinetic energy (f32 round-off allowed: 1e-5 relative), and the corners
    /// still hold (1 mm/s).
    #[test]
    fn bending_joints_in_a_closed_loop_add_no_energy() {
        let half = 0.25;
        let centres = [
            Vec3::new(0.0, 0.0, -half),
            Vec3::new(half, 0.0, 0.0),
            Vec3::new(0.0, 0.0, half),
            Vec3::new(-half, 0.0, 0.0),
        ];
        let axes = [Vec3::X, Vec3::Z, Vec3::X, Vec3::Z];
        let spins = [
            Vec3::new(3.0, -5.0, 2.0),
            Vec3::new(-4.0, 1.0, 6.0),
            Vec3::new(5.0, 4.0, -3.0),
            Vec3::new(-2.0, -6.0, -1.0),
        ];
        let mut bodies = bars(&centres, &axes, &spins);
        let corners = [
            Vec3::new(half, 0.0, -half),
            Vec3::new(half, 0.0, half),
            Vec3::new(-half, 0.0, half),
            Vec3::new(-half, 0.0, -half),
        ];
        let mut joints: Vec<Joint> = (0..4)
            .map(|k| {
                let mut joint = Joint::new(&bodies, k, (k + 1) % 4, corners[k], PLASTIC).unwrap();
                joint.clamped = true;
                joint
            })
            .collect();
        let settings = WorldSettings::default();
        let before = kinetic(&bodies);
        poststabilize(&mut joints, &mut bodies, &settings);
        let after = kinetic(&bodies);
        assert!(after <= before * (1.0 + 1e-5), "kinetic energy {before} J became {after} J");
        let worst = worst_anchor_speed(&joints, &bodies);
        assert!(worst < 1e-3, "corners part at {worst} m/s");
    }

    /// The recorded group of a tetrahedron in the full scene's pile, three of its plastic joints
    /// bending (see `damped_bends_recorded.rs`): holding their bend targets as given took its
    /// kinetic energy from 7.4 J to 4,900 J in one post-stabilization. It must not rise at all
    /// (1e-5 relative for round-off), and the anchors must hold (1 mm/s).
    #[test]
    fn a_recorded_bending_truss_gains_no_energy() {
        let (bodies, mut joints) = recorded::group();
        let mob = mobilities(&bodies, &WorldSettings::default());
        let mut v: Vec<Motion> =
            bodies.iter().map(|b| Motion { linear: b.linear_velocity, angular: b.angular_velocity }).collect();
        let before = kinetic(&bodies);
        hold_velocities(&mut joints, &bodies, &mob, &mut v, true);
        let mut after = bodies.clone();
        for (body, m) in after.iter_mut().zip(&v) {
            (body.linear_velocity, body.angular_velocity) = (m.linear, m.angular);
        }
        let gained = kinetic(&after) - before;
        assert!(gained <= 1e-5 * before, "kinetic energy {before} J gained {gained} J");
        let worst = worst_anchor_speed(&joints, &after);
        assert!(worst < 1e-3, "anchors part at {worst} m/s");
    }

    /// One bar bending off another (an open chain): its damped rate is a target the joint can
    /// meet, so post-stabilization holds all of it (paper §4.1: the bend goes on briefly after
    /// the hit): the relative angular velocity after is the damped one within 0.1 %.
    #[test]
    fn a_lone_bending_joint_keeps_its_damped_rate() {
        let centres = [Vec3::new(-0.25, 0.0, 0.0), Vec3::new(0.25, 0.0, 0.0)];
        let spins = [Vec3::ZERO, Vec3::new(0.0, 0.0, 8.0)];
        let mut bodies = bars(&centres, &[Vec3::X, Vec3::X], &spins);
        let mut joint = Joint::new(&bodies, 0, 1, Vec3::ZERO, PLASTIC).unwrap();
        joint.clamped = true;
        let mut joints = vec![joint];
        let settings = WorldSettings::default();
        let JointKind::Bend(JointRule::Plastic { damping_constant, damping_proportional, .. }) = PLASTIC else {
            unreachable!()
        };
        poststabilize(&mut joints, &mut bodies, &settings);
        let turning = bodies[1].angular_velocity - bodies[0].angular_velocity;
        let speed = 8.0 - (damping_constant + damping_proportional * 8.0) * settings.dt;
        assert!((turning.length() - speed).abs() < 1e-3 * speed, "turning at {turning}, wanted {speed} rad/s");
        assert!(worst_anchor_speed(&joints, &bodies) < 1e-3);
    }
}
