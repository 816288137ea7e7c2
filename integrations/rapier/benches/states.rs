//! What recording the bodies' states before a step costs in a world of 5,000 fixed bodies
//! (static level geometry, each a small box collider) and 100 dynamic balls.
//!
//! `cargo bench -p dentbend-rapier --bench states`

use criterion::{Criterion, criterion_group, criterion_main};
use dentbend_rapier::rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};
use dentbend_rapier::{BodyStates, PhysicsWorld};
use glam::Vec3;

fn world(fixed: usize, dynamic: usize) -> PhysicsWorld {
    let mut world = PhysicsWorld::new(Vec3::new(0.0, -9.81, 0.0), 1.0 / 60.0);
    for k in 0..fixed {
        let at = Vec3::new((k % 100) as f32 * 2.0, 0.0, (k / 100) as f32 * 2.0);
        let body = world.bodies.insert(RigidBodyBuilder::fixed().translation(at));
        world.colliders.insert_with_parent(ColliderBuilder::cuboid(0.5, 0.5, 0.5), body, &mut world.bodies);
    }
    for k in 0..dynamic {
        let at = Vec3::new((k % 10) as f32 * 2.0, 3.0, (k / 10) as f32 * 2.0);
        let body = world.bodies.insert(RigidBodyBuilder::dynamic().translation(at));
        world.colliders.insert_with_parent(ColliderBuilder::ball(0.2), body, &mut world.bodies);
    }
    world
}

fn states(c: &mut Criterion) {
    let w = world(5000, 100);
    c.bench_function("record_5000_fixed_100_dynamic", |b| {
        b.iter(|| BodyStates::record(std::hint::black_box(&w.bodies), &w.colliders))
    });
}

criterion_group!(benches, states);
criterion_main!(benches);
