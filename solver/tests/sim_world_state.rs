//! The world's dummy-step support (paper Algorithm 2): a snapshot restored and stepped again
//! repeats the same steps exactly, and a body rebuilt in place keeps its joints where they were.

use dentbend::glam::{Quat, Vec3};
use dentbend::mesh;
use dentbend_solver::sim::{BodyDesc, BodyKind, ColliderKind, JointKind, MassProperties, World, WorldSettings};

fn block(name: &str, at: Vec3) -> BodyDesc {
    BodyDesc::new(name, mesh::subdivided_box(Vec3::new(1.0, 0.2, 0.2), [1, 1, 1]).unwrap())
        .at(at)
        .collider(ColliderKind::Cuboid)
}

fn hanging_pair() -> World {
    let mut world = World::new(WorldSettings::default()).unwrap();
    let hook = world.add(block("hook", Vec3::new(0.0, 3.0, 0.0)).kind(BodyKind::Static)).unwrap();
    let arm = world.add(block("arm", Vec3::new(1.0, 3.0, 0.0))).unwrap();
    let tip = world.add(block("tip", Vec3::new(2.0, 3.0, 0.0))).unwrap();
    world.add_joint(hook, arm, Vec3::new(0.5, 3.0, 0.0), JointKind::Ball).unwrap();
    world.add_joint(arm, tip, Vec3::new(1.5, 3.0, 0.0), JointKind::Rigid).unwrap();
    world
}

/// Stepping from a restored snapshot is bit-identical to the first time (the state is all
/// there: warm-start impulses and joint targets included).
#[test]
fn a_restored_snapshot_steps_the_same_way_again() {
    let mut world = hanging_pair();
    for _ in 0..20 {
        world.step();
    }
    let saved = world.snapshot();
    let run = |world: &mut World| -> Vec<(Vec3, Quat)> {
        for _ in 0..30 {
            world.step();
        }
        world.bodies().iter().map(|b| (b.position, b.orientation)).collect()
    };
    let first = run(&mut world);
    world.restore(&saved).unwrap();
    assert_eq!(world.steps(), 20);
    assert_eq!(run(&mut world), first);
}

/// A snapshot taken before a body was added cannot be restored.
#[test]
fn a_snapshot_of_another_body_count_is_refused() {
    let mut world = hanging_pair();
    let saved = world.snapshot();
    world.add(block("extra", Vec3::new(5.0, 0.0, 0.0))).unwrap();
    let before = world.bodies()[1].position;
    assert!(world.restore(&saved).is_err());
    assert_eq!(world.bodies()[1].position, before);
}

/// Rebuilding the arm with a different centre of mass (given mass properties, as a bending
/// body's sub-body gets from its voxels) and a turned frame keeps both joints' anchors together
/// in the world (1e-5 m: f32 round-off on metre-sized offsets) and the tip welded.
#[test]
fn a_rebuilt_body_keeps_its_joints_in_place() {
    let mut world = hanging_pair();
    for _ in 0..10 {
        world.step();
    }
    let arm = world.find("arm").unwrap();
    let body = &world.bodies()[arm];
    let model = body.model_transform();
    let turn = Quat::from_rotation_z(0.3);
    let mass = MassProperties { center: Vec3::new(0.1, 0.02, 0.0), ..shape_mass(body) };
    // The same geometry, described in a model frame turned by `turn`.
    let mut mesh = mesh::subdivided_box(Vec3::new(1.0, 0.2, 0.2), [1, 1, 1]).unwrap();
    mesh.transform(dentbend::glam::Affine3A::from_quat(turn.inverse())).unwrap();
    let (_, orientation, origin) = model.to_scale_rotation_translation();
    let desc = BodyDesc::new("arm", mesh)
        .at(origin)
        .with_mass_properties(MassProperties { center: turn.inverse() * mass.center, ..mass });
    let desc = BodyDesc { orientation: orientation * turn, ..desc };
    let deviation = |world: &World| -> Vec<f32> {
        world.joints().iter().map(|j| j.deviation(world.bodies()).unwrap().length()).collect()
    };
    let before = deviation(&world);
    world.rebuild_body(arm, desc).unwrap();
    for (joint, was) in world.joints().iter().zip(before) {
        let separation = joint.separation(world.bodies()).unwrap();
        assert!(separation.length() < 1e-5, "anchors {separation} apart after the rebuild");
        let now = joint.deviation(world.bodies()).unwrap().length();
        assert!((now - was).abs() < 1e-5, "deviation from the target {was} -> {now} rad");
    }
    for _ in 0..30 {
        world.step();
    }
    for joint in world.joints() {
        assert!(joint.separation(world.bodies()).unwrap().length() < 1e-3);
    }
}

fn shape_mass(body: &dentbend_solver::sim::RigidBody) -> MassProperties {
    MassProperties { mass: body.mass, center: Vec3::ZERO, inertia: body.inertia, volume: 0.04 }
}
