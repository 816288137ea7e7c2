//! Articulated bodies in maximal coordinates: rigid and ball joints hold under gravity while
//! swinging, jointed bodies still collide with others and sleep as a group, bad joints are refused.

use dentbend::bend::JointRule;
use dentbend::glam::{Quat, Vec3};
use dentbend::mesh;
use dentbend_solver::sim::{BodyDesc, BodyKind, ColliderKind, JointKind, SimError, World, WorldSettings};

fn block(name: &str, size: Vec3, at: Vec3) -> BodyDesc {
    let mesh = mesh::subdivided_box(size, [1, 1, 1]).unwrap();
    BodyDesc::new(name, mesh).at(at).collider(ColliderKind::Cuboid)
}

fn fixed(name: &str, size: Vec3, at: Vec3) -> BodyDesc {
    block(name, size, at).kind(BodyKind::Static)
}

/// Kinetic plus gravitational potential energy of the dynamic bodies, J.
fn energy(world: &World) -> f64 {
    let g = -f64::from(world.settings().gravity.y);
    world
        .bodies()
        .iter()
        .filter(|b| b.kind == BodyKind::Dynamic)
        .map(|b| f64::from(b.kinetic_energy()) + f64::from(b.mass) * g * f64::from(b.position.y))
        .sum()
}

/// An L-shaped pair (arm + tip, rigid joint) on a ball joint under a static hook, released
/// horizontally, swings through its lowest point at about 4 m/s. Over 4 s the anchors of both
/// joints stay within 1 mm (the brief's bound; one step of free fall is g·dt² ≈ 2.7 mm, so an
/// unheld joint fails at once) and the rigid joint's relative orientation within 0.5°.
/// Semi-implicit Euler makes the energy of a pendulum oscillate by about m·g·v·dt ≈ 1 J here
/// without drifting, so energy is checked for growth between windows: the highest energy in the
/// last 1.5 s may not exceed that of the first 1.5 s by more than 1 % of the drop's energy
/// (0.5 J), which catches joints that pump energy through their position corrections.
#[test]
fn rigid_pair_swinging_from_a_hook_stays_together() {
    let settings = WorldSettings { angular_damping: 0.0, sleep_time: 0.0, ..Default::default() };
    let mut world = World::new(settings).unwrap();
    let hook = world.add(fixed("hook", Vec3::splat(0.1), Vec3::new(0.0, 2.0, 0.0))).unwrap();
    let arm = world.add(block("arm", Vec3::new(0.6, 0.1, 0.1), Vec3::new(0.3, 2.0, 0.0))).unwrap();
    let tip = world.add(block("tip", Vec3::new(0.1, 0.4, 0.1), Vec3::new(0.65, 1.85, 0.0))).unwrap();
    let pivot = world.add_joint(hook, arm, Vec3::new(0.0, 2.0, 0.0), JointKind::Ball).unwrap();
    let weld = world.add_joint(arm, tip, Vec3::new(0.6, 2.0, 0.0), JointKind::Rigid).unwrap();
    let mut lowest = f32::INFINITY;
    let (mut worst_gap, mut worst_angle) = (0.0f32, 0.0f32);
    let (mut early, mut late) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for step in 0..240 {
        world.step();
        for k in [pivot, weld] {
            worst_gap = worst_gap.max(world.joints()[k].separation(world.bodies()).unwrap().length());
        }
        worst_angle = worst_angle.max(world.joints()[weld].deviation(world.bodies()).unwrap().length());
        lowest = lowest.min(world.bodies()[tip].position.y);
        if step < 90 {
            early = early.max(energy(&world));
        } else if step >= 150 {
            late = late.max(energy(&world));
        }
    }
    // The tip centre is 0.667 m from the pivot, so it can go no lower than y = 1.333.
    assert!(lowest < 1.4, "the pendulum did not swing down: lowest tip centre {lowest}");
    assert!(worst_gap < 1e-3, "anchors drifted {worst_gap} m apart");
    assert!(worst_angle.to_degrees() < 0.5, "rigid joint turned {}°", worst_angle.to_degrees());
    let drop = f64::from(world.bodies()[arm].mass + world.bodies()[tip].mass) * 9.81 * 0.5;
    assert!(late <= early + 0.01 * drop, "energy grew from {early} to {late} J");
}

