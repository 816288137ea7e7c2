//! The scene two of the adapter's tests share: a fixed 2 × 0.5 × 2 m block and a 0.1 m ball
//! just above its top face falling onto it at 6 m/s, with the head-on contact between them.

use dentbend::mesh::{self, TriMesh};
use dentbend_rapier::rapier3d::prelude::{ColliderHandle, RigidBodyBuilder};
use dentbend_rapier::{Contact, PhysicsWorld, convex_collider, trimesh_collider};
use glam::Vec3;

/// The world, the block's collider and mesh, the ball's collider and mesh; the ball's centre at
/// `height` m, gravity `gravity` m/s².
pub fn block_and_ball(
    gravity: Vec3,
    height: f32,
) -> (PhysicsWorld, (ColliderHandle, TriMesh), (ColliderHandle, TriMesh)) {
    let mut world = PhysicsWorld::new(gravity, 1.0 / 60.0);
    let block_mesh = mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [16, 4, 16]).unwrap();
    let fixed = world.bodies.insert(RigidBodyBuilder::fixed());
    let block = world.colliders.insert_with_parent(trimesh_collider(&block_mesh).unwrap(), fixed, &mut world.bodies);
    let ball_mesh = mesh::icosphere(0.1, 2).unwrap();
    let falling =
        RigidBodyBuilder::dynamic().translation(Vec3::new(0.0, height, 0.0)).linvel(Vec3::new(0.0, -6.0, 0.0));
    let body = world.bodies.insert(falling);
    let ball = world.colliders.insert_with_parent(convex_collider(&ball_mesh).unwrap(), body, &mut world.bodies);
    (world, (block, block_mesh), (ball, ball_mesh))
}

/// The ball's contact with the block's top face (normal from block to ball); `started` on the
/// impact's step.
pub fn top_contact(block: ColliderHandle, ball: ColliderHandle, started: bool) -> Contact {
    Contact {
        collider1: block,
        collider2: ball,
        point: Vec3::new(0.0, 0.25, 0.0),
        normal: Vec3::Y,
        impulse: 1.0,
        started,
    }
}
