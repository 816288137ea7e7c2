//! Restitution against triangle meshes: a ball landing across several triangles of a mesh
//! collider must bounce with e × its closing speed, not more (internal-edge contacts with
//! tilted normals used to add up to 40 % extra bounce).

use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_solver::coupling::Simulation;
use dentbend_solver::sim::{BodyDesc, BodyKind, ColliderKind, DentSettings, SurfaceMaterial, World, WorldSettings};

const GRAVITY: f32 = 9.81;

/// Drops a ball at 7 m/s onto a 4 × 1 × 4 block and returns (closing speed of the first
/// event, the ball's vertical velocity after that step).
fn bounce(block_collider: ColliderKind, ball_collider: ColliderKind, dentable: bool, e: f32) -> (f32, f32) {
    let settings = WorldSettings {
        gravity: Vec3::new(0.0, -GRAVITY, 0.0),
        sleep_time: 0.0,
        angular_damping: 0.0,
        ..Default::default()
    };
    let mut world = World::new(settings).unwrap();
    let surface = SurfaceMaterial { restitution: e, friction: 0.3 };
    let block = mesh::subdivided_box(Vec3::new(4.0, 1.0, 4.0), [16, 4, 16]).unwrap();
    let mut block = BodyDesc::new("block", block).kind(BodyKind::Static).collider(block_collider);
    block.surface = surface;
    if dentable {
        block = block.dentable(DentSettings::new(1.0, 0.02, 0.2));
    }
    world.add(block).unwrap();
    // Off the block's vertex lattice on purpose: the ball lands across several triangles.
    let mut ball = BodyDesc::new("ball", mesh::icosphere(0.3, 3).unwrap())
        .at(Vec3::new(0.07, 1.5, -0.11))
        .velocity(Vec3::new(0.0, -7.0, 0.0))
        .collider(ball_collider);
    ball.surface = surface;
    let ball = world.add(ball).unwrap();
    let mut sim = Simulation::new(world, None).unwrap();
    for _ in 0..40 {
        let (_, report) = sim.step().unwrap();
        if let Some(event) = report.events.first() {
            return (event.normal_speed, sim.world().bodies()[ball].linear_velocity.y);
        }
    }
    panic!("the ball never hit the block");
}

/// After the collision phase the ball leaves at e × v_closing, then gravity takes g·dt off in
/// the same step. 1 % covers f32 round-off and the slight tilt of a dented surface's normal.
#[test]
fn ball_on_a_triangle_mesh_bounces_with_e() {
    let dt = WorldSettings::default().dt;
    for (block, ball, dentable) in [
        (ColliderKind::TriMesh, ColliderKind::Ball, false),
        (ColliderKind::TriMesh, ColliderKind::ConvexHull, false),
        (ColliderKind::TriMesh, ColliderKind::Ball, true),
        (ColliderKind::Cuboid, ColliderKind::Ball, false),
    ] {
        for e in [0.1, 0.5] {
            let (closing, after) = bounce(block, ball, dentable, e);
            let expected = e * closing - GRAVITY * dt;
            assert!(
                (after - expected).abs() < 0.01 * e * closing,
                "{block:?} block, {ball:?} ball, dentable {dentable}, e {e}: left at {after} m/s, expected {expected}"
            );
        }
    }
}

/// Dents refit a triangle-mesh collider in place only while its vertices stay one-to-one with
/// the body's mesh; the internal-edge fix must not merge or drop any of them.
#[test]
fn triangle_mesh_colliders_keep_the_mesh_vertices() {
    let meshes = [
        mesh::subdivided_box(Vec3::new(4.0, 1.0, 4.0), [16, 4, 16]).unwrap(),
        mesh::icosphere(0.5, 3).unwrap(),
        mesh::cylinder(0.5, 2.0, 32, 4).unwrap(),
        mesh::load("bunny").unwrap(),
    ];
    for mesh in meshes {
        let count = mesh.vertex_count();
        let shape = ColliderKind::TriMesh.build_for(BodyKind::Static, &mesh).unwrap();
        let trimesh = shape.as_trimesh().expect("a triangle mesh");
        assert_eq!(trimesh.vertices().len(), count);
        assert!(trimesh.pseudo_normals().is_some(), "internal-edge fix needs pseudo-normals");
    }
}
