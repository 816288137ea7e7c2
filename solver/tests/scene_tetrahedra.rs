//! The `tetrahedra` scene (paper Figure 13) as rigid trusses: struts pinned at their balls'
//! centres by ball joints, struts meeting at a ball ignoring each other. A falling tetrahedron
//! makes no contacts with itself and is condensed into one cluster; a landing hit dissolves it
//! (and may split struts), and once quiet it is one cluster again, split halves included. A
//! hard hit on a plastic joint leaves no body spinning past `max_turn` per step.

use std::collections::BTreeMap;

use dentbend::bend::JointRule;
use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_solver::coupling::Simulation;
use dentbend_solver::scene::{SceneSize, tetrahedra_grid};
use dentbend_solver::sim::{BodyDesc, BodyKind, ColliderKind, JointKind, SurfaceMaterial, World, WorldSettings};

/// The world bodies of each tetrahedron (`tetra<t>/…`: balls, struts and strut halves), by name
/// prefix.
fn tetrahedra(world: &World) -> BTreeMap<String, Vec<usize>> {
    let mut by_name: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (k, body) in world.bodies().iter().enumerate() {
        if body.kind == BodyKind::Dynamic && !body.is_cluster_proxy() {
            let prefix = body.name.split('/').next().expect("a name").to_owned();
            assert!(prefix.starts_with("tetra"), "unexpected dynamic body {}", body.name);
            by_name.entry(prefix).or_default().push(k);
        }
    }
    by_name
}

/// Whether `bodies` are exactly the members of one cluster.
fn one_cluster(world: &World, bodies: &[usize]) -> bool {
    let Some(cluster) = world.cluster_of(bodies[0]) else { return false };
    let mut members = world.cluster_members(cluster).expect("an active cluster");
    members.sort_unstable();
    let mut bodies = bodies.to_vec();
    bodies.sort_unstable();
    members == bodies
}

/// Edge length of a tetrahedron, ball centre to ball centre, m (`TETRA_EDGE` of the scene).
const EDGE: f32 = 0.6;

/// Largest error of a distance between two ball centres of tetrahedron 0 from the edge, m.
fn edge_error(world: &World) -> f32 {
    let ball = |k: usize| world.bodies()[world.find(&format!("tetra000/ball{k}")).expect("a ball")].position;
    let mut worst = 0.0f32;
    for a in 0..4 {
        for b in a + 1..4 {
            worst = worst.max((ball(a).distance(ball(b)) - EDGE).abs());
        }
    }
    worst
}

/// A lone tetrahedron lifted 20 m and left to fall for 1 s (4.9 m) with nothing near it: its
/// struts meet 1 cm apart at the balls, inside the 1 cm contact margin, yet they are filtered,
/// so the step finds no contact point at all. The plain world (no condensation) keeps all ten
/// bodies free, so every strut pair is tested every step. The truss keeps its shape: the ball
/// centres stay an edge apart within 1 mm (the joints hold anchors to solver tolerance; a loose
/// truss would sag by centimetres).
#[test]
fn a_falling_tetrahedron_makes_no_contacts_with_itself() {
    let mut world = tetrahedra_grid(1, 1, SceneSize::Demo).expect("scene").world;
    let bodies = tetrahedra(&world).remove("tetra000").expect("tetrahedron 0");
    assert_eq!(bodies.len(), 10, "four balls and six struts");
    for &k in &bodies {
        world.bodies_mut()[k].position.y += 20.0;
    }
    for step in 1..=60 {
        let report = world.step();
        assert_eq!(report.contact_points, 0, "step {step}: {} contact points in free fall", report.contact_points);
        assert!(edge_error(&world) < 1e-3, "step {step}: an edge is off by {} m", edge_error(&world));
    }
    // It did fall freely: 1 s of gravity is 9.81 m/s down (linear motion is undamped; 1 %
    // covers f32 sums and joint corrections).
    let fall = world.bodies()[bodies[0]].linear_velocity.y;
    assert!((fall + 9.81).abs() < 0.1, "fell at {fall} m/s after 1 s");
}

/// What a run of the one-tetrahedron scene left behind.
struct Landing {
    /// Step at which all the tetrahedron's bodies were first one cluster.
    condensed: Option<u64>,
    /// First step after that with one of its bodies free (a hit woke it).
    woken: Option<u64>,
    /// Fastest closing speed of a hit on one of its bodies, m/s.
    fastest_hit: f32,
}

