//! Capsule colliders fitted to a mesh (`ColliderKind::Capsule`): a rigid rod and a bending
//! strut rest on the ground at their radius, a strut's split halves get capsules fitted to their
//! own parts, and a bending body refuses colliders that cannot be fitted to a part.

use dentbend::bend::JointRule;
use dentbend::bend::WeightParams;
use dentbend::glam::{Quat, Vec3};
use dentbend::mesh::{self, TriMesh};
use dentbend_solver::coupling::Simulation;
use dentbend_solver::coupling::{BendableDesc, Bending, DynamicArticulation, SkeletonSpec};
use dentbend_solver::sim::{BodyDesc, BodyKind, ColliderKind, JointKind, World, WorldSettings};

/// The tetrahedra's strut: radius 0.025 m, 0.48 m long, along its model y axis.
const RADIUS: f32 = 0.025;
const LENGTH: f32 = 0.48;

fn strut_mesh() -> TriMesh {
    mesh::cylinder(RADIUS, LENGTH, 8, 8).unwrap()
}

/// A world with gravity and a static 4 × 0.2 × 4 m ground whose top is at y = 0.
fn grounded_world() -> World {
    let mut world = World::new(WorldSettings::default()).unwrap();
    let ground = mesh::subdivided_box(Vec3::new(4.0, 0.2, 4.0), [1, 1, 1]).unwrap();
    let desc = BodyDesc::new("ground", ground).kind(BodyKind::Static).at(Vec3::new(0.0, -0.1, 0.0));
    world.add(desc.collider(ColliderKind::Cuboid)).unwrap();
    world
}

/// A strut bending body lying along x at height `height` (m), capsule colliders.
fn strut(height: f32) -> BendableDesc {
    let mut desc = BendableDesc::new("strut", strut_mesh());
    desc.position = Vec3::new(0.0, height, 0.0);
    desc.orientation = Quat::from_rotation_z(-std::f32::consts::FRAC_PI_2);
    desc.collider = ColliderKind::Capsule;
    desc.skeleton = SkeletonSpec::Auto { bones: 1 };
    desc.weights = WeightParams { resolution: 32, ..WeightParams::default() };
    desc
}

/// The world segment (a, b) and radius of body `index`'s capsule collider.
fn world_capsule(world: &World, index: usize) -> (Vec3, Vec3, f32) {
    let body = &world.bodies()[index];
    let capsule = body.shape().as_capsule().unwrap_or_else(|| panic!("{} has no capsule", body.name));
    let to_world = body.transform();
    (to_world.transform_point3(capsule.segment.a), to_world.transform_point3(capsule.segment.b), capsule.radius)
}

/// Dropped 5 cm flat onto the ground, a capsule rod comes to rest lying on it: its axis at its
/// radius above the ground and level. Tolerances: 1 mm in height (the contact solver's
/// speculative margin leaves sub-millimetre gaps or overlaps at rest) and 1 mm of height
/// difference between the ends (a level rod; a tilt would lift one tip by centimetres).
#[test]
fn a_capsule_rod_and_a_capsule_strut_rest_on_the_ground_at_their_radius() {
    let mut world = grounded_world();
    let lying = Quat::from_rotation_z(-std::f32::consts::FRAC_PI_2);
    let rod = BodyDesc::new("rod", strut_mesh()).at(Vec3::new(0.0, RADIUS + 0.05, 1.0)).collider(ColliderKind::Capsule);
    let rod = world.add(BodyDesc { orientation: lying, density: 1500.0, ..rod }).unwrap();
    let mut bending = Bending::new();
    let index = bending.add(&mut world, strut(RADIUS + 0.05)).unwrap();
    let strut_body = bending.bodies()[index].body_indices()[0];
    let mut sim = Simulation::new(world, None).unwrap().with_bending(bending);
    for _ in 0..120 {
        sim.step().unwrap();
    }
    for body in [rod, strut_body] {
        let (a, b, radius) = world_capsule(sim.world(), body);
        let name = &sim.world().bodies()[body].name;
        assert!((radius - RADIUS).abs() < 1e-5, "{name}: radius {radius}");
        for end in [a, b] {
            assert!((end.y - RADIUS).abs() < 1e-3, "{name}: capsule end {end} not resting at {RADIUS} m");
        }
        assert!((a.y - b.y).abs() < 1e-3, "{name}: not level, ends {a} and {b}");
        // The segment spans the rod less one radius at each end: its tips are the rod's ends.
        let span = a.distance(b) + 2.0 * radius;
        assert!((span - LENGTH).abs() < 1e-4, "{name}: capsule spans {span} m, rod {LENGTH} m");
    }
}

