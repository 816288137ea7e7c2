//! Denting in the simulation loop (paper Algorithm 1): thresholds, Figure 1's symmetry through
//! the full simulation, glancing hits, the energy model, and determinism.

use dentbend::glam::Vec3;
use dentbend::mesh::{self, TriMesh};
use dentbend_solver::coupling::Simulation;
use dentbend_solver::sim::{BodyDesc, BodyKind, ColliderKind, DentSettings, World, WorldSettings};

fn weightless() -> WorldSettings {
    WorldSettings { gravity: Vec3::ZERO, sleep_time: 0.0, ..Default::default() }
}

fn dentable_block() -> BodyDesc {
    let block = mesh::builtin("block").unwrap();
    BodyDesc::new("block", block).kind(BodyKind::Static).dentable(DentSettings::new(1.0, 0.04, 0.3))
}

fn ball(name: &str, at: Vec3, velocity: Vec3) -> BodyDesc {
    BodyDesc::new(name, mesh::icosphere(0.5, 3).unwrap()).at(at).velocity(velocity).collider(ColliderKind::Ball)
}

/// Runs `steps` steps and returns the simulation.
fn run(world: World, steps: usize) -> Simulation {
    let mut sim = Simulation::new(world, None).unwrap();
    for _ in 0..steps {
        sim.step().unwrap();
    }
    sim
}

fn largest_move(before: &TriMesh, after: &TriMesh) -> f32 {
    before.positions().iter().zip(after.positions()).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max)
}

#[test]
fn no_dent_below_the_threshold_and_a_dent_above_it() {
    for (speed, dents) in [(0.8f32, false), (6.0, true)] {
        let mut world = World::new(weightless()).unwrap();
        let block = world.add(dentable_block()).unwrap();
        world.add(ball("ball", Vec3::new(0.0, 1.2, 0.0), Vec3::new(0.0, -speed, 0.0))).unwrap();
        let before = world.bodies()[block].mesh().clone();
        let sim = run(world, 90);
        let moved = largest_move(&before, sim.world().bodies()[block].mesh());
        if dents {
            // d = gain·(v − threshold) = 0.04·5 = 0.2 m.
            assert_eq!(sim.dents().len(), 1, "{:?}", sim.dents());
            let d = sim.dents()[0].dent_distance;
            assert!((d - 0.2).abs() < 0.01, "dent distance {d}");
            assert!((moved - d).abs() < 0.1 * d, "deepest move {moved} for d = {d}");
        } else {
            assert!(sim.dents().is_empty(), "{:?}", sim.dents());
            assert_eq!(moved, 0.0);
        }
    }
}

/// Figure 1 through the simulation: two equal dentable balls meeting head-on dent each other
/// equally. The icosphere is mirror-symmetric, so the dents are mirror images; the deepest
/// moves agree to 1e-4 m (f32 round-off of two independently planned maps).
#[test]
fn two_dentable_balls_dent_symmetrically() {
    let mut world = World::new(weightless()).unwrap();
    let settings = DentSettings::new(1.0, 0.03, 0.25);
    let sphere = mesh::icosphere(1.0, 4).unwrap();
    let left = BodyDesc::new("left", sphere.clone())
        .at(Vec3::new(-1.5, 0.0, 0.0))
        .velocity(Vec3::new(4.0, 0.0, 0.0))
        .collider(ColliderKind::Ball)
        .dentable(settings.clone());
    let right = BodyDesc::new("right", sphere.clone())
        .at(Vec3::new(1.5, 0.0, 0.0))
        .velocity(Vec3::new(-4.0, 0.0, 0.0))
        .collider(ColliderKind::Ball)
        .dentable(settings);
    let (l, r) = (world.add(left).unwrap(), world.add(right).unwrap());
    let sim = run(world, 30);
    let bodies = sim.world().bodies();
    assert_eq!(sim.dents().len(), 2, "{:?}", sim.dents());
    let (dl, dr) = (largest_move(&sphere, bodies[l].mesh()), largest_move(&sphere, bodies[r].mesh()));
    assert!(dl > 0.1, "left barely dented: {dl}");
    assert!((dl - dr).abs() < 1e-4, "left {dl} vs right {dr}");
    // The dents face each other: left's deepest vertex is on its +x side, right's on −x.
    let deepest = |mesh: &TriMesh| {
        let k = (0..mesh.vertex_count())
            .max_by(|&i, &j| {
                let di = sphere.positions()[i].distance(mesh.positions()[i]);
                let dj = sphere.positions()[j].distance(mesh.positions()[j]);
                di.total_cmp(&dj)
            })
            .unwrap();
        sphere.positions()[k]
    };
    assert!(deepest(bodies[l].mesh()).x > 0.9 && deepest(bodies[r].mesh()).x < -0.9);
    assert!((bodies[l].mesh().volume() - bodies[r].mesh().volume()).abs() < 1e-4);
}