/// Runs `sim` for `steps` steps, watching tetrahedron `name`. Asserts that before it is first
/// condensed the step finds no contact point (it falls in the air, its struts filtered).
fn watch(sim: &mut Simulation, name: &str, steps: u64) -> Landing {
    let mut landing = Landing { condensed: None, woken: None, fastest_hit: 0.0 };
    for _ in 0..steps {
        let (_, report) = sim.step().expect("step");
        let world = sim.world();
        let step = world.steps();
        let bodies = &tetrahedra(world)[name];
        if landing.condensed.is_none() {
            assert_eq!(report.contact_points, 0, "step {step}: contact points before the tetrahedron was condensed");
        }
        for event in &report.events {
            if bodies.contains(&event.a) || bodies.contains(&event.b) {
                landing.fastest_hit = landing.fastest_hit.max(event.normal_speed);
            }
        }
        let together = one_cluster(world, bodies);
        if together && landing.condensed.is_none() {
            landing.condensed = Some(step);
        }
        let any_free = bodies.iter().any(|&k| world.cluster_of(k).is_none());
        if landing.condensed.is_some() && landing.woken.is_none() && any_free {
            landing.woken = Some(step);
        }
    }
    landing
}

/// The lone tetrahedron of `tetrahedra_grid(1, 1, Demo)` falls from 2.6 m between the frames.
/// Its joints are quiet at once (it falls rigidly), so after the 0.1 s quiet time (6 steps)
/// all ten bodies are one cluster: by step 8 (one step of slack for when quiet is counted),
/// and without a contact point before that. It lands at about 6.4 m/s, above the 3 m/s wake
/// speed, so the hit dissolves the cluster; 3 s later (about 2 s after the landing) it lies
/// still and all its bodies, halves of any split strut included, are one cluster again, and
/// stayed so through the last second. (With a ball joint's whole relative spin counted as
/// activity, spin in place included, the woken tetrahedron stayed ten free bodies.)
#[test]
fn a_landed_tetrahedron_is_one_cluster_again() {
    let scene = tetrahedra_grid(1, 1, SceneSize::Demo).expect("scene");
    let mut sim = Simulation::new(scene.world, None).expect("simulation").with_bending(scene.bending);
    let landing = watch(&mut sim, "tetra000", 120);
    let condensed = landing.condensed.expect("never condensed in the air");
    assert!(condensed <= 8, "condensed only at step {condensed}");
    // 3 m/s: the scene's wake and split speed; the fall from about 2.3 m gives 6.7 m/s.
    assert!(landing.fastest_hit > 3.0, "landed at only {} m/s", landing.fastest_hit);
    assert!(landing.woken.is_some(), "the landing did not wake the tetrahedron");
    for _ in 0..60 {
        sim.step().expect("step");
        let world = sim.world();
        let bodies = &tetrahedra(world)["tetra000"];
        assert!(
            one_cluster(world, bodies),
            "step {}: not one cluster: {:?}",
            world.steps(),
            bodies.iter().map(|&k| world.cluster_of(k)).collect::<Vec<_>>()
        );
        // At rest: 1 cm/s is well below the 0.05 m/s sleep speed.
        let speed = world.bodies()[bodies[0]].linear_velocity.length();
        assert!(speed < 0.01, "step {}: still moving at {speed} m/s", world.steps());
    }
}

/// Four tetrahedra (`tetrahedra_grid(4, 2, Demo)`) fall onto the frames' corners and the
/// ground; a strut hit above the 3 m/s split speed splits in two. Every tetrahedron is woken by
/// its landing, and after 3 s each is exactly one cluster of its own bodies: ten, or eleven and
/// more for one with a split strut, whose halves are members too. At least one strut split
/// (measured: one), so the halves' joints and collision filters take part.
#[test]
fn tetrahedra_with_split_struts_are_one_cluster_each_again() {
    let scene = tetrahedra_grid(4, 2, SceneSize::Demo).expect("scene");
    let mut sim = Simulation::new(scene.world, None).expect("simulation").with_bending(scene.bending);
    let mut woken: BTreeMap<String, u64> = BTreeMap::new();
    for _ in 0..180 {
        sim.step().expect("step");
        let world = sim.world();
        // Step 10: all four were condensed in the air by then (after the 6-step quiet time).
        if world.steps() > 10 {
            for (name, bodies) in tetrahedra(world) {
                if bodies.iter().any(|&k| world.cluster_of(k).is_none()) {
                    woken.entry(name).or_insert(world.steps());
                }
            }
        }
    }
    let world = sim.world();
    let all = tetrahedra(world);
    assert_eq!(all.len(), 4);
    assert!(!sim.bending().joints().is_empty(), "no strut split: the test does not exercise split halves");
    assert!(all.values().any(|b| b.len() > 10), "no tetrahedron gained a strut half");
    for (name, bodies) in &all {
        assert!(woken.contains_key(name), "{name} never woke");
        let clusters: Vec<Option<usize>> = bodies.iter().map(|&k| world.cluster_of(k)).collect();
        assert!(one_cluster(world, bodies), "{name} ({} bodies) is not one cluster: {clusters:?}", bodies.len());
    }
}

