//! Plastic joints (paper §4.1): a bar of two boxes joined by a plastic joint, hit near its free
//! end by a steel ball in free space, keeps its shape below the joint's strength and takes a
//! lasting bend above it, more for faster hits; the bend goes on briefly after the hit, damped.

use dentbend::bend::JointRule;
use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_solver::sim::{BendEvent, BodyDesc, ColliderKind, JointKind, SurfaceMaterial, World, WorldSettings};

/// Angular impulse the joint transmits per step before it bends, N·m·s.
const STRENGTH: f32 = 0.5;

struct Hit {
    world: World,
    joint: usize,
    /// Total linear momentum before the step loop, kg·m/s.
    momentum: Vec3,
    bends: Vec<(usize, BendEvent)>,
}

/// Two 0.5 × 0.1 × 0.1 m boxes (5 kg each) meeting at the origin, joined there; a 5 cm steel
/// ball (about 4 kg, restitution 0.3) falls at `speed` onto the right box 0.45 m from the joint. For
/// a rigid bar that hit needs an angular impulse of about 0.15 N·m·s per m/s at the joint, so
/// 0.5 N·m·s holds up to about 3.3 m/s (measured: no bend at 3.0, a bend at 3.5).
fn hit(speed: f32, steps: usize) -> Hit {
    let settings = WorldSettings { gravity: Vec3::ZERO, angular_damping: 0.0, sleep_time: 0.0, ..Default::default() };
    let mut world = World::new(settings).unwrap();
    let half = mesh::subdivided_box(Vec3::new(0.5, 0.1, 0.1), [1, 1, 1]).unwrap();
    let box_at = |name: &str, x: f32| {
        BodyDesc::new(name, half.clone()).at(Vec3::new(x, 0.0, 0.0)).collider(ColliderKind::Cuboid)
    };
    let left = world.add(box_at("left", -0.25)).unwrap();
    let right = world.add(box_at("right", 0.25)).unwrap();
    let kind =
        JointKind::Bend(JointRule::Plastic { strength: STRENGTH, damping_constant: 5.0, damping_proportional: 20.0 });
    let joint = world.add_joint(left, right, Vec3::ZERO, kind).unwrap();
    let mut ball = BodyDesc::new("ball", mesh::icosphere(0.05, 2).unwrap())
        .at(Vec3::new(0.45, 0.2, 0.0))
        .velocity(Vec3::new(0.0, -speed, 0.0))
        .collider(ColliderKind::Ball);
    ball.density = 7800.0;
    ball.surface = SurfaceMaterial { restitution: 0.3, friction: 0.0 };
    world.add(ball).unwrap();
    let momentum = total_momentum(&world);
    let mut bends = Vec::new();
    for step in 0..steps {
        bends.extend(world.step().bends.into_iter().map(|b| (step, b)));
    }
    Hit { world, joint, momentum, bends }
}

fn total_momentum(world: &World) -> Vec3 {
    world.bodies().iter().map(|b| b.momentum()).sum()
}

/// The angle between the bar halves' relative orientation now and when the joint was made, rad.
fn bent(h: &Hit) -> f32 {
    let joint = &h.world.joints()[h.joint];
    joint.rest().angle_between(joint.relative_orientation(h.world.bodies()).unwrap())
}

/// Below strength (2 m/s, 60 % of the threshold speed) the joint stays rigid: after 1 s the
/// halves are within 0.5° of their original relative orientation and no bend was reported.
/// Linear momentum is kept to f32 round-off (1e-4 relative): joint impulses are internal.
#[test]
fn a_soft_hit_leaves_no_bend() {
    let h = hit(2.0, 60);
    assert!(bent(&h).to_degrees() < 0.5, "bent by {}°", bent(&h).to_degrees());
    assert!(h.bends.is_empty(), "bends reported: {:?}", h.bends);
    let momentum = total_momentum(&h.world);
    assert!((momentum - h.momentum).length() < 1e-4 * h.momentum.length(), "momentum {} -> {momentum}", h.momentum);
    assert!(h.world.bodies()[0].angular_velocity.length() > 0.1, "the hit did not reach the bar");
}

/// Above strength the bar bends and stays bent: after 1 s the relative motion of the halves has
/// stopped (< 1e-3 rad/s, the joint no longer bending) and the bend is over 0.5°; another 1 s
/// later it is unchanged within 0.01°. The joint's target followed the bend (what remains is
/// the joint's own `bend_angle`, within 0.05°), and the reported step angles add up to it.
/// A faster hit bends more, strictly, over 4, 5 and 6 m/s (each by over 1°).
#[test]
fn hard_hits_bend_for_good_and_faster_bends_more() {
    let mut previous = 0.0f32;
    for speed in [4.0, 5.0, 6.0] {
        let mut h = hit(speed, 60);
        let joint = &h.world.joints()[h.joint];
        let relative_spin = h.world.bodies()[1].angular_velocity - h.world.bodies()[0].angular_velocity;
        assert!(relative_spin.length() < 1e-3, "{speed} m/s: still turning at {relative_spin}");
        assert!(!joint.is_bending(), "{speed} m/s: still bending after 1 s");
        let angle = bent(&h);
        assert!(angle.to_degrees() > 0.5, "{speed} m/s: bent only {}°", angle.to_degrees());
        assert!((joint.bend_angle() - angle).abs().to_degrees() < 0.05, "target lags the bend");
        let reported: f32 = h.bends.iter().map(|(_, b)| b.angle).sum();
        assert!((reported - angle).abs().to_degrees() < 0.05, "{speed} m/s: events add to {reported} rad");
        assert!(angle.to_degrees() > previous + 1.0, "{speed} m/s bent {}° after {previous}°", angle.to_degrees());
        previous = angle.to_degrees();
        for _ in 0..60 {
            h.world.step();
        }
        let later = bent(&h);
        assert!((later - angle).abs().to_degrees() < 0.01, "{speed} m/s: bend went from {angle} to {later} rad");
    }
}

/// The bend goes on for a few steps after the hit, each step's added angle smaller than the
/// last (constant + proportional damping of the relative spin, never reversing), then stops.
#[test]
fn the_bend_continues_briefly_and_dies_out() {
    let h = hit(6.0, 60);
    assert!(h.bends.len() >= 3, "the bend stopped at once: {:?}", h.bends);
    let steps: Vec<usize> = h.bends.iter().map(|(s, _)| *s).collect();
    assert!(steps.windows(2).all(|w| w[1] == w[0] + 1), "bend steps not consecutive: {steps:?}");
    let angles: Vec<f32> = h.bends.iter().map(|(_, b)| b.angle).collect();
    assert!(angles[1..].windows(2).all(|w| w[1] < w[0]), "bend does not slow down: {angles:?}");
    let totals: Vec<f32> = h.bends.iter().map(|(_, b)| b.total_angle).collect();
    assert!(totals.windows(2).all(|w| w[1] > w[0]), "bend reversed: {totals:?}");
    assert!(steps.len() < 30, "bend lasted {} steps", steps.len());
}