/// A glancing hit (45°) drags the dent along the projectile's velocity: the moved vertices'
/// mean displacement points along +x, the velocity's in-plane direction.
#[test]
fn glancing_hits_dent_along_the_velocity() {
    let mut world = World::new(weightless()).unwrap();
    let block = world.add(dentable_block()).unwrap();
    world.add(ball("ball", Vec3::new(-0.6, 1.1, 0.0), Vec3::new(5.0, -5.0, 0.0))).unwrap();
    let before = world.bodies()[block].mesh().clone();
    let sim = run(world, 30);
    assert_eq!(sim.dents().len(), 1);
    let after = sim.world().bodies()[block].mesh();
    let moves: Vec<Vec3> =
        before.positions().iter().zip(after.positions()).map(|(a, b)| *b - *a).filter(|m| m.length() > 1e-6).collect();
    let mean = moves.iter().sum::<Vec3>() / moves.len() as f32;
    assert!(mean.y < 0.0, "the dent goes down: {mean}");
    assert!(mean.x > 0.2 * -mean.y, "no drag along the velocity: {mean}");
    assert!(mean.z.abs() < 0.05 * -mean.y, "drag sideways: {mean}");
}

/// Energy model: with the same hardness, a faster or a heavier ball dents deeper.
#[test]
fn the_energy_model_dents_deeper_for_harder_hits() {
    let depth = |speed: f32, density: f32| {
        let mut world = World::new(weightless()).unwrap();
        let mut settings = DentSettings::new(0.5, 1.0, 0.4);
        settings.hardness = Some(2.0e5);
        let block = mesh::builtin("block").unwrap();
        world.add(BodyDesc::new("block", block).kind(BodyKind::Static).dentable(settings)).unwrap();
        let mut projectile = ball("ball", Vec3::new(0.0, 1.2, 0.0), Vec3::new(0.0, -speed, 0.0));
        projectile.density = density;
        let sim = run(world_with(world, projectile), 40);
        assert_eq!(sim.dents().len(), 1);
        sim.dents()[0].dent_distance
    };
    let (slow, fast, heavy) = (depth(3.0, 1000.0), depth(6.0, 1000.0), depth(3.0, 4000.0));
    assert!(slow > 0.0 && slow < 0.4, "slow {slow}");
    assert!(fast > slow * 1.2, "fast {fast} vs slow {slow}");
    assert!(heavy > slow * 1.2, "heavy {heavy} vs slow {slow}");
}

fn world_with(mut world: World, desc: BodyDesc) -> World {
    world.add(desc).unwrap();
    world
}

/// The same scene twice on the CPU gives bit-identical meshes and poses.
#[test]
fn runs_are_deterministic() {
    let build = || {
        let mut world = World::new(WorldSettings::default()).unwrap();
        world.add(dentable_block()).unwrap();
        for k in 0..6 {
            let x = -1.2 + 0.5 * k as f32;
            world
                .add(ball(
                    &format!("ball{k}"),
                    Vec3::new(x, 2.0 + 0.3 * k as f32, 0.1 * k as f32),
                    Vec3::new(0.0, -4.0, 0.0),
                ))
                .unwrap();
        }
        run(world, 80)
    };
    let (a, b) = (build(), build());
    assert!(!a.dents().is_empty());
    for (x, y) in a.world().bodies().iter().zip(b.world().bodies()) {
        assert_eq!(x.mesh().positions(), y.mesh().positions(), "{}", x.name);
        assert_eq!(x.position, y.position, "{}", x.name);
        assert_eq!(x.orientation, y.orientation, "{}", x.name);
    }
}
