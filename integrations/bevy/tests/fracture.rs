//! Breakable bodies in Bevy: a 50 kg ball at 12 m/s dents and breaks a fixed prescored wall
//! (toughness 1 kJ); the wall's mesh and collider become its rest, each piece an entity with a
//! dynamic bevy_rapier3d body carrying the piece's mass, and the ball goes through the hole. A
//! breakable body whose mesh is open is refused with a reason naming the fix.

mod common;

use std::process::ExitCode;

use bevy::prelude::*;
use bevy_dentbend::dentbend::fracture::{FractureSettings, PatternParams};
use bevy_dentbend::dentbend::{TriMesh, mesh};
use bevy_dentbend::{DentPiece, DentRefused, DentStats, DentWorld, Dentable, DentbendPlugin, bevy_mesh};
use bevy_rapier3d::prelude::*;

/// The wall: 3 × 2 × 0.2 m, 60 × 40 × 2 cells, standing on y = 0 (front face at z = 0.1).
fn wall_mesh() -> TriMesh {
    mesh::subdivided_box(Vec3::new(3.0, 2.0, 0.2), [60, 40, 2]).expect("a box")
}

/// An app with Rapier and the plug-in (CPU path), 1/60 s a frame, no gravity.
fn app() -> App {
    let mut app = common::physics_app(RapierPhysicsPlugin::<NoUserData>::default(), DentbendPlugin::cpu_only());
    let mut q = app.world_mut().query::<&mut RapierConfiguration>();
    for mut config in q.iter_mut(app.world_mut()) {
        config.gravity = Vec3::ZERO;
    }
    app
}

/// Spawns the breakable wall made of `tri`; its entity.
fn spawn_wall(app: &mut App, tri: &TriMesh) -> Entity {
    let pattern = PatternParams { cells: 40, seed: 3, radius: 0.5 };
    let mut fracture = FractureSettings::new(pattern, Some(1000.0), None).expect("settings");
    fracture.density = 300.0;
    let collider = Collider::trimesh(tri.positions().to_vec(), tri.faces().to_vec()).expect("a tri-mesh");
    let mesh = app.world_mut().resource_mut::<Assets<Mesh>>().add(bevy_mesh(tri));
    let dentable = Dentable::new(2.0, 0.002, 0.03).breaking(fracture);
    app.world_mut().spawn((Mesh3d(mesh), Transform::from_xyz(0.0, 1.0, 0.0), RigidBody::Fixed, collider, dentable)).id()
}

fn a_ball_breaks_a_wall_into_bodies() {
    let mut app = app();
    let wall = spawn_wall(&mut app, &wall_mesh());
    // 50 kg at 12 m/s: 3.6 kJ against the wall's 1 kJ toughness.
    let volume = 4.0 / 3.0 * std::f32::consts::PI * 0.2f32.powi(3);
    let ball = common::launch_ball(&mut app, Vec3::new(0.2, 1.1, 1.0), 0.2, 50.0 / volume, Vec3::new(0.0, 0.0, -12.0));
    for _ in 0..60 {
        app.update();
    }
    let stats = app.world().resource::<DentStats>().clone();
    assert_eq!(stats.fractures, 1, "{stats:?}");
    assert!(stats.pieces >= 20, "{stats:?}");
    let mut q = app.world_mut().query::<(&DentPiece, &RigidBody, &Collider, &ReadMassProperties)>();
    let pieces: Vec<_> = q.iter(app.world()).collect();
    assert_eq!(pieces.len() as u64, stats.pieces, "every piece became a body");
    for (piece, body, collider, mass) in &pieces {
        assert_eq!(piece.from, wall);
        assert_eq!(**body, RigidBody::Dynamic);
        assert!(collider.as_convex_polyhedron().is_some());
        let expected = piece.mass.mass;
        assert!((mass.mass - expected).abs() < 1e-3 * expected, "mass {} against the piece's {expected}", mass.mass);
    }
    // The wall's mesh is its rest, and its collider has the rest's vertices.
    let rest = app.world().resource::<DentWorld>().mesh(wall).expect("the wall stays").clone();
    assert!(rest.volume().abs() < 0.2 * 2.0 * 3.0 - 0.1, "the rest lost the pattern's prism");
    let collider = app.world().get::<Collider>(wall).expect("a collider");
    assert_eq!(collider.as_trimesh().expect("a tri-mesh").raw.vertices().len(), rest.vertex_count());
    let z = app.world().get::<Transform>(ball).expect("the ball").translation.z;
    assert!(z < -0.3, "the ball at z = {z} did not go through");
}

fn an_open_breakable_mesh_is_refused() {
    let mut app = app();
    let whole = wall_mesh();
    let open = TriMesh::new(whole.positions().to_vec(), whole.faces()[1..].to_vec()).expect("a mesh");
    let wall = spawn_wall(&mut app, &open);
    for _ in 0..3 {
        app.update();
    }
    let why = app.world().get::<DentRefused>(wall).map(|r| r.0.clone()).expect("refused");
    assert!(why.contains("cannot break") && why.contains("closed mesh"), "{why}");
    assert!(app.world().resource::<DentWorld>().mesh(wall).is_none());
}

fn main() -> ExitCode {
    common::run_headless(vec![
        ("a_ball_breaks_a_wall_into_bodies", a_ball_breaks_a_wall_into_bodies),
        ("an_open_breakable_mesh_is_refused", an_open_breakable_mesh_is_refused),
    ])
}
