//! `rapier_wall` (paper Figure 3 in Rapier): a ball breaks a prescored wall through the damage
//! API's fracture. The wall breaks once, at the hit; every piece becomes a dynamic body with the
//! piece's mass; the wall's collider becomes its rest (a ray through the hole's centre misses
//! it); the ball carries on through the hole, pushing pieces ahead.

use dentbend_rapier::demo::wall::{PATTERN, WALL_SIZE, Wall};
use dentbend_rapier::rapier3d::parry::query::Ray;
use glam::Vec3;

/// Steps of 1/60 s, as the example runs.
const STEPS: usize = 90;

#[test]
fn a_ball_breaks_the_wall_into_bodies_and_goes_through_the_hole() {
    let mut wall = Wall::new().unwrap();
    let mut pieces = Vec::new();
    let mut fractures = 0;
    let mut hit_point = None;
    for _ in 0..STEPS {
        let report = wall.step().unwrap();
        for broken in &report.fractures {
            fractures += 1;
            assert_eq!(broken.collider, wall.wall);
            assert!(!broken.whole, "a 0.5 m pattern leaves most of a 3 m wall");
            pieces.extend(broken.pieces.iter().copied());
            hit_point = report.contacts.iter().map(|c| c.point).next();
        }
    }
    assert_eq!(fractures, 1);
    assert!(pieces.len() >= 20, "{} pieces from a 40-cell pattern", pieces.len());
    for p in &pieces {
        let body = &wall.world.bodies[p.body];
        assert!(body.is_dynamic());
        assert!(body.mass() > 0.0 && body.mass() < 300.0 * 0.2 * 0.8, "piece mass {} kg", body.mass());
        assert!(wall.world.colliders.contains(p.collider));
    }
    // The rest lost the pattern's 16-gon prism (inradius R, through the 0.2 m wall): 0.2 · 16 ·
    // tan(π/16) · R², within 1 % (the dent before the break moved a little volume).
    let r = PATTERN.radius;
    let hole = WALL_SIZE.z * 16.0 * (std::f32::consts::PI / 16.0).tan() * r * r;
    let rest = wall.wall_mesh().unwrap().volume().abs();
    let expected = WALL_SIZE.x * WALL_SIZE.y * WALL_SIZE.z - hole;
    assert!((rest - expected).abs() < 0.01 * expected, "rest volume {rest} m³, expected {expected}");
    // The collider is the rest: a ray along the hit's normal through the hole misses it.
    let collider = &wall.world.colliders[wall.wall];
    let point = hit_point.expect("the breaking step's contacts");
    let ray = Ray::new(point + Vec3::Z, -Vec3::Z);
    let toi = collider.shape().cast_ray(collider.position(), &ray, 2.0, true);
    assert!(toi.is_none(), "the ray through the hole hits the wall's collider at {toi:?}");
    // The ball went through; so did pieces it pushed.
    let ball = &wall.world.bodies[wall.ball];
    assert!(ball.translation().z < -0.5, "ball at z = {}", ball.translation().z);
    let through = pieces.iter().filter(|p| wall.world.bodies[p.body].center_of_mass().z < -0.1).count();
    assert!(through >= 5, "{through} pieces went through");
}

/// The broken wall's recorded damage restores on a fresh wall: its mesh is the rest bit for
/// bit, and its collider has the hole.
#[test]
fn a_broken_wall_restores_from_its_damage_file() {
    let mut wall = Wall::new().unwrap();
    wall.adapter.dentables.record_damage(wall.wall, "wall").unwrap();
    let mut point = None;
    for _ in 0..20 {
        let report = wall.step().unwrap();
        if !report.fractures.is_empty() {
            point = report.contacts.first().map(|c| c.point);
        }
    }
    let point = point.expect("the wall broke");
    let file = wall.adapter.dentables.damage_file();
    let mut fresh = Wall::new().unwrap();
    let moved = fresh.adapter.dentables.restore(&mut fresh.world.colliders, fresh.wall, &file.bodies[0]).unwrap();
    assert!(!moved.is_empty());
    assert_eq!(fresh.wall_mesh(), wall.wall_mesh());
    let collider = &fresh.world.colliders[fresh.wall];
    let ray = Ray::new(point + Vec3::Z, -Vec3::Z);
    assert!(collider.shape().cast_ray(collider.position(), &ray, 2.0, true).is_none());
}

/// A wall whose mesh is open cannot be made breakable: the error names the collider and the
/// open edge, and the wall stays dentable and unbreakable.
#[test]
fn an_open_mesh_cannot_break() {
    use dentbend::dent::DentSettings;
    use dentbend::fracture::FractureSettings;
    use dentbend::mesh::{TriMesh, subdivided_box};
    use dentbend_rapier::rapier3d::prelude::RigidBodyBuilder;
    use dentbend_rapier::{AdapterError, PhysicsWorld, dentbend, trimesh_collider};
    let whole = subdivided_box(WALL_SIZE, [6, 4, 1]).unwrap();
    let open = TriMesh::new(whole.positions().to_vec(), whole.faces()[1..].to_vec()).unwrap();
    let mut world = PhysicsWorld::new(Vec3::ZERO, 1.0 / 60.0);
    let body = world.bodies.insert(RigidBodyBuilder::fixed());
    let collider = world.colliders.insert_with_parent(trimesh_collider(&open).unwrap(), body, &mut world.bodies);
    let mut dentables = dentbend_rapier::Dentables::new();
    dentables.insert(&world.colliders, &world.bodies, collider, open, DentSettings::new(1.0, 0.01, 0.05)).unwrap();
    let settings = FractureSettings::new(PATTERN, Some(10.0), None).unwrap();
    let error = dentables.set_fracture(collider, Some(settings)).unwrap_err();
    assert!(matches!(error, AdapterError::Fracture { error: dentbend::fracture::FractureError::OpenMesh { .. }, .. }));
    assert!(error.to_string().contains("not closed"), "{error}");
}