/// A light 0.3 m bar of two 15 cm halves (3 cm thick) joined by a weak plastic joint, hit near
/// its end by a 4 kg steel ball at 60 m/s in free space: the joint bends fast. After every
/// step no body spins faster than `max_turn` per step, to f32 round-off of the scaling (1e-5
/// relative): the bend rate and the velocities post-stabilization writes are held to it. The
/// hit is hard enough to matter: some body reaches 90 % of the limit (measured 96 %; without
/// the limit on post-stabilized spins the bar reached 104.5 %).
#[test]
fn a_hard_hit_on_a_plastic_joint_leaves_no_spin_past_max_turn() {
    let settings = WorldSettings { gravity: Vec3::ZERO, angular_damping: 0.0, sleep_time: 0.0, ..Default::default() };
    let mut world = World::new(settings).expect("world");
    let half = mesh::subdivided_box(Vec3::new(0.15, 0.03, 0.03), [1, 1, 1]).expect("box");
    let box_at = |name: &str, x: f32| {
        BodyDesc::new(name, half.clone()).at(Vec3::new(x, 0.0, 0.0)).collider(ColliderKind::Cuboid)
    };
    let left = world.add(box_at("left", -0.075)).expect("left");
    let right = world.add(box_at("right", 0.075)).expect("right");
    let kind = JointKind::Bend(JointRule::Plastic { strength: 0.01, damping_constant: 1.0, damping_proportional: 6.0 });
    world.add_joint(left, right, Vec3::ZERO, kind).expect("joint");
    let mut ball = BodyDesc::new("ball", mesh::icosphere(0.05, 2).expect("ball"))
        .at(Vec3::new(0.27, 0.2, 0.0))
        .velocity(Vec3::new(0.0, -60.0, 0.0))
        .collider(ColliderKind::Ball);
    ball.density = 7800.0;
    ball.surface = SurfaceMaterial { restitution: 0.3, friction: 0.0 };
    world.add(ball).expect("ball");
    let limit = world.settings().max_turn / world.settings().dt;
    let (mut fastest, mut bends) = (0.0f32, 0);
    for step in 1..=20 {
        bends += world.step().bends.len();
        for body in world.bodies().iter().filter(|b| b.kind == BodyKind::Dynamic) {
            let spin = body.angular_velocity.length();
            assert!(spin <= limit * (1.0 + 1e-5), "step {step}: {} spins at {spin} rad/s, limit {limit}", body.name);
            fastest = fastest.max(spin);
        }
    }
    assert!(bends > 0, "the joint never bent");
    assert!(fastest > 0.9 * limit, "the hit only reached {fastest} rad/s of {limit}");
}

/// The demo pile (`tetrahedra_grid(16, 4, Demo)`) 5 s after it fell: every tetrahedron is one
/// cluster of its own bodies again. Before pre-stabilization asked a bending joint for the turn
/// the quaternion step makes at its bend rate, a split strut half in tetrahedron 2 twisted about
/// its axis at 84.86 rad/s for good (its plastic joint bending 1.33 rad every step), and that
/// tetrahedron stayed twelve free bodies.
#[test]
fn every_tetrahedron_of_the_demo_pile_is_one_cluster_again() {
    let scene = tetrahedra_grid(16, 4, SceneSize::Demo).expect("scene");
    let mut sim = Simulation::new(scene.world, None).expect("simulation").with_bending(scene.bending);
    for _ in 0..300 {
        sim.step().expect("step");
    }
    let world = sim.world();
    for (name, bodies) in tetrahedra(world) {
        let spins: Vec<String> = bodies
            .iter()
            .map(|&k| &world.bodies()[k])
            .filter(|b| b.angular_velocity.length() > 1.0)
            .map(|b| format!("{} at {:.2} rad/s", b.name, b.angular_velocity.length()))
            .collect();
        assert!(
            one_cluster(world, &bodies),
            "{name} ({} bodies) is not one cluster; spinning: {spins:?}",
            bodies.len()
        );
    }
}