/// Five links on ball joints from a static hook, released horizontally: every joint's anchors
/// stay within 1 mm over 2 s while the chain swings (the free end falls by more than 1 m).
#[test]
fn chain_of_five_swings_attached() {
    let mut world = World::new(WorldSettings::default()).unwrap();
    let hook = world.add(fixed("hook", Vec3::splat(0.06), Vec3::new(0.0, 3.0, 0.0))).unwrap();
    let mut previous = hook;
    let mut joints = Vec::new();
    for k in 0..5 {
        let x = 0.3 * k as f32;
        let link =
            world.add(block(&format!("link{k}"), Vec3::new(0.3, 0.06, 0.06), Vec3::new(x + 0.15, 3.0, 0.0))).unwrap();
        joints.push(world.add_joint(previous, link, Vec3::new(x, 3.0, 0.0), JointKind::Ball).unwrap());
        previous = link;
    }
    let mut worst = 0.0f32;
    let mut lowest = f32::INFINITY;
    for _ in 0..120 {
        world.step();
        for &k in &joints {
            worst = worst.max(world.joints()[k].separation(world.bodies()).unwrap().length());
        }
        lowest = lowest.min(world.bodies()[previous].position.y);
    }
    assert!(lowest < 2.0, "the chain did not swing: free end lowest at {lowest}");
    assert!(worst < 1e-3, "a joint opened by {worst} m");
}

/// A ball joint leaves rotation free: a bar pinned at its centre of mass to a static post keeps
/// spinning (no gravity, no angular damping) at its initial rate within 1 %.
#[test]
fn ball_joint_leaves_rotation_free() {
    let settings = WorldSettings { gravity: Vec3::ZERO, angular_damping: 0.0, ..Default::default() };
    let mut world = World::new(settings).unwrap();
    let post = world.add(fixed("post", Vec3::splat(0.05), Vec3::ZERO)).unwrap();
    let mut bar = block("bar", Vec3::new(0.6, 0.1, 0.1), Vec3::ZERO);
    bar.angular_velocity = Vec3::new(0.0, 0.0, 3.0);
    let bar = world.add(bar).unwrap();
    world.add_joint(post, bar, Vec3::ZERO, JointKind::Ball).unwrap();
    for _ in 0..60 {
        world.step();
    }
    let spin = world.bodies()[bar].angular_velocity.z;
    assert!((spin - 3.0).abs() < 0.03, "spin changed to {spin} rad/s");
    assert!(world.bodies()[bar].position.length() < 1e-3, "the pin moved");
}

/// A block hanging by a ball joint from a kinematic carrier moving at 1 m/s along x (no
/// gravity) is dragged along: after 1 s the joint is closed within 1 mm and the block's centre,
/// free to swing round the joint, is within its 0.15 m lever (+1 mm) of the carrier's anchor,
/// 1 m from where it started. The carrier is not pushed back (it keeps its 1 m/s).
#[test]
fn kinematic_carrier_drags_its_load() {
    let settings = WorldSettings { gravity: Vec3::ZERO, ..Default::default() };
    let mut world = World::new(settings).unwrap();
    let carrier = block("carrier", Vec3::splat(0.1), Vec3::new(0.0, 1.0, 0.0))
        .kind(BodyKind::Kinematic)
        .velocity(Vec3::new(1.0, 0.0, 0.0));
    let carrier = world.add(carrier).unwrap();
    let load = world.add(block("load", Vec3::new(0.1, 0.3, 0.1), Vec3::new(0.0, 0.8, 0.0))).unwrap();
    let joint = world.add_joint(carrier, load, Vec3::new(0.0, 0.95, 0.0), JointKind::Ball).unwrap();
    for _ in 0..60 {
        world.step();
    }
    let (on_carrier, _) = world.joints()[joint].anchors(world.bodies()).unwrap();
    let reach = world.bodies()[load].position.distance(on_carrier);
    assert!(reach < 0.151, "the load is {reach} m from the anchor");
    assert!((on_carrier.x - 1.0).abs() < 1e-3, "carrier anchor at {on_carrier}");
    assert_eq!(world.bodies()[carrier].linear_velocity, Vec3::new(1.0, 0.0, 0.0));
    let gap = world.joints()[joint].separation(world.bodies()).unwrap().length();
    assert!(gap < 1e-3, "joint opened by {gap} m");
}

