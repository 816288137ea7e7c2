//! Rigid clusters (paper §4.2, condensation): bodies condensed into one move as the same bodies
//! held by rigid joints would, keep their momentum, report hits on the member hit, swing on the
//! joints that tie them to the rest of the world, and come apart again with the cluster's motion.

use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_solver::sim::{
    BodyDesc, BodyKind, ColliderKind, DentSettings, JointKind, SurfaceMaterial, World, WorldSettings,
};

fn block(name: &str, size: Vec3, at: Vec3) -> BodyDesc {
    let mesh = mesh::subdivided_box(size, [1, 1, 1]).unwrap();
    BodyDesc::new(name, mesh).at(at).collider(ColliderKind::ConvexHull)
}

/// A T of three blocks (a bar and two legs of different sizes, so the inertia is not
/// symmetric) welded by rigid joints, thrown spinning over a static floor. Returns the world
/// and the indices of the blocks.
///
/// The spin is about z, a principal axis (the T is symmetric about the xy plane), and angular
/// damping is off: the world integrates a free body with constant ω (no gyroscopic term) and
/// damps each body's own ω, while rigid joints pass momentum-conserving impulses between their
/// bodies, so about other axes, or with damping, the two models themselves differ (by 0.26 m
/// after 1 s for ω = (0.5, 3, −2) rad/s with the default damping) whatever the cluster does.
fn thrown_t(floor: bool, (v, w): (Vec3, Vec3)) -> (World, [usize; 3]) {
    let settings = WorldSettings { sleep_time: 0.0, angular_damping: 0.0, ..Default::default() };
    let mut world = World::new(settings).unwrap();
    if floor {
        let ground = block("floor", Vec3::new(8.0, 0.2, 8.0), Vec3::new(0.0, -0.1, 0.0));
        let surface = SurfaceMaterial { restitution: 0.0, ..ground.surface };
        world.add(BodyDesc { surface, ..ground.kind(BodyKind::Static).collider(ColliderKind::Cuboid) }).unwrap();
    }
    let mut add = |name: &str, size: Vec3, at: Vec3| {
        let centre = Vec3::new(0.0, 1.5, 0.0);
        let desc = block(name, size, at).velocity(v + w.cross(at - centre));
        let surface = SurfaceMaterial { restitution: 0.0, ..desc.surface };
        world.add(BodyDesc { angular_velocity: w, surface, ..desc }).unwrap()
    };
    let bar = add("bar", Vec3::new(0.8, 0.1, 0.1), Vec3::new(0.0, 1.5, 0.0));
    // Upright in the xy plane in flight; lying in the xz plane over the floor.
    let (long, short, anchor) = if floor {
        ((Vec3::new(0.1, 0.1, 0.5), -0.3), (Vec3::new(0.1, 0.1, 0.2), -0.15), Vec3::new(0.0, 0.0, -0.05))
    } else {
        ((Vec3::new(0.1, 0.5, 0.1), -0.3), (Vec3::new(0.1, 0.2, 0.2), -0.15), Vec3::new(0.0, -0.05, 0.0))
    };
    let down = if floor { Vec3::Z } else { Vec3::Y };
    let long = add("long leg", long.0, Vec3::new(-0.35, 1.5, 0.0) + long.1 * down);
    let short = add("short leg", short.0, Vec3::new(0.35, 1.5, 0.0) + short.1 * down);
    world.add_joint(bar, long, Vec3::new(-0.35, 1.5, 0.0) + anchor, JointKind::Rigid).unwrap();
    world.add_joint(bar, short, Vec3::new(0.35, 1.5, 0.0) + anchor, JointKind::Rigid).unwrap();
    (world, [bar, long, short])
}

/// Thrown up and sideways, spinning at 1.5 rad/s.
const THROW: (Vec3, Vec3) = (Vec3::new(1.0, 1.5, 0.3), Vec3::new(0.0, 0.0, -1.5));

/// Dropped flat, turning slowly about the bar so that it lands on one leg first (the T lies in
/// the xz plane then: upright, it could balance on both legs or fall either way on round-off).
const DROP: (Vec3, Vec3) = (Vec3::ZERO, Vec3::new(0.6, 0.0, 0.0));

/// Largest distance between the same block in two worlds, m.
fn largest_gap(a: &World, b: &World, blocks: &[usize]) -> f32 {
    blocks.iter().map(|&k| a.bodies()[k].position.distance(b.bodies()[k].position)).fold(0.0, f32::max)
}

