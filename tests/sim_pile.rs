//! 1,500 spheres poured into a walled box come to rest: contacts stay stable in a large pile.

use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend::sim::{BodyDesc, BodyKind, ColliderKind, World, WorldSettings};

#[test]
#[ignore = "known failure, issue 4: a 15-layer pile keeps ~2 cm/s of contact jitter (median speed) and never sleeps"]
fn a_pile_of_1500_spheres_comes_to_rest() {
    let mut world = World::new(WorldSettings::default()).unwrap();
    // A 3 m × 3 m floor (top at y = 0) with 2 m walls.
    let slab = |size: Vec3| mesh::subdivided_box(size, [1, 1, 1]).unwrap();
    let walls = [
        (Vec3::new(4.0, 1.0, 4.0), Vec3::new(0.0, -0.5, 0.0)),
        (Vec3::new(0.5, 3.0, 4.0), Vec3::new(-1.75, 1.0, 0.0)),
        (Vec3::new(0.5, 3.0, 4.0), Vec3::new(1.75, 1.0, 0.0)),
        (Vec3::new(4.0, 3.0, 0.5), Vec3::new(0.0, 1.0, -1.75)),
        (Vec3::new(4.0, 3.0, 0.5), Vec3::new(0.0, 1.0, 1.75)),
    ];
    for (k, (size, at)) in walls.into_iter().enumerate() {
        world.add(BodyDesc::new(format!("wall{k}"), slab(size)).kind(BodyKind::Static).at(at)).unwrap();
    }
    let ball = mesh::icosphere(0.1, 1).unwrap();
    // 15 × 10 × 10 lattice, 0.25 m apart, slightly jittered so the pile is not a crystal.
    let mut n = 0;
    for i in 0..15 {
        for j in 0..10 {
            for k in 0..10 {
                let jitter = 0.02 * (((i * 7 + j * 13 + k * 29) % 11) as f32 / 11.0 - 0.5);
                let at = Vec3::new(-1.2 + 0.25 * j as f32 + jitter, 0.3 + 0.25 * i as f32, -1.2 + 0.25 * k as f32);
                world.add(BodyDesc::new(format!("ball{n}"), ball.clone()).at(at).collider(ColliderKind::Ball)).unwrap();
                n += 1;
            }
        }
    }
    assert_eq!(n, 1500);
    let start = world.kinetic_energy();
    for _ in 0..600 {
        world.step();
    }
    let balls = || world.bodies().iter().filter(|b| b.kind == BodyKind::Dynamic);
    // At rest: mean speed under 2 cm/s (the sleep threshold is 5 cm/s), nothing escaped or sank
    // through the floor (a ball of radius 0.1 rests with its centre at y ≥ 0.1 − slop).
    let mean_speed = balls().map(|b| b.linear_velocity.length()).sum::<f32>() / n as f32;
    assert!(mean_speed < 0.02, "mean speed {mean_speed} m/s after 10 s");
    for b in balls() {
        assert!(
            b.position.y > 0.09 && b.position.x.abs() < 1.5 && b.position.z.abs() < 1.5,
            "{}: {}",
            b.name,
            b.position
        );
    }
    assert!(world.kinetic_energy() < 1e-3 * start.max(1.0), "kinetic energy {} J", world.kinetic_energy());
}
