//! Rigid-body core: restitution and momentum in two-ball collisions, energy that never grows,
//! a box stack that stays standing.

use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_solver::sim::{BodyDesc, BodyKind, ColliderKind, SurfaceMaterial, World, WorldSettings};

fn ball(name: &str, radius: f32, at: Vec3, velocity: Vec3, restitution: f32) -> BodyDesc {
    let mesh = mesh::icosphere(radius, 3).unwrap();
    let mut desc = BodyDesc::new(name, mesh).at(at).velocity(velocity).collider(ColliderKind::Ball);
    desc.surface = SurfaceMaterial { restitution, friction: 0.0 };
    desc
}

fn weightless() -> WorldSettings {
    WorldSettings { gravity: Vec3::ZERO, sleep_time: 0.0, angular_damping: 0.0, ..Default::default() }
}

/// Head-on, unequal masses: momentum is kept and the closing speed comes back times e. A
/// single contact point is solved exactly by the accumulated impulse, so 1e-3 relative covers
/// f32 round-off over the iterations.
#[test]
fn two_balls_keep_momentum_and_bounce_with_restitution() {
    for e in [0.0f32, 0.5, 1.0] {
        let mut world = World::new(weightless()).unwrap();
        let a = world.add(ball("a", 1.0, Vec3::new(-2.0, 0.0, 0.0), Vec3::new(4.0, 0.0, 0.0), e)).unwrap();
        let b = world.add(ball("b", 0.7, Vec3::new(2.0, 0.0, 0.0), Vec3::new(-3.0, 0.0, 0.0), e)).unwrap();
        let p0 = world.bodies()[a].momentum() + world.bodies()[b].momentum();
        let closing = 7.0;
        let mut events = 0;
        for _ in 0..60 {
            events += world.step().events.len();
        }
        assert!(events >= 1, "no collision event");
        let (va, vb) = (world.bodies()[a].linear_velocity, world.bodies()[b].linear_velocity);
        let p1 = world.bodies()[a].momentum() + world.bodies()[b].momentum();
        assert!((p1 - p0).length() <= 1e-3 * p0.length().max(1.0), "e = {e}: momentum {p0} -> {p1}");
        let separating = vb.x - va.x;
        assert!((separating - e * closing).abs() <= 1e-3 * closing, "e = {e}: separating at {separating}");
        assert!(va.y.abs() + va.z.abs() + vb.y.abs() + vb.z.abs() < 1e-4, "head-on hit went sideways");
    }
}

/// The rotation of the bodies enters the relative velocity at the contact (v + ω × r).
#[test]
fn events_carry_the_contact_velocity_including_spin() {
    let mut world = World::new(weightless()).unwrap();
    let mut spinning = ball("spinning", 1.0, Vec3::new(-1.5, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0), 0.0);
    spinning.angular_velocity = Vec3::new(0.0, 0.0, 3.0);
    world.add(spinning).unwrap();
    world.add(ball("still", 1.0, Vec3::new(1.0, 0.0, 0.0), Vec3::ZERO, 0.0)).unwrap();
    let event = (0..30).find_map(|_| world.step().events.first().copied()).expect("a collision");
    // At the contact (+1 m along x from the spinning ball's centre) ω × r = (0, 3, 0): b sees a
    // moves at (2, 3, 0) relative to it, so b's velocity relative to a is (−2, −3, 0).
    let expected = Vec3::new(-2.0, -3.0, 0.0);
    assert!((event.relative_velocity - expected).length() < 0.05, "{:?}", event.relative_velocity);
    assert!((event.normal - Vec3::X).length() < 1e-3);
    assert!((event.normal_speed - 2.0).abs() < 0.05);
    assert!(event.impulse.x > 0.0, "b is pushed along +x: {:?}", event.impulse);
}

/// Total energy (kinetic + potential) of a ball bouncing on the ground never grows from one
/// step to the next beyond f32 round-off (1e-4 of the initial energy).
#[test]
fn energy_does_not_grow() {
    let settings = WorldSettings { sleep_time: 0.0, angular_damping: 0.0, ..Default::default() };
    let mut world = World::new(settings).unwrap();
    // A 40 m wide slab (top at y = 0.5) so nothing bounces off its edge.
    let ground = mesh::subdivided_box(Vec3::new(40.0, 1.0, 40.0), [4, 1, 4]).unwrap();
    world.add(BodyDesc::new("ground", ground).kind(BodyKind::Static)).unwrap();
    let mut boxy =
        BodyDesc::new("box", mesh::subdivided_box(Vec3::splat(0.5), [1, 1, 1]).unwrap()).at(Vec3::new(0.3, 3.0, 0.0));
    boxy.angular_velocity = Vec3::new(1.0, 2.0, 0.5);
    boxy.surface = SurfaceMaterial { restitution: 0.8, friction: 0.4 };
    let b = world.add(boxy).unwrap();
    world.add(ball("ball", 0.4, Vec3::new(-0.5, 2.0, 0.3), Vec3::new(0.5, 0.0, 0.0), 0.9)).unwrap();
    let g = 9.81;
    let energy = |w: &World| {
        w.bodies()
            .iter()
            .filter(|x| x.kind == BodyKind::Dynamic)
            .map(|x| f64::from(x.kinetic_energy() + x.mass * g * x.position.y))
            .sum::<f64>()
    };
    let start = energy(&world);
    let mut previous = start;
    for step in 0..300 {
        world.step();
        let now = energy(&world);
        assert!(now <= previous + 1e-4 * start.abs(), "step {step}: energy grew {previous} -> {now}");
        previous = now;
    }
    assert!(world.bodies()[b].position.y > 0.7, "the box sank into the ground");
}

/// Five boxes stacked on the ground stay standing for 5 s: the top box drifts < 2 cm
/// sideways and sinks < 2 cm (slop and the position correction allow a few mm per contact).
#[test]
fn a_box_stack_stays_standing() {
    let mut world = World::new(WorldSettings::default()).unwrap();
    world.add(BodyDesc::new("ground", mesh::builtin("block").unwrap()).kind(BodyKind::Static)).unwrap();
    let cube = mesh::subdivided_box(Vec3::splat(0.5), [1, 1, 1]).unwrap();
    let mut top = 0;
    for level in 0..5 {
        let y = 0.5 + 0.25 + 0.5 * level as f32 + 0.001 * level as f32;
        top = world.add(BodyDesc::new(format!("box{level}"), cube.clone()).at(Vec3::new(0.0, y, 0.0))).unwrap();
    }
    let start = world.bodies()[top].position;
    for _ in 0..300 {
        world.step();
    }
    let end = world.bodies()[top].position;
    let drift = Vec3::new(end.x - start.x, 0.0, end.z - start.z).length();
    assert!(drift < 0.02, "top box drifted {drift} m");
    assert!(start.y - end.y < 0.02, "top box sank {} m", start.y - end.y);
}