/// A bar of two boxes welded by a rigid joint falls 0.3 m onto a static slab: it rests on it
/// (the bottoms above the slab top within 5 mm, the world's slop being 2 mm), the weld holds
/// (1 mm, 0.5°), the two halves always share one sleep state, and they end asleep. A ball then
/// dropped on one half wakes both.
#[test]
fn jointed_bar_rests_on_the_ground_and_sleeps_as_one() {
    let mut world = World::new(WorldSettings::default()).unwrap();
    world.add(fixed("ground", Vec3::new(4.0, 0.2, 4.0), Vec3::new(0.0, -0.1, 0.0))).unwrap();
    let left = world.add(block("left", Vec3::new(0.5, 0.1, 0.1), Vec3::new(-0.25, 0.35, 0.0))).unwrap();
    let right = world.add(block("right", Vec3::new(0.5, 0.1, 0.1), Vec3::new(0.25, 0.35, 0.0))).unwrap();
    let weld = world.add_joint(left, right, Vec3::new(0.0, 0.35, 0.0), JointKind::Rigid).unwrap();
    let (mut worst_gap, mut worst_angle) = (0.0f32, 0.0f32);
    for step in 0..150 {
        world.step();
        let (l, r) = (&world.bodies()[left], &world.bodies()[right]);
        assert_eq!(l.is_asleep(), r.is_asleep(), "step {step}: the halves sleep apart");
        worst_gap = worst_gap.max(world.joints()[weld].separation(world.bodies()).unwrap().length());
        worst_angle = worst_angle.max(world.joints()[weld].deviation(world.bodies()).unwrap().length());
    }
    for k in [left, right] {
        let bottom = world.bodies()[k].position.y - 0.05;
        assert!(bottom > -0.005 && bottom < 0.01, "{} rests at {bottom} m", world.bodies()[k].name);
        assert!(world.bodies()[k].is_asleep(), "{} never fell asleep", world.bodies()[k].name);
    }
    assert!(worst_gap < 1e-3, "weld opened by {worst_gap} m");
    assert!(worst_angle.to_degrees() < 0.5, "weld turned {}°", worst_angle.to_degrees());

    let ball = BodyDesc::new("ball", mesh::icosphere(0.05, 2).unwrap())
        .at(Vec3::new(0.4, 0.3, 0.0))
        .velocity(Vec3::new(0.0, -2.0, 0.0))
        .collider(ColliderKind::Ball);
    world.add(ball).unwrap();
    let mut woke = false;
    for _ in 0..20 {
        world.step();
        let (l, r) = (&world.bodies()[left], &world.bodies()[right]);
        assert_eq!(l.is_asleep(), r.is_asleep(), "the halves sleep apart after the hit");
        woke |= !l.is_asleep();
    }
    assert!(woke, "the ball did not wake the bar");
}

/// A square frame of four bars welded at its corners by rigid joints is a closed loop: its
/// joints are redundant (any three hold the fourth), so the joint system is singular. Dropped
/// 0.3 m onto a slab it must still hold together (1 mm, 0.5°), land flat and come to rest.
#[test]
fn closed_loop_of_rigid_joints_holds() {
    let mut world = World::new(WorldSettings::default()).unwrap();
    world.add(fixed("ground", Vec3::new(4.0, 0.2, 4.0), Vec3::new(0.0, -0.1, 0.0))).unwrap();
    let y = 0.325;
    let along_x = Vec3::new(0.55, 0.05, 0.05);
    let along_z = Vec3::new(0.05, 0.05, 0.55);
    let bars = [
        world.add(block("north", along_x, Vec3::new(0.0, y, -0.25))).unwrap(),
        world.add(block("east", along_z, Vec3::new(0.25, y, 0.0))).unwrap(),
        world.add(block("south", along_x, Vec3::new(0.0, y, 0.25))).unwrap(),
        world.add(block("west", along_z, Vec3::new(-0.25, y, 0.0))).unwrap(),
    ];
    let corners = [(0.25, -0.25), (0.25, 0.25), (-0.25, 0.25), (-0.25, -0.25)];
    let welds: Vec<usize> = (0..4)
        .map(|k| {
            let (x, z) = corners[k];
            world.add_joint(bars[k], bars[(k + 1) % 4], Vec3::new(x, y, z), JointKind::Rigid).unwrap()
        })
        .collect();
    let (mut worst_gap, mut worst_angle) = (0.0f32, 0.0f32);
    for _ in 0..120 {
        world.step();
        for &k in &welds {
            worst_gap = worst_gap.max(world.joints()[k].separation(world.bodies()).unwrap().length());
            worst_angle = worst_angle.max(world.joints()[k].deviation(world.bodies()).unwrap().length());
        }
    }
    assert!(worst_gap < 1e-3, "a corner opened by {worst_gap} m");
    assert!(worst_angle.to_degrees() < 0.5, "a corner turned {}°", worst_angle.to_degrees());
    for &k in &bars {
        let body = &world.bodies()[k];
        assert!((body.position.y - 0.025).abs() < 0.005, "{} rests at {}", body.name, body.position.y);
        assert!(body.linear_velocity.length() < 0.05, "{} still moves at {}", body.name, body.linear_velocity);
    }
}

fn refused(result: Result<usize, SimError>, what: &str) {
    assert!(matches!(result, Err(SimError::Invalid { .. })), "{what}: {result:?}");
}

