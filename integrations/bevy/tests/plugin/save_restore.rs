//! Save and restore in Bevy: a recorded block's dents (three balls) go into a damage file; a
//! fresh block spawned undamaged in another app takes the file through `RestoreDamage` and has
//! the same mesh bit for bit, its collider too, and its asset the UVs the played one has
//! (the vertices the dents' refinement added included). Damage saved from another mesh is
//! refused and changes nothing.

use crate::common;
use libtest_mimic::Trial;

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

/// Spawns a fixed dentable block of `tri`, textured (UVs: x and z, 2 a metre), and lets it
/// register; its entity.
fn spawn_block(app: &mut App, tri: &TriMesh) -> Entity {
    let collider = Collider::trimesh(tri.positions().to_vec(), tri.faces().to_vec()).expect("a tri-mesh");
    let uvs: Vec<[f32; 2]> = tri.positions().iter().map(|p| [2.0 * p.x, 2.0 * p.z]).collect();
    let textured = bevy_mesh(tri).with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, uvs);
    let mesh = app.world_mut().resource_mut::<Assets<Mesh>>().add(textured);
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

/// The UVs of `entity`'s asset.
fn uvs(app: &App, entity: Entity) -> Vec<[f32; 2]> {
    let handle = &app.world().get::<Mesh3d>(entity).expect("a mesh").0;
    match app.world().resource::<Assets<Mesh>>().get(handle).and_then(|m| m.attribute(Mesh::ATTRIBUTE_UV_0)) {
        Some(bevy::mesh::VertexAttributeValues::Float32x2(uv)) => uv.clone(),
        other => panic!("no Float32x2 UVs: {other:?}"),
    }
}

/// A block of 0.5 m cells, which the dents refine.
fn coarse_block() -> TriMesh {
    mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [4, 1, 4]).expect("a box")
}

/// Three balls dent a recorded block of `tri`; its damage file, final mesh and asset UVs.
fn dented_and_saved(tri: &TriMesh) -> (DamageFile, TriMesh, Vec<[f32; 2]>) {
    let mut app = app();
    let block_entity = spawn_block(&mut app, tri);
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
    let (file, mesh) = (world.damage_file(), world.mesh(block_entity).expect("the block").clone());
    (file, mesh, uvs(&app, block_entity))
}

fn a_saved_block_restores_bit_for_bit() {
    restores_bit_for_bit(&block());
}

/// As [`a_saved_block_restores_bit_for_bit`] on a block the dents refine: the restored asset
/// has the played one's vertices, and their UVs.
fn a_refined_block_restores_its_uvs() {
    let (_, dented, _) = restores_bit_for_bit(&coarse_block());
    assert!(dented.vertex_count() > coarse_block().vertex_count(), "the dents refined the block");
}

/// Dents a recorded block of `tri`, restores its damage file onto a fresh one and checks the
/// mesh, the collider and the asset's UVs; what the first block had.
fn restores_bit_for_bit(tri: &TriMesh) -> (DamageFile, TriMesh, Vec<[f32; 2]>) {
    let (file, dented, played_uvs) = dented_and_saved(tri);
    assert_eq!(file.bodies.len(), 1);
    assert_eq!(file.bodies[0].dents(), 3);
    let mut app = app();
    let fresh = spawn_block(&mut app, tri);
    app.world_mut().write_message(RestoreDamage { entity: fresh, damage: file.bodies[0].clone() });
    for _ in 0..3 {
        app.update();
    }
    let outcomes = &app.world().resource::<Outcomes>().0;
    assert!(matches!(outcomes.as_slice(), [DamageRestored { result: Ok(()), .. }]), "{outcomes:?}");
    assert_eq!(app.world().resource::<DentWorld>().mesh(fresh), Some(&dented), "the same mesh, bit for bit");
    let collider = app.world().get::<Collider>(fresh).expect("a collider");
    assert_eq!(collider.as_trimesh().expect("a tri-mesh").raw.vertices(), dented.positions());
    // A new vertex's UV is its edge's midpoint's: the same as in play, within f32 rounding of
    // a midpoint taken from either end (1e-6 UV units).
    let restored_uvs = uvs(&app, fresh);
    assert_eq!(restored_uvs.len(), played_uvs.len());
    for (v, (a, b)) in restored_uvs.iter().zip(&played_uvs).enumerate() {
        assert!((a[0] - b[0]).abs() < 1e-6 && (a[1] - b[1]).abs() < 1e-6, "vertex {v}: UV {a:?}, in play {b:?}");
    }
    (file, dented, played_uvs)
}

fn damage_of_another_mesh_is_refused() {
    let (file, ..) = dented_and_saved(&block());
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

pub fn tests() -> Vec<Trial> {
    common::headless_trials(
        module_path!(),
        vec![
            ("a_saved_block_restores_bit_for_bit", a_saved_block_restores_bit_for_bit),
            ("a_refined_block_restores_its_uvs", a_refined_block_restores_its_uvs),
            ("damage_of_another_mesh_is_refused", damage_of_another_mesh_is_refused),
        ],
    )
}
