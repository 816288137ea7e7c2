//! Long runs of the built-in `rain` and `tetrahedra` scenes at demo size (a simulated minute,
//! 3,600 steps): the solver creates no energy and what stays on the floor comes to rest.
//!
//! Energy is counted per body, kinetic plus potential above the floor's top (y = 0 in both
//! scenes). Nothing in a step may add to that sum but the split position correction, which
//! pushes overlapping bodies apart and so may lift them (by the overlap they landed with), and
//! the joints' drift correction (at most `joint_correction_speed`); everything else — gravity
//! integrated, collisions with restitution ≤ 1, contacts, friction, joints, plastic bends,
//! dents — keeps or loses energy. The slack allowed is every body lifted 1 cm. Kinetic energy
//! alone is not bounded in `rain`: its spheres roll off the 18 × 12 m floor and fall without
//! end (their potential energy pays for it), so the end state is checked on the bodies still
//! over the floor.

mod energy_ledger;

use dentbend_solver::coupling::Simulation;
use dentbend_solver::scene::{SceneSize, builtin_scene};
use dentbend_solver::sim::{RigidBody, World};
use energy_ledger::{massive, mechanical_energy, one_step_of_gravity};

/// Steps run: one simulated minute at 60 steps per second.
const STEPS: usize = 3600;

/// Height below which a body has fallen off the floor (the floors are 1 m and 0.2 m thick,
/// tops at 0), m.
const FALLEN: f32 = -1.0;

fn on_floor(body: &RigidBody) -> bool {
    body.position.y > FALLEN
}

/// Kinetic energy (J) and mass (kg) of the bodies still over the floor.
fn on_floor_energy(world: &World) -> (f64, f32) {
    massive(world).filter(|b| on_floor(b)).fold((0.0, 0.0), |(e, m), b| (e + f64::from(b.kinetic_energy()), m + b.mass))
}

/// Runs the built-in scene `name` at demo size for [`STEPS`] steps and checks:
/// - every step, kinetic plus potential energy is at most its start plus the slack (every body
///   lifted 1 cm), and so is the kinetic energy of the bodies over the floor;
/// - at the end, the bodies over the floor hold less kinetic energy than one step of gravity
///   gives them (½·m·(g·dt)²: resting), and at least `staying` of them are there.
fn stays_bounded(name: &str, staying: usize) {
    let scene = builtin_scene(name, SceneSize::Demo).expect("scene");
    let mut sim = Simulation::new(scene.world, None).expect("simulation").with_bending(scene.bending);
    let world = sim.world();
    let start = mechanical_energy(world, 0.0);
    let g = f64::from(world.settings().gravity.length());
    let slack = massive(world).map(|b| f64::from(b.mass) * g * 0.01).sum::<f64>();
    let bound = start + slack;
    for step in 1..=STEPS {
        sim.step().expect("step");
        let world = sim.world();
        let energy = mechanical_energy(world, 0.0);
        assert!(energy <= bound, "{name}, step {step}: energy {energy} J, started at {start} J (bound {bound} J)");
        let (moving, _) = on_floor_energy(world);
        assert!(moving <= bound, "{name}, step {step}: kinetic energy on the floor {moving} J (bound {bound} J)");
    }
    let world = sim.world();
    let (moving, mass) = on_floor_energy(world);
    let left = massive(world).filter(|b| on_floor(b)).count();
    assert!(left >= staying, "{name}: only {left} bodies left on the floor");
    let rest = one_step_of_gravity(world, mass);
    assert!(moving <= rest, "{name}: {moving} J still moving on the floor after {STEPS} steps (at rest: {rest} J)");
}

/// 150 small, 2 medium and 1 large dentable spheres rain on a bunny and a slab: spheres hit at
/// 10–14 m/s, dent and roll; many roll off the floor's edge (36 stay).
#[test]
fn rain_keeps_its_energy_bounded_for_a_minute() {
    stays_bounded("rain", 20);
}

/// 16 tetrahedra fall 2.6 m onto four cube frames, split and bend their struts and condense;
/// all of them stay (172 bodies).
#[test]
fn tetrahedra_keep_their_energy_bounded_for_a_minute() {
    stays_bounded("tetrahedra", 172);
}