/// In flight, the cluster and the jointed T follow the same free rigid motion. The centres of
/// mass agree to round-off; the jointed T's spin bleeds about 1.3 % per second (its velocity
/// projections are first order in ω·dt), so it lags the cluster by about 0.01 rad after 1 s and
/// its blocks, 0.4 m from the centre, by 3.7 mm (measured). Bound: 5 mm, against the 0.26 m a
/// wrong inertia or a lost spin gives. The cluster keeps the blocks' momentum and energy.
#[test]
fn a_cluster_flies_like_the_same_bodies_held_by_rigid_joints() {
    let (mut jointed, blocks) = thrown_t(false, THROW);
    let (mut condensed, _) = thrown_t(false, THROW);
    let momentum = |w: &World| blocks.iter().map(|&k| w.bodies()[k].momentum()).sum::<Vec3>();
    let before = momentum(&condensed);
    let energy_before = condensed.kinetic_energy();
    let id = condensed.condense(&blocks).unwrap();
    assert_eq!(condensed.cluster_members(id).unwrap(), blocks.to_vec());
    assert!(condensed.bodies()[blocks[0]].is_condensed());
    assert!((momentum(&condensed) - before).length() < 1e-4 * before.length());
    // The blocks moved rigidly, so condensing keeps the kinetic energy too (f32 sums: 1e-5).
    assert!((condensed.kinetic_energy() - energy_before).abs() < 1e-5 * energy_before);
    for _ in 0..60 {
        jointed.step();
        condensed.step();
    }
    let gap = largest_gap(&jointed, &condensed, &blocks);
    assert!(gap < 5e-3, "condensed and jointed T differ by {gap} m after 1 s of flight");
    let spin = |w: &World| w.bodies()[blocks[1]].angular_velocity;
    // The cluster keeps its spin (a rigid body about a principal axis); the jointed T's bleeds.
    assert!((spin(&condensed) - THROW.1).length() < 1e-5 * THROW.1.length(), "{:?}", spin(&condensed));
    assert!((spin(&jointed) - spin(&condensed)).length() < 0.02 * THROW.1.length(), "{:?}", spin(&jointed));
}

/// Landing (no restitution): the cluster's compound collider meets the floor where the blocks
/// would. After 2 s both Ts lie flat and still: every block's centre at half its thickness,
/// 5 cm, within the slop plus 1 mm (a cluster colliding as one convex hull would rest on its
/// hull's corners, a cluster not colliding would fall through). The jointed T's joints soak up
/// a little more of the landing, so it slides less after touching down: the blocks end 2.5 cm
/// apart (measured); bound 4 cm, 5 % of the T's 0.8 m span.
#[test]
fn a_cluster_lands_like_the_jointed_bodies() {
    let (mut jointed, blocks) = thrown_t(true, DROP);
    let (mut condensed, _) = thrown_t(true, DROP);
    condensed.condense(&blocks).unwrap();
    for _ in 0..120 {
        jointed.step();
        condensed.step();
    }
    let gap = largest_gap(&jointed, &condensed, &blocks);
    assert!(gap < 0.04, "condensed and jointed T end {gap} m apart");
    for world in [&jointed, &condensed] {
        let bound = world.settings().slop + 1e-3;
        for &k in &blocks {
            let body = &world.bodies()[k];
            assert!((body.position.y - 0.05).abs() < bound, "block {k} rests at {}", body.position.y);
            assert!(body.linear_velocity.length() < 1e-3);
        }
    }
}

/// Hits on a cluster are reported on the member hit: the T falls flat-ish on its long leg
/// first, so the first event names the long leg and the floor, never the cluster's proxy.
#[test]
fn events_name_the_member_hit() {
    let (mut world, blocks) = thrown_t(true, DROP);
    world.condense(&blocks).unwrap();
    let proxies: Vec<usize> = (0..world.bodies().len()).filter(|&k| world.bodies()[k].is_cluster_proxy()).collect();
    assert_eq!(proxies.len(), 1);
    let mut seen = Vec::new();
    for _ in 0..120 {
        for event in world.step().events {
            assert!(!proxies.contains(&event.a) && !proxies.contains(&event.b), "{event:?}");
            assert!(event.a < event.b);
            seen.push((event.a, event.b));
        }
    }
    assert!(!seen.is_empty(), "the T never hit the floor");
    assert!(seen.iter().all(|&(a, b)| a == 0 && blocks.contains(&b)), "{seen:?}");
}