/// A ball hits a free capsule strut at 8 m/s, 6 cm off its middle: the strut splits there, and
/// each half collides as a capsule fitted to its own part, with the strut's radius, on the
/// strut's axis, the two spanning the strut between them. Tolerances: the halves' parts are
/// whole triangles, so where they meet they overlap or leave a gap of at most one band of the
/// cylinder (0.48 / 8 = 0.06 m); each half's capsule lies along its own part of the strut's
/// axis within 0.5° (a half's vertices are rings about that axis, so the fit is exact up to f32
/// round-off).
#[test]
fn a_split_strut_collides_as_two_capsules_fitted_to_its_halves() {
    let mut world = World::new(WorldSettings { gravity: Vec3::ZERO, ..WorldSettings::default() }).unwrap();
    let plastic =
        JointKind::Bend(JointRule::Plastic { strength: 1.0, damping_constant: 1.0, damping_proportional: 6.0 });
    let mut desc = strut(0.0);
    desc.density = 1500.0;
    desc.dynamic = Some(DynamicArticulation { max_joints: 1, ..DynamicArticulation::new(3.0, plastic, 0.1) });
    let mut bending = Bending::new();
    bending.add(&mut world, desc).unwrap();
    let ball = BodyDesc::new("ball", mesh::icosphere(0.07, 2).unwrap())
        .at(Vec3::new(0.06, 0.2, 0.0))
        .velocity(Vec3::new(0.0, -8.0, 0.0))
        .collider(ColliderKind::Ball);
    world.add(BodyDesc { density: 1500.0, ..ball }).unwrap();
    let mut sim = Simulation::new(world, None).unwrap().with_bending(bending);
    for _ in 0..30 {
        sim.step().unwrap();
        if !sim.bending().joints().is_empty() {
            break;
        }
    }
    assert_eq!(sim.bending().joints().len(), 1, "the strut did not split");
    let halves = sim.bending().find("strut").unwrap().body_indices().to_vec();
    assert_eq!(halves.len(), 2);
    let mut span = 0.0;
    for &half in &halves {
        let (a, b, radius) = world_capsule(sim.world(), half);
        assert!((radius - RADIUS).abs() < 1e-4, "half {half}: radius {radius}");
        let axis = (b - a).normalize();
        let strut_axis = sim.world().bodies()[half].model_transform().transform_vector3(Vec3::Y).normalize();
        let off_axis = axis.dot(strut_axis).abs().clamp(0.0, 1.0).acos().to_degrees();
        assert!(off_axis < 0.5, "half {half}: capsule axis {axis} is {off_axis}° off the strut's {strut_axis}");
        span += a.distance(b) + 2.0 * radius;
    }
    assert!((span - LENGTH).abs() <= LENGTH / 8.0, "the halves span {span} m of the {LENGTH} m strut");
}

/// Colliders that cannot be fitted to a part (a ball, a box, a triangle mesh) are refused with
/// an error naming the field, and the world is unchanged.
#[test]
fn a_bending_body_refuses_colliders_it_cannot_fit_to_a_part() {
    for collider in [ColliderKind::Ball, ColliderKind::Cuboid, ColliderKind::TriMesh] {
        let mut world = World::new(WorldSettings::default()).unwrap();
        let error = Bending::new().add(&mut world, BendableDesc { collider, ..strut(0.0) }).expect_err("accepted");
        let message = error.to_string();
        assert!(message.contains("collider") && message.contains("capsule"), "{collider:?}: {message}");
        assert!(world.bodies().is_empty() && world.joints().is_empty(), "{collider:?}: the world changed");
    }
}