/// Bad joints are refused with `SimError::Invalid` and leave the world without joints.
#[test]
fn bad_joints_are_refused() {
    let mut world = World::new(WorldSettings::default()).unwrap();
    let post = world.add(fixed("post", Vec3::splat(0.1), Vec3::ZERO)).unwrap();
    let wall = world.add(fixed("wall", Vec3::splat(0.1), Vec3::X)).unwrap();
    let a = world.add(block("a", Vec3::splat(0.1), Vec3::Y)).unwrap();
    let b = world.add(block("b", Vec3::splat(0.1), Vec3::new(0.0, 2.0, 0.0))).unwrap();
    let at = Vec3::new(0.0, 1.5, 0.0);
    refused(world.add_joint(a, a, at, JointKind::Rigid), "same body twice");
    refused(world.add_joint(a, 99, at, JointKind::Rigid), "body index out of range");
    refused(world.add_joint(99, a, at, JointKind::Rigid), "body index out of range");
    refused(world.add_joint(post, wall, at, JointKind::Rigid), "two static bodies");
    refused(world.add_joint(a, b, Vec3::new(f32::NAN, 0.0, 0.0), JointKind::Rigid), "NaN anchor");
    refused(world.add_joint(a, b, Vec3::splat(f32::INFINITY), JointKind::Ball), "infinite anchor");
    let plastic = |strength, damping_constant, damping_proportional| {
        JointKind::Bend(JointRule::Plastic { strength, damping_constant, damping_proportional })
    };
    refused(world.add_joint(a, b, at, plastic(-1.0, 0.0, 0.0)), "negative strength");
    refused(world.add_joint(a, b, at, plastic(0.0, 0.0, 0.0)), "zero strength");
    refused(world.add_joint(a, b, at, plastic(f32::NAN, 0.0, 0.0)), "NaN strength");
    refused(world.add_joint(a, b, at, plastic(1.0, -1.0, 0.0)), "negative constant damping");
    refused(world.add_joint(a, b, at, plastic(1.0, 0.0, f32::INFINITY)), "infinite proportional damping");
    refused(
        world.add_joint(a, b, at, JointKind::Bend(JointRule::Elastic { stiffness: -1.0, damping: 0.0 })),
        "negative stiffness",
    );
    refused(
        world.add_joint(a, b, at, JointKind::Bend(JointRule::Elastic { stiffness: 1.0, damping: f32::NAN })),
        "NaN damping",
    );
    let prismatic = |axis| JointKind::ElasticPrismatic { axis, stiffness: 1.0, damping: 0.0 };
    refused(world.add_joint(a, b, at, prismatic(Vec3::ZERO)), "zero axis");
    refused(world.add_joint(a, b, at, prismatic(Vec3::new(f32::NAN, 1.0, 0.0))), "NaN axis");
    assert!(world.joints().is_empty());
    // The same bodies with good numbers are fine, and a rotated body's anchor lands where given.
    world.bodies_mut()[b].orientation = Quat::from_rotation_z(0.7);
    let k = world.add_joint(a, b, at, plastic(1.0, 0.5, 0.5)).unwrap();
    let (on_a, on_b) = world.joints()[k].anchors(world.bodies()).unwrap();
    assert!(on_a.distance(at) < 1e-6 && on_b.distance(at) < 1e-6, "{on_a} {on_b}");
    assert!(world.joints()[k].deviation(world.bodies()).unwrap().length() < 1e-6);
}

/// A chain of three boards welded by rigid joints rests across two supports under its ends.
/// Contacts are solved before the joints' impulses, so without alternating the two the joints
/// pushed the end boards into their supports every step and the chain sank through them
/// (measured before the fix: 6.5 mm in 1 s for a two-bone bar, and on). After 5 s every board's
/// centre is at half its thickness above the supports within the slop plus 1 mm.
#[test]
fn a_jointed_chain_resting_on_two_supports_does_not_sink() {
    let mut world = World::new(WorldSettings::default()).unwrap();
    for (name, x) in [("left", -1.3), ("right", 1.3)] {
        world.add(fixed(name, Vec3::new(0.4, 0.6, 0.6), Vec3::new(x, -0.3, 0.0))).unwrap();
    }
    let boards: Vec<usize> = (0..3)
        .map(|k| {
            let x = -1.0 + k as f32;
            world.add(block(&format!("board{k}"), Vec3::new(1.0, 0.1, 0.3), Vec3::new(x, 0.051, 0.0))).unwrap()
        })
        .collect();
    for k in 0..2 {
        let anchor = Vec3::new(-0.5 + k as f32, 0.051, 0.0);
        world.add_joint(boards[k], boards[k + 1], anchor, JointKind::Rigid).unwrap();
    }
    for _ in 0..300 {
        world.step();
    }
    let bound = world.settings().slop + 1e-3;
    for &k in &boards {
        let y = world.bodies()[k].position.y;
        assert!((y - 0.05).abs() < bound, "board {k} rests at {y} m (0.05 expected)");
    }
}
