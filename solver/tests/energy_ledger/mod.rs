//! Energy bookkeeping shared by the rest-energy tests: what the dynamic bodies of a world hold,
//! counted once per body (a cluster's members, not its proxy, whose motion they share).
#![allow(dead_code, reason = "each test binary uses a different subset")]

use dentbend_solver::sim::{BodyKind, RigidBody, World};

/// The bodies that carry the world's mass: dynamic, not a cluster's stand-in.
pub fn massive(world: &World) -> impl Iterator<Item = &RigidBody> {
    world.bodies().iter().filter(|b| b.kind == BodyKind::Dynamic && !b.is_cluster_proxy())
}

/// Kinetic plus gravitational potential energy (centre of mass above height `floor`, m) of every
/// dynamic body, J.
pub fn mechanical_energy(world: &World, floor: f32) -> f64 {
    let g = world.settings().gravity;
    let up = -g.normalize_or_zero();
    let potential = |b: &RigidBody| f64::from(b.mass) * f64::from(g.length()) * f64::from(b.position.dot(up) - floor);
    massive(world).map(|b| f64::from(b.kinetic_energy()) + potential(b)).sum()
}

/// The kinetic energy one step of gravity gives a body of `mass` kg at rest, J: ½·m·(g·dt)².
/// A resting contact takes it back every step, so it is the scale of a resting body's jitter.
pub fn one_step_of_gravity(world: &World, mass: f32) -> f64 {
    let s = world.settings();
    let kick = f64::from(s.gravity.length() * s.dt);
    0.5 * f64::from(mass) * kick * kick
}
