//! Spheres poured into a walled box come to rest: contacts stay stable in a large pile, which
//! holds its weight (the bottom layer sinks no deeper than the slop) and falls asleep.

use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_solver::sim::{BodyDesc, BodyKind, ColliderKind, World, WorldSettings};

/// Ball radius, m.
const RADIUS: f32 = 0.1;

/// A floor (top at y = 0) walled in to `half` m either side of the origin, and `layers` ×
/// `side` × `side` balls on a lattice 0.25 m apart, slightly jittered so the pile is not a crystal.
fn poured(side: usize, layers: usize, half: f32) -> World {
    let mut world = World::new(WorldSettings::default()).unwrap();
    let slab = |size: Vec3| mesh::subdivided_box(size, [1, 1, 1]).unwrap();
    let (span, wall) = (2.0 * half + 1.0, half + 0.25);
    let walls = [
        (Vec3::new(span, 1.0, span), Vec3::new(0.0, -0.5, 0.0)),
        (Vec3::new(0.5, 3.0, span), Vec3::new(-wall, 1.0, 0.0)),
        (Vec3::new(0.5, 3.0, span), Vec3::new(wall, 1.0, 0.0)),
        (Vec3::new(span, 3.0, 0.5), Vec3::new(0.0, 1.0, -wall)),
        (Vec3::new(span, 3.0, 0.5), Vec3::new(0.0, 1.0, wall)),
    ];
    for (k, (size, at)) in walls.into_iter().enumerate() {
        world.add(BodyDesc::new(format!("wall{k}"), slab(size)).kind(BodyKind::Static).at(at)).unwrap();
    }
    let ball = mesh::icosphere(RADIUS, 1).unwrap();
    let start = -0.12 * side as f32;
    let mut n = 0;
    for i in 0..layers {
        for j in 0..side {
            for k in 0..side {
                let jitter = 0.02 * (((i * 7 + j * 13 + k * 29) % 11) as f32 / 11.0 - 0.5);
                let at = Vec3::new(start + 0.25 * j as f32 + jitter, 0.3 + 0.25 * i as f32, start + 0.25 * k as f32);
                world.add(BodyDesc::new(format!("ball{n}"), ball.clone()).at(at).collider(ColliderKind::Ball)).unwrap();
                n += 1;
            }
        }
    }
    assert_eq!(n, side * side * layers);
    world
}

/// Steps the poured world 10 s and checks that the pile is at rest inside the box.
fn comes_to_rest(mut world: World, half: f32) {
    let start = world.kinetic_energy();
    for _ in 0..600 {
        world.step();
    }
    let balls: Vec<_> = world.bodies().iter().filter(|b| b.kind == BodyKind::Dynamic).collect();
    let speeds: Vec<f32> = balls.iter().map(|b| b.linear_velocity.length()).collect();
    let asleep = balls.iter().filter(|b| b.is_asleep()).count();
    let lowest = balls.iter().map(|b| b.position.y).fold(f32::INFINITY, f32::min);
    let mean_speed = speeds.iter().sum::<f32>() / balls.len() as f32;
    let max_speed = speeds.iter().fold(0.0_f32, |m, &s| m.max(s));
    eprintln!(
        "{} balls after 10 s: mean speed {mean_speed} m/s, max {max_speed} m/s, {asleep} asleep, lowest centre {lowest} m",
        balls.len()
    );
    // At rest: mean speed under 2 cm/s (the sleep threshold is 5 cm/s), none faster than that.
    assert!(mean_speed < 0.02, "mean speed {mean_speed} m/s after 10 s");
    assert!(max_speed < 0.05, "max speed {max_speed} m/s after 10 s");
    // Nothing escaped or sank through the floor (a ball of radius 0.1 rests with its centre at
    // y ≥ 0.1 − slop).
    for b in &balls {
        assert!(
            b.position.y > 0.09 && b.position.x.abs() < half && b.position.z.abs() < half,
            "{}: {}",
            b.name,
            b.position
        );
    }
    // The pile holds its weight: the bottom layer overlaps the floor by at most the slop (2 mm)
    // plus 1 mm.
    let slop = world.settings().slop;
    assert!(lowest >= RADIUS - slop - 0.001, "lowest centre {lowest} m: the pile sinks into the floor");
    // Asleep: every ball, and (so) no kinetic energy left.
    assert_eq!(asleep, balls.len(), "balls asleep after 10 s");
    assert!(world.kinetic_energy() < 1e-3 * start.max(1.0), "kinetic energy {} J", world.kinetic_energy());
}

#[test]
#[ignore = "slow in debug; run with --release --ignored"]
fn a_pile_of_1500_spheres_comes_to_rest() {
    // 15 layers of 10 × 10 in a 3 m × 3 m box: about 6 layers deep once settled.
    comes_to_rest(poured(10, 15, 1.5), 1.5);
}

#[test]
fn a_pile_of_300_spheres_comes_to_rest() {
    // 12 layers of 5 × 5 in a 1.5 m × 1.5 m box: as deep as the large pile.
    comes_to_rest(poured(5, 12, 0.75), 0.75);
}
