//! Rolling resistance (`WorldSettings::rolling_resistance`, μ_r): a ball on a slope steeper than
//! tan α = μ_r rolls down with acceleration (5/7) g (sin α − μ_r cos α); a gentler slope holds
//! it. (Gravity is tilted instead of the floor.)

use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_solver::sim::{BodyDesc, BodyKind, ColliderKind, World, WorldSettings};

const GRAVITY: f32 = 9.81;
const ROLLING: f32 = 0.02;

/// A ball of radius 0.1 resting on a floor under gravity tilted by `tan_alpha` along +x; returns
/// its x velocity after `seconds`.
fn roll(tan_alpha: f32, seconds: f32) -> f32 {
    let alpha = tan_alpha.atan();
    let settings = WorldSettings {
        gravity: GRAVITY * Vec3::new(alpha.sin(), -alpha.cos(), 0.0),
        rolling_resistance: ROLLING,
        angular_damping: 0.0,
        sleep_time: 0.0,
        ..Default::default()
    };
    let mut world = World::new(settings).unwrap();
    let floor = mesh::subdivided_box(Vec3::new(20.0, 1.0, 4.0), [1, 1, 1]).unwrap();
    world.add(BodyDesc::new("floor", floor).kind(BodyKind::Static).at(Vec3::new(0.0, -0.5, 0.0))).unwrap();
    let ball = BodyDesc::new("ball", mesh::icosphere(0.1, 3).unwrap()).at(Vec3::new(0.0, 0.1, 0.0));
    let ball = world.add(ball.collider(ColliderKind::Ball)).unwrap();
    for _ in 0..(seconds * 60.0).round() as usize {
        world.step();
    }
    world.bodies()[ball].linear_velocity.x
}

#[test]
fn a_ball_rolls_down_a_slope_steeper_than_the_rolling_resistance() {
    let tan_alpha: f32 = 0.06;
    let alpha = tan_alpha.atan();
    let expected = 5.0 / 7.0 * GRAVITY * (alpha.sin() - ROLLING * alpha.cos()) * 1.0;
    let speed = roll(tan_alpha, 1.0);
    // The icosphere's inertia is within a few % of a solid sphere's; 10 % tolerance.
    assert!((speed - expected).abs() < 0.1 * expected, "speed after 1 s: {speed} m/s, expected {expected}");
}

#[test]
fn a_gentler_slope_holds_the_ball() {
    let speed = roll(0.5 * ROLLING, 2.0);
    assert!(speed.abs() < 1e-3, "speed after 2 s: {speed} m/s");
}
