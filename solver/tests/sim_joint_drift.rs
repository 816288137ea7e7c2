//! Joint drift is closed at a bounded rate (`WorldSettings::joint_correction_speed` and
//! `joint_correction_spin`): pre-stabilization closes drift with real velocity, so closing a
//! large drift at once flings the bodies; bounded, it is closed over a few steps.

use dentbend::glam::{Quat, Vec3};
use dentbend::mesh;
use dentbend_solver::sim::{BodyDesc, ColliderKind, JointKind, World, WorldSettings};

/// Two 10 cm cubes side by side in free space, joined by `kind` at the point between them; then
/// the right one is moved `offset` and turned by `turn`, so the joint starts with that drift.
fn drifted_pair(settings: WorldSettings, kind: JointKind, offset: Vec3, turn: Quat) -> World {
    let mut world = World::new(settings).expect("world");
    let cube = mesh::subdivided_box(Vec3::splat(0.1), [1, 1, 1]).expect("cube");
    let at = |name: &str, x: f32| {
        BodyDesc::new(name, cube.clone()).at(Vec3::new(x, 0.0, 0.0)).collider(ColliderKind::Cuboid)
    };
    let left = world.add(at("left", -0.05)).expect("left");
    let right = world.add(at("right", 0.05)).expect("right");
    world.add_joint(left, right, Vec3::ZERO, kind).expect("joint");
    let body = &mut world.bodies_mut()[right];
    body.position += offset;
    body.orientation = turn * body.orientation;
    world
}

/// Steps `world` `steps` times, checking that `drift` (m or rad) shrinks by at most `allowance`
/// per step; returns the first step after which it is below 1e-3, if any.
fn steps_to_close(world: &mut World, steps: usize, drift: impl Fn(&World) -> f32, allowance: f32) -> Option<usize> {
    let mut before = drift(world);
    let mut closed_at = None;
    for step in 1..=steps {
        world.step();
        let now = drift(world);
        assert!(now >= before - allowance, "step {step}: closed {} at once, more than {allowance}", before - now);
        if now < 1e-3 && closed_at.is_none() {
            closed_at = Some(step);
        }
        before = now;
    }
    closed_at
}

fn free_space() -> WorldSettings {
    WorldSettings { gravity: Vec3::ZERO, angular_damping: 0.0, sleep_time: 0.0, ..Default::default() }
}

/// A ball joint torn 10 cm apart closes by at most `joint_correction_speed`·dt per step (plus
/// 0.1 mm for the linearization), so it takes at least 6 steps at the default 1 m/s; it is
/// closed to 1 mm within 10. With an unbounded speed the same drift closes in the first step.
#[test]
fn a_torn_ball_joint_closes_at_the_correction_speed() {
    let settings = free_space();
    let reach = settings.joint_correction_speed * settings.dt;
    let mut world = drifted_pair(settings, JointKind::Ball, Vec3::new(0.0, 0.1, 0.0), Quat::IDENTITY);
    let gap = |world: &World| world.joints()[0].separation(world.bodies()).expect("gap").length();
    let start = gap(&world);
    assert!((start - 0.1).abs() < 1e-5, "the drift is {start} m, not 10 cm");
    let closed_at = steps_to_close(&mut world, 10, gap, reach + 1e-4).expect("not closed to 1 mm within 10 steps");
    assert!(closed_at >= 6, "closed by step {closed_at}: faster than 1 m/s");

    let unbounded = WorldSettings { joint_correction_speed: 1e6, ..free_space() };
    let mut world = drifted_pair(unbounded, JointKind::Ball, Vec3::new(0.0, 0.1, 0.0), Quat::IDENTITY);
    world.step();
    assert!(gap(&world) < 1e-3, "unbounded: still {} m apart after one step", gap(&world));
}

/// A rigid joint turned 0.5 rad off its target turns back by at most `joint_correction_spin`·dt
/// per step (plus 1 mrad), so at least 9 steps at the default π rad/s, and is back within
/// 1 mrad by step 15. The bodies then turn together: their spins agree within 1 mrad/s, so the
/// correction did not leave them spinning apart.
#[test]
fn a_twisted_rigid_joint_turns_back_at_the_correction_spin() {
    let settings = free_space();
    let turn = settings.joint_correction_spin * settings.dt;
    let twist = Quat::from_rotation_z(0.5);
    let mut world = drifted_pair(settings, JointKind::Rigid, Vec3::ZERO, twist);
    let angle = |world: &World| world.joints()[0].deviation(world.bodies()).expect("deviation").length();
    let start = angle(&world);
    assert!((start - 0.5).abs() < 1e-4, "the twist is {start} rad, not 0.5");
    let back_at = steps_to_close(&mut world, 15, angle, turn + 1e-3).expect("not back within 1 mrad in 15 steps");
    assert!(back_at >= 9, "back by step {back_at}: faster than π rad/s");
    let spins: Vec<Vec3> = world.bodies().iter().map(|b| b.angular_velocity).collect();
    assert!((spins[0] - spins[1]).length() < 1e-3, "the halves spin apart: {spins:?}");
}

/// Correction speeds must be finite and positive.
#[test]
fn bad_correction_speeds_are_refused() {
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        for settings in [
            WorldSettings { joint_correction_speed: bad, ..Default::default() },
            WorldSettings { joint_correction_spin: bad, ..Default::default() },
        ] {
            let error = World::new(settings).expect_err("bad correction speed accepted").to_string();
            assert!(error.contains("joint_correction"), "unclear error: {error}");
        }
    }
}
