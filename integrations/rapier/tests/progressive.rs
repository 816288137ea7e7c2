//! A push that goes on after the impact: only progressive targets dent again, deepening one
//! dent from the pre-dent surface (paper Figure 3); ordinary targets dent once per impact.

use dentbend::dent::{CpuBackend, DentSettings};
use dentbend::mesh;
use dentbend_rapier::rapier3d::prelude::RigidBodyBuilder;
use dentbend_rapier::{BodyStates, Contact, Dentables, PhysicsWorld, convex_collider, trimesh_collider};
use glam::Vec3;

/// Dent distances made by the two steps of a push at 6 m/s on a block denting with
/// `settings`: the impact's step (`started`), then a step of the same push.
fn push_twice(settings: DentSettings) -> (Vec<f32>, Vec<f32>) {
    let mut world = PhysicsWorld::new(Vec3::ZERO, 1.0 / 60.0);
    let block_mesh = mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [16, 4, 16]).unwrap();
    let fixed = world.bodies.insert(RigidBodyBuilder::fixed());
    let block = world.colliders.insert_with_parent(trimesh_collider(&block_mesh).unwrap(), fixed, &mut world.bodies);
    let ball_mesh = mesh::icosphere(0.1, 2).unwrap();
    let body = world
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vec3::new(0.0, 0.35, 0.0)).linvel(Vec3::new(0.0, -6.0, 0.0)));
    let ball = world.colliders.insert_with_parent(convex_collider(&ball_mesh).unwrap(), body, &mut world.bodies);
    let mut dentables = Dentables::new();
    dentables.insert(&world.colliders, block, block_mesh, settings).unwrap();
    dentables.insert_projectile(&world.colliders, ball, ball_mesh).unwrap();
    let states = BodyStates::record(&world.bodies, &world.colliders);
    let contact = |started| Contact {
        collider1: block,
        collider2: ball,
        point: Vec3::new(0.0, 0.25, 0.0),
        normal: Vec3::Y,
        impulse: 1.0,
        started,
    };
    let mut step = |started| {
        let r = dentables
            .process(&[contact(started)], &states, &mut world.bodies, &mut world.colliders, &mut CpuBackend)
            .unwrap();
        r.dents.iter().map(|d| d.dent_distance).collect::<Vec<f32>>()
    };
    (step(true), step(false))
}

#[test]
fn only_progressive_targets_dent_again_while_the_push_goes_on() {
    // 2 m/s threshold, 5 mm per m/s: 2 cm per step at 6 m/s, at most 5 cm.
    let plain = DentSettings::new(2.0, 0.005, 0.05);
    let (first, second) = push_twice(plain.clone());
    assert_eq!((first.len(), second.len()), (1, 0), "{first:?} {second:?}");
    assert!((first[0] - 0.02).abs() < 1e-6);

    let progressive = DentSettings { progressive: true, ..plain };
    let (first, second) = push_twice(progressive);
    assert_eq!((first.len(), second.len()), (1, 1), "{first:?} {second:?}");
    // The second step deepens the same dent: the accumulated distance, 2 + 2 cm.
    assert!((first[0] - 0.02).abs() < 1e-6 && (second[0] - 0.04).abs() < 1e-6, "{first:?} {second:?}");
}
