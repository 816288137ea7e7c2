//! Colliders the adapter cannot serve correctly are refused at `Dentables::insert`, each with a
//! message that names the fix, and nothing is registered: a convex collider on a fixed body,
//! primitives and compounds, a collider built from another or a scaled mesh, a dented mesh
//! given back instead of restored.

use dentbend::mesh::{self, TriMesh};
use dentbend_rapier::demo::rain::target_dent;
use dentbend_rapier::rapier3d::prelude::{ColliderBuilder, ColliderHandle, RigidBodyBuilder};
use dentbend_rapier::{AdapterError, Dentables, PhysicsWorld, convex_collider, trimesh_collider};
use glam::Vec3;

fn refused(world: &PhysicsWorld, handle: ColliderHandle, mesh: TriMesh, needle: &str) {
    let mut dentables = Dentables::new();
    let err = dentables.insert(&world.colliders, &world.bodies, handle, mesh, target_dent()).unwrap_err();
    assert!(matches!(err, AdapterError::Refit { .. }), "{err}");
    assert!(err.to_string().contains(needle), "{err} does not name {needle:?}");
    assert!(!dentables.is_dentable(handle));
}

#[test]
fn a_convex_collider_on_a_fixed_body_is_refused_naming_trimesh_collider() {
    let mut world = PhysicsWorld::new(Vec3::ZERO, 1.0 / 60.0);
    let block = mesh::subdivided_box(Vec3::new(1.0, 0.5, 1.0), [4, 2, 4]).unwrap();
    let fixed = world.bodies.insert(RigidBodyBuilder::fixed());
    let c = world.colliders.insert_with_parent(convex_collider(&block).unwrap(), fixed, &mut world.bodies);
    refused(&world, c, block.clone(), "trimesh_collider(&mesh)");
    // Without a body it is fixed too.
    let c = world.colliders.insert(convex_collider(&block).unwrap());
    refused(&world, c, block.clone(), "trimesh_collider(&mesh)");
    // On a dynamic body it is accepted.
    let body = world.bodies.insert(RigidBodyBuilder::dynamic());
    let c = world.colliders.insert_with_parent(convex_collider(&block).unwrap(), body, &mut world.bodies);
    Dentables::new().insert(&world.colliders, &world.bodies, c, block, target_dent()).unwrap();
}

#[test]
fn primitive_and_compound_shapes_are_refused_naming_the_shape_and_the_fix() {
    let mut world = PhysicsWorld::new(Vec3::ZERO, 1.0 / 60.0);
    let body = world.bodies.insert(RigidBodyBuilder::dynamic());
    let ball = mesh::icosphere(0.5, 2).unwrap();
    let c = world.colliders.insert_with_parent(ColliderBuilder::ball(0.5), body, &mut world.bodies);
    refused(&world, c, ball.clone(), "Ball");
    refused(&world, c, ball.clone(), "convex_collider(&mesh)");
    let c = world.colliders.insert_with_parent(ColliderBuilder::cuboid(0.5, 0.5, 0.5), body, &mut world.bodies);
    refused(&world, c, ball.clone(), "Cuboid");
    let parts = vec![
        (dentbend_rapier::rapier3d::math::Pose::IDENTITY, dentbend_rapier::rapier3d::prelude::SharedShape::ball(0.2)),
        (
            dentbend_rapier::rapier3d::math::Pose::translation(0.5, 0.0, 0.0),
            dentbend_rapier::rapier3d::prelude::SharedShape::ball(0.2),
        ),
    ];
    let c = world.colliders.insert_with_parent(ColliderBuilder::compound(parts), body, &mut world.bodies);
    refused(&world, c, ball, "a collider of its own");
}

#[test]
fn a_collider_built_from_another_or_a_scaled_mesh_is_refused() {
    let mut world = PhysicsWorld::new(Vec3::ZERO, 1.0 / 60.0);
    let fixed = world.bodies.insert(RigidBodyBuilder::fixed());
    let block = mesh::subdivided_box(Vec3::new(1.0, 0.5, 1.0), [4, 2, 4]).unwrap();
    let mut scaled = block.clone();
    scaled.transform(glam::Affine3A::from_scale(Vec3::splat(1.5))).unwrap();
    // The collider is the scaled mesh; the mesh given is the unscaled one.
    let c = world.colliders.insert_with_parent(trimesh_collider(&scaled).unwrap(), fixed, &mut world.bodies);
    refused(&world, c, block.clone(), "trimesh_collider(&mesh)");
    // A dented mesh given back to an undented collider (a save restored by hand).
    let mut dented = block.clone();
    let mut positions = dented.positions().to_vec();
    positions[5].y -= 0.05;
    dented = TriMesh::new(positions, dented.faces().to_vec()).unwrap();
    let c = world.colliders.insert_with_parent(trimesh_collider(&block).unwrap(), fixed, &mut world.bodies);
    refused(&world, c, dented, "Dentables::restore");
    // A dynamic hull of the scaled mesh.
    let body = world.bodies.insert(RigidBodyBuilder::dynamic());
    let c = world.colliders.insert_with_parent(convex_collider(&scaled).unwrap(), body, &mut world.bodies);
    refused(&world, c, block, "convex_collider(&mesh)");
}
