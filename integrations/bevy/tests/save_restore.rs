//! Save and restore in Bevy: a recorded block's dents (three balls) go into a damage file; a
//! fresh block spawned undamaged in another app takes the file through `RestoreDamage` and has
//! the same mesh bit for bit, its collider too. Damage saved from another mesh is refused and
//! changes nothing.

mod common;

use std::process::ExitCode;

use bevy::prelude::*;
use bevy_dentbend::dentbend::record::DamageFile;
use bevy_dentbend::dentbend::{TriMesh, mesh};
use bevy_dentbend::{DamageRestored, DentStats, DentWorld, Dentable, DentbendPlugin, RestoreDamage, bevy_mesh};
use bevy_rapier3d::prelude::*;

#[derive(Resource, Default)]
struct Outcomes(Vec<DamageRestored>);

fn collect(mut restored: MessageReader<DamageRestored>, mut out: ResMut<Outcomes>) {
    out.0.extend(restored.read().cloned());
}

fn app() -> App {
    let mut app = common::physics_app(RapierPhysicsPlugin::<NoUserData>::default(), DentbendPlugin::cpu_only());
    app.init_resource::<Outcomes>().add_systems(Last, collect);
    app
}

/// Spawns a fixed dentable block of `tri` and lets it register; its entity.
fn spawn_block(app: &mut App, tri: &TriMesh) -> Entity {
    let collider = Collider::trimesh(tri.positions().to_vec(), tri.faces().to_vec()).expect("a tri-mesh");
    let mesh = app.world_mut().resource_mut::<Assets<Mesh>>().add(bevy_mesh(tri));
    let block = app
        .world_mut()
        .spawn((Mesh3d(mesh), Transform::default(), RigidBody::Fixed, collider, Dentable::new(2.0, 0.01, 0.05)))
        .id();
    for _ in 0..2 {
        app.update();
    }
    block
}

fn block() -> TriMesh {
    mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [16, 4, 16]).expect("a box")
}

/// Three balls dent a recorded block; its damage file and final mesh.
fn dented_and_saved() -> (DamageFile, TriMesh) {
    let mut app = app();
    let block_entity = spawn_block(&mut app, &block());
    app.world_mut().resource_mut::<DentWorld>().record_damage(block_entity, "block").expect("registered");
    for (k, (x, z)) in [(-0.5, 0.3), (0.4, -0.2), (0.1, 0.6)].into_iter().enumerate() {
        let at = Vec3::new(x, 0.6 + 0.3 * k as f32, z);
        common::launch_ball(&mut app, at, 0.1, 2000.0, Vec3::new(0.0, -6.0, 0.0));
    }
    for _ in 0..60 {
        app.update();
    }
    assert_eq!(app.world().resource::<DentStats>().dents, 3, "three dents");
    let world = app.world().resource::<DentWorld>();
    (world.damage_file(), world.mesh(block_entity).expect("the block").clone())
}

fn a_saved_block_restores_bit_for_bit() {
    let (file, dented) = dented_and_saved();
    assert_eq!(file.bodies.len(), 1);
    assert_eq!(file.bodies[0].dents(), 3);
    let mut app = app();
    let fresh = spawn_block(&mut app, &block());
    app.world_mut().write_message(RestoreDamage { entity: fresh, damage: file.bodies[0].clone() });
    for _ in 0..3 {
        app.update();
    }
    let outcomes = &app.world().resource::<Outcomes>().0;
    assert!(matches!(outcomes.as_slice(), [DamageRestored { result: Ok(()), .. }]), "{outcomes:?}");
    assert_eq!(app.world().resource::<DentWorld>().mesh(fresh), Some(&dented), "the same mesh, bit for bit");
    let collider = app.world().get::<Collider>(fresh).expect("a collider");
    assert_eq!(collider.as_trimesh().expect("a tri-mesh").raw.vertices(), dented.positions());
}

fn damage_of_another_mesh_is_refused() {
    let (file, _) = dented_and_saved();
    let mut app = app();
    let other = mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [12, 4, 12]).expect("a box");
    let fresh = spawn_block(&mut app, &other);
    app.world_mut().write_message(RestoreDamage { entity: fresh, damage: file.bodies[0].clone() });
    for _ in 0..3 {
        app.update();
    }
    let outcomes = &app.world().resource::<Outcomes>().0;
    assert!(matches!(outcomes.as_slice(), [DamageRestored { result: Err(_), .. }]), "{outcomes:?}");
    assert_eq!(app.world().resource::<DentWorld>().mesh(fresh), Some(&other), "unchanged");
}

fn main() -> ExitCode {
    common::run_headless(vec![
        ("a_saved_block_restores_bit_for_bit", a_saved_block_restores_bit_for_bit),
        ("damage_of_another_mesh_is_refused", damage_of_another_mesh_is_refused),
    ])
}