/// A cluster hanging on a ball joint from a static hook (the joint moves to the proxy while
/// condensed) swings like the jointed pair; uncondensed halfway, the pair goes on with the
/// cluster's motion and its own joints. The tip's path agrees within 1 cm over 2 s (swing
/// speed about 3 m/s; a joint left on the idle member would drop the cluster 20 m in 2 s).
#[test]
fn a_cluster_swings_on_a_joint_and_comes_apart_with_its_motion() {
    let build = || {
        let settings = WorldSettings { sleep_time: 0.0, angular_damping: 0.0, ..Default::default() };
        let mut world = World::new(settings).unwrap();
        let hook = block("hook", Vec3::splat(0.1), Vec3::new(0.0, 2.0, 0.0)).kind(BodyKind::Static);
        let hook = world.add(hook).unwrap();
        let arm = world.add(block("arm", Vec3::new(0.6, 0.1, 0.1), Vec3::new(0.3, 2.0, 0.0))).unwrap();
        let tip = world.add(block("tip", Vec3::new(0.1, 0.4, 0.1), Vec3::new(0.65, 1.85, 0.0))).unwrap();
        world.add_joint(hook, arm, Vec3::new(0.0, 2.0, 0.0), JointKind::Ball).unwrap();
        world.add_joint(arm, tip, Vec3::new(0.6, 2.0, 0.0), JointKind::Rigid).unwrap();
        (world, [arm, tip])
    };
    let (mut jointed, pair) = build();
    let (mut condensed, _) = build();
    let id = condensed.condense(&pair).unwrap();
    let ends = |w: &World| w.joints().iter().map(|j| (j.a(), j.b())).collect::<Vec<_>>();
    assert_ne!(ends(&condensed), ends(&jointed), "the hook's joint moves to the proxy");
    let mut worst = 0.0f32;
    for step in 0..120 {
        if step == 60 {
            condensed.uncondense(id).unwrap();
            assert_eq!(ends(&condensed), ends(&jointed), "joints go back to their members");
            assert!(!condensed.bodies()[pair[1]].is_condensed());
        }
        jointed.step();
        condensed.step();
        worst = worst.max(largest_gap(&jointed, &condensed, &pair[1..]));
    }
    assert!(worst < 0.01, "the tip's paths differ by up to {worst} m");
}

/// Condensing, dissolving and condensing again reuses the proxy: the world does not grow.
/// A snapshot taken before a condensation cannot be restored after it.
#[test]
fn proxies_are_reused_and_snapshots_keep_to_their_layout() {
    let (mut world, blocks) = thrown_t(false, THROW);
    let snapshot = world.snapshot();
    let id = world.condense(&blocks).unwrap();
    let count = world.bodies().len();
    assert_eq!(count, blocks.len() + 1);
    assert!(world.restore(&snapshot).is_err());
    world.step();
    world.uncondense(id).unwrap();
    assert_eq!(world.clusters(), Vec::<usize>::new());
    world.step();
    let again = world.condense(&blocks[..2]).unwrap();
    assert_eq!(world.bodies().len(), count);
    assert_eq!(world.cluster_of(blocks[0]), Some(again));
    assert_eq!(world.cluster_of(blocks[2]), None);
}

/// Bad clusters are refused and leave the world as it was.
#[test]
fn bad_clusters_are_refused() {
    let (mut world, blocks) = thrown_t(true, DROP);
    let dentable =
        block("soft", Vec3::splat(0.2), Vec3::new(2.0, 1.0, 0.0)).dentable(DentSettings::new(1.0, 0.01, 0.05));
    let soft = world.add(dentable).unwrap();
    let before = world.bodies().len();
    let cases: Vec<(Vec<usize>, &str)> = vec![
        (vec![blocks[0]], "at least two"),
        (vec![blocks[0], blocks[0]], "twice"),
        (vec![blocks[0], 99], "not a body"),
        (vec![0, blocks[0]], "not dynamic"),
        (vec![blocks[0], soft], "dentable"),
    ];
    for (members, why) in cases {
        let error = world.condense(&members).unwrap_err().to_string();
        assert!(error.contains(why), "{members:?}: {error}");
        assert_eq!(world.bodies().len(), before);
        assert!(world.clusters().is_empty());
    }
    let id = world.condense(&blocks[..2]).unwrap();
    assert!(world.condense(&[blocks[1], blocks[2]]).unwrap_err().to_string().contains("already condensed"));
    assert!(world.uncondense(id + 1).is_err());
    let desc = block("late", Vec3::splat(0.1), Vec3::ZERO);
    assert!(world.rebuild_body(blocks[0], desc).is_err(), "a member cannot be rebuilt");
    assert!(world.add_joint(blocks[0], blocks[2], Vec3::ZERO, JointKind::Ball).is_err());
}
