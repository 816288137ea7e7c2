//! Breakable bodies in Bevy: a 50 kg ball at 12 m/s dents and breaks a fixed prescored wall
//! (toughness 1 kJ); the wall's mesh and collider become its rest, each piece an entity with a
//! dynamic bevy_rapier3d body carrying the piece's mass, and the ball goes through the hole. A
//! breakable body whose mesh is open is refused with a reason naming the fix. A textured wall's
//! rest and pieces keep its UVs.

use crate::common;
use libtest_mimic::Trial;

use bevy::prelude::*;
use bevy_dentbend::dentbend::fracture::{FractureSettings, PatternParams};
use bevy_dentbend::dentbend::{TriMesh, mesh};
use bevy_dentbend::{DentPiece, DentRefused, DentStats, DentWorld, Dentable, DentbendPlugin, RestoreDamage, bevy_mesh};
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

/// The UV a vertex at `p` of the test walls has: its x and y, 2 UV units a metre.
fn wall_uv(p: Vec3) -> [f32; 2] {
    [2.0 * p.x, 2.0 * p.y]
}

/// The wall's UVs one per vertex of `mesh` (`None` without Float32x2 UVs).
fn uvs_of(mesh: &Mesh) -> Option<Vec<[f32; 2]>> {
    match mesh.attribute(Mesh::ATTRIBUTE_UV_0) {
        Some(bevy::mesh::VertexAttributeValues::Float32x2(uv)) => Some(uv.clone()),
        _ => None,
    }
}

/// Spawns the breakable wall with UVs ([`wall_uv`]); its entity.
fn spawn_textured_wall(app: &mut App) -> Entity {
    let tri = wall_mesh();
    let uvs: Vec<[f32; 2]> = tri.positions().iter().map(|&p| wall_uv(p)).collect();
    let wall = spawn_wall(app, &tri);
    let handle = app.world().get::<Mesh3d>(wall).expect("a mesh").0.clone();
    let mut assets = app.world_mut().resource_mut::<Assets<Mesh>>();
    assets.get_mut(&handle).expect("the asset").insert_attribute(Mesh::ATTRIBUTE_UV_0, uvs);
    wall
}

/// `entity`'s asset.
fn asset_of(app: &App, entity: Entity) -> Mesh {
    let handle = &app.world().get::<Mesh3d>(entity).expect("a mesh").0;
    app.world().resource::<Assets<Mesh>>().get(handle).expect("the asset").clone()
}

/// A textured wall breaks, and its rest and pieces keep UVs: one per vertex of each piece's
/// and of the rest's asset, and the rest's vertices beyond the pattern's reach (farther than
/// 0.8 m from the hit in x or y: a 0.5 m pattern, a dent of a 0.2 m ball) have the UV of their
/// position, within 1e-6 (the cut's planes run across the whole wall, and the vertices they
/// make there interpolate their edge's UVs in f32: a few ulps of UVs up to 3). Its damage, saved and restored onto a fresh textured wall, gives the same asset:
/// the same positions bit for bit and the same UVs within 1e-6 (a refined vertex's midpoint
/// taken from either end).
fn a_broken_wall_keeps_its_uvs() {
    let mut app = app();
    let wall = spawn_textured_wall(&mut app);
    for _ in 0..2 {
        app.update();
    }
    app.world_mut().resource_mut::<DentWorld>().record_damage(wall, "wall").expect("registered");
    let volume = 4.0 / 3.0 * std::f32::consts::PI * 0.2f32.powi(3);
    common::launch_ball(&mut app, Vec3::new(0.2, 1.1, 1.0), 0.2, 50.0 / volume, Vec3::new(0.0, 0.0, -12.0));
    for _ in 0..60 {
        app.update();
    }
    assert_eq!(app.world().resource::<DentStats>().fractures, 1);
    let handle = app.world().get::<Mesh3d>(wall).expect("the wall stays").0.clone();
    let assets = app.world().resource::<Assets<Mesh>>();
    let rest = assets.get(&handle).expect("the rest's asset");
    let rest_uvs = uvs_of(rest).expect("the rest keeps UVs");
    assert_eq!(rest_uvs.len(), rest.count_vertices());
    let Some(bevy::mesh::VertexAttributeValues::Float32x3(positions)) = rest.attribute(Mesh::ATTRIBUTE_POSITION) else {
        panic!("the rest has no positions")
    };
    let mut far = 0;
    for (p, uv) in positions.iter().map(|p| Vec3::from_array(*p)).zip(&rest_uvs) {
        if (p.x - 0.2).abs() > 0.8 || (p.y - 0.1).abs() > 0.8 {
            far += 1;
            let expected = wall_uv(p);
            let off = (uv[0] - expected[0]).abs().max((uv[1] - expected[1]).abs());
            assert!(off <= 1e-6, "a vertex at {p} far from the hole has UV {uv:?}, not {expected:?}");
        }
    }
    assert!(far > 1000, "{far} vertices far from the hole");
    let played = rest.clone();
    let mut q = app.world_mut().query_filtered::<&Mesh3d, With<DentPiece>>();
    let pieces: Vec<Handle<Mesh>> = q.iter(app.world()).map(|m| m.0.clone()).collect();
    assert!(pieces.len() >= 20);
    let assets = app.world().resource::<Assets<Mesh>>();
    for handle in pieces {
        let piece = assets.get(&handle).expect("a piece's asset");
        let uvs = uvs_of(piece).expect("a piece has UVs");
        assert_eq!(uvs.len(), piece.count_vertices());
        assert!(uvs.iter().flatten().all(|c| c.is_finite()));
    }
    let file = app.world().resource::<DentWorld>().damage_file();
    let mut again = self::app();
    let fresh = spawn_textured_wall(&mut again);
    for _ in 0..2 {
        again.update();
    }
    again.world_mut().write_message(RestoreDamage { entity: fresh, damage: file.bodies[0].clone() });
    for _ in 0..3 {
        again.update();
    }
    let restored = asset_of(&again, fresh);
    assert_eq!(restored.attribute(Mesh::ATTRIBUTE_POSITION), played.attribute(Mesh::ATTRIBUTE_POSITION));
    let (a, b) = (uvs_of(&restored).expect("restored UVs"), uvs_of(&played).expect("played UVs"));
    assert_eq!(a.len(), b.len());
    for (v, (x, y)) in a.iter().zip(&b).enumerate() {
        assert!((x[0] - y[0]).abs() < 1e-6 && (x[1] - y[1]).abs() < 1e-6, "vertex {v}: UV {x:?}, in play {y:?}");
    }
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

pub fn tests() -> Vec<Trial> {
    common::headless_trials(
        module_path!(),
        vec![
            ("a_ball_breaks_a_wall_into_bodies", a_ball_breaks_a_wall_into_bodies),
            ("a_broken_wall_keeps_its_uvs", a_broken_wall_keeps_its_uvs),
            ("an_open_breakable_mesh_is_refused", an_open_breakable_mesh_is_refused),
        ],
    )
}
