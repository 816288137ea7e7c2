//! Stability guards of the step: the spin limit (`WorldSettings::max_turn`) and the joint–contact
//! rounds that put back an island whose kinetic energy they raise. Without them the `tetrahedra`
//! scene (struts pinned by ball joints, split by plastic joints, wedged in frames) ran away to
//! speeds of 10⁹ m/s within a second.

use dentbend::glam::Vec3;
use dentbend::mesh::subdivided_box;
use dentbend_solver::coupling::Simulation;
use dentbend_solver::scene::{SceneSize, tetrahedra_grid};
use dentbend_solver::sim::{BodyDesc, ColliderKind, World, WorldSettings};

/// The fastest the pile's bodies can honestly move, m/s: the highest tetrahedron falls about
/// 4.6 m (9.5 m/s; the guarded run's fastest body was 10.3 m/s); 30 m/s is three times that
/// and far below the runaway's 10⁶–10¹³ m/s.
const SANE_SPEED: f32 = 30.0;

/// Frames run: the unguarded pile ran away within them (at about frame 100, once the third
/// layer landed on the first two).
const FRAMES: u32 = 150;

#[test]
fn a_pile_of_tetrahedra_stays_bounded_through_its_splits_and_bends() {
    // Three layers of 4 × 4 dropped on the frames: the full scene's mechanism (struts of
    // jointed loops split and wedged between bars and each other) at a tenth of its size.
    let scene = tetrahedra_grid(48, 4, SceneSize::Demo).expect("scene");
    let frames = FRAMES;
    let mut sim = Simulation::new(scene.world, None).expect("simulation").with_bending(scene.bending);
    let mut fastest = 0.0f32;
    for frame in 1..=frames {
        sim.step().unwrap_or_else(|e| panic!("frame {frame}: {e}"));
        let world = sim.world();
        let max_turn = world.settings().max_turn / world.settings().dt;
        for body in world.bodies().iter().filter(|b| !b.is_condensed()) {
            assert!(body.position.is_finite(), "frame {frame}: {} left the world", body.name);
            let (v, w) = (body.linear_velocity.length(), body.angular_velocity.length());
            fastest = fastest.max(v);
            assert!(v < SANE_SPEED, "frame {frame}: {} moves at {v} m/s", body.name);
            // Post-stabilization may turn a clamped spin by its joints' relative velocity; twice
            // the limit still tells a bounded spin from a runaway.
            assert!(w < 2.0 * max_turn, "frame {frame}: {} spins at {w} rad/s", body.name);
        }
    }
    assert!(!sim.bending().joints().is_empty(), "no strut split: the test did not exercise the rounds");
    assert!(fastest > 3.0, "nothing fell ({fastest} m/s)");
}

fn spinning_box(spin: f32) -> World {
    let mut world =
        World::new(WorldSettings { gravity: Vec3::ZERO, angular_damping: 0.0, ..Default::default() }).expect("world");
    let desc = BodyDesc::new("box", subdivided_box(Vec3::splat(0.2), [1, 1, 1]).expect("box"));
    let index = world.add(desc.collider(ColliderKind::Cuboid)).expect("add");
    world.bodies_mut()[index].angular_velocity = Vec3::new(0.0, spin, 0.0);
    world
}

#[test]
fn a_spin_faster_than_max_turn_per_step_is_scaled_down_and_a_slower_one_kept() {
    let dt = WorldSettings::default().dt;
    let limit = WorldSettings::default().max_turn / dt;
    let mut fast = spinning_box(3.0 * limit);
    fast.step();
    let w = fast.bodies()[0].angular_velocity;
    // Scaled, not clipped per axis: the axis stays, the magnitude is the limit (f32 round-off).
    assert!((w.length() - limit).abs() < 1e-3 * limit, "spin {w} not brought to {limit}");
    assert!(w.normalize().dot(Vec3::Y) > 0.999_999, "spin axis turned: {w}");
    let mut slow = spinning_box(0.5 * limit);
    slow.step();
    assert_eq!(slow.bodies()[0].angular_velocity, Vec3::new(0.0, 0.5 * limit, 0.0));
}

#[test]
fn a_bad_max_turn_is_refused() {
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        let settings = WorldSettings { max_turn: bad, ..Default::default() };
        let error = World::new(settings).expect_err("bad max_turn accepted").to_string();
        assert!(error.contains("max_turn"), "{error}");
    }
}
