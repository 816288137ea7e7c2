//! Condensation of articulated bodies (paper §4.2): a quiet body is simulated as one rigid
//! cluster and moves like the same body with rigid joints; a hit dissolves the cluster, the
//! bodies on either side of the joint that bends collapse into two clusters while it bends, and
//! the whole body condenses again once it is quiet, keeping its bend.

use dentbend::bend::JointRule;
use dentbend::bend::WeightParams;
use dentbend::glam::{Affine3A, Vec3};
use dentbend::mesh;
use dentbend_solver::coupling::{BendableDesc, Bending, CondenseSettings, SkeletonSpec};
use dentbend_solver::sim::{BodyDesc, ColliderKind, JointKind, SurfaceMaterial, World, WorldSettings};

/// A 2.4 × 0.2 × 0.2 m bar along x with six bones, thrown spinning about z (a principal axis),
/// without gravity or angular damping (see solver/tests/sim_condense.rs for why).
fn thrown_bar(joint: JointKind) -> (World, Bending) {
    let settings = WorldSettings { gravity: Vec3::ZERO, angular_damping: 0.0, sleep_time: 0.0, ..Default::default() };
    let mut world = World::new(settings).unwrap();
    let mut desc = BendableDesc::new("bar", mesh::plank(2.4, 0.2, 0.2, 24).unwrap());
    desc.skeleton = SkeletonSpec::Auto { bones: 6 };
    desc.weights = WeightParams { resolution: 48, ..WeightParams::default() };
    desc.joint = joint;
    desc.linear_velocity = Vec3::new(1.0, 0.5, 0.0);
    desc.angular_velocity = Vec3::new(0.0, 0.0, 1.5);
    let mut bending = Bending::new();
    bending.add(&mut world, desc).unwrap();
    (world, bending)
}

fn bones(world: &World, bending: &Bending) -> Vec<Affine3A> {
    bending.bodies()[0].bone_transforms(world).unwrap()
}

/// Condensed, the six-bone bar with rigid joints becomes one cluster once its joints have been
/// quiet for `quiet_time` (0.1 s = 6 steps), and over 1 s its skinned mesh follows the
/// uncondensed bar's within 2 cm. The difference is the jointed bar's: its spin bleeds 1.8 % in
/// the second through its five joints' first-order velocity projections (measured: 1.5 →
/// 1.474 rad/s, while the cluster keeps 1.497, having bled only in its first 7 jointed steps),
/// a lag of about 0.011 rad, 1.4 cm at the bar's ends 1.2 m from the centre (measured 1.25
/// cm). A cluster with a wrong inertia, lost spin or bones frozen in the wrong place is off by
/// decimetres.
#[test]
fn a_condensed_body_moves_like_the_same_body_with_rigid_joints() {
    let (mut plain_world, mut plain) = thrown_bar(JointKind::Rigid);
    let (mut world, mut condensed) = thrown_bar(JointKind::Rigid);
    condensed.condense(CondenseSettings::default()).unwrap();
    let mut clustered_from = None;
    for step in 1..=60 {
        plain.step(&mut plain_world).unwrap();
        condensed.step(&mut world).unwrap();
        if clustered_from.is_none() && !world.clusters().is_empty() {
            clustered_from = Some(step);
        }
    }
    assert!(clustered_from.is_some_and(|s| s <= 8), "condensed from step {clustered_from:?}");
    assert_eq!(world.clusters().len(), 1);
    let members = world.cluster_members(world.clusters()[0]).unwrap();
    assert_eq!(members.len(), 6, "all six bones in the cluster");
    let a = plain.bodies()[0].skinned_mesh(&plain_world).unwrap();
    let b = condensed.bodies()[0].skinned_mesh(&world).unwrap();
    let worst = a.positions().iter().zip(b.positions()).map(|(p, q)| p.distance(*q)).fold(0.0f32, f32::max);
    assert!(worst < 0.02, "skinned meshes differ by {worst} m");
    let spin = |w: &World, b: &Bending| w.bodies()[b.bodies()[0].body_indices()[0]].angular_velocity.z;
    assert!((spin(&world, &condensed) - 1.5).abs() < 0.005 * 1.5, "cluster spin {}", spin(&world, &condensed));
    // The bones stay where the rigid bar holds them relative to each other.
    let (ta, tb) = (bones(&plain_world, &plain), bones(&world, &condensed));
    let relative = |t: &[Affine3A]| t[0].inverse() * t[5];
    assert!(relative(&ta).translation.distance(relative(&tb).translation) < 1e-3);
}

/// A floating six-bone bar with plastic joints (strength 10 N·m·s) is condensed; a 30 kg ball
/// hits it at 6 m/s at its middle joint, between bones 2 and 3. The hit dissolves the cluster;
/// only the middle joint carries more than its strength (the bending moment of a free bar
/// under a central blow falls off as (L/2 − x)², so the next joints get under half of it) and
/// bends; from the quiet time on, while it keeps bending, the bones on either side of it are
/// two clusters of three. Once the bend has died out the whole bar is one cluster again and
/// keeps its bend.
#[test]
fn a_hit_uncondenses_and_each_side_of_the_bending_joint_collapses() {
    let joint =
        JointKind::Bend(JointRule::Plastic { strength: 10.0, damping_constant: 0.5, damping_proportional: 2.0 });
    let (mut world, mut bending) = thrown_bar(joint);
    for body in world.bodies_mut() {
        body.linear_velocity = Vec3::ZERO;
        body.angular_velocity = Vec3::ZERO;
    }
    bending.condense(CondenseSettings::default()).unwrap();
    for _ in 0..10 {
        bending.step(&mut world).unwrap();
    }
    assert_eq!(world.clusters().len(), 1, "the quiet bar condenses");
    let ball = mesh::icosphere(0.15, 2).unwrap();
    let density = 30.0 / ball.volume();
    let desc = BodyDesc::new("ball", ball).at(Vec3::new(0.0, 0.5, 0.0)).velocity(Vec3::new(0.0, -6.0, 0.0));
    let surface = SurfaceMaterial { restitution: 0.0, friction: 0.3 };
    world.add(BodyDesc { density, surface, ..desc.collider(ColliderKind::Ball) }).unwrap();
    let bones = bending.bodies()[0].body_indices().to_vec();
    let middle = world.joints().iter().position(|j| j.a() == bones[2] && j.b() == bones[3]).unwrap();
    let mut saw_two = false;
    for _ in 0..120 {
        bending.step(&mut world).unwrap();
        let clusters = world.clusters();
        if clusters.len() == 2 && world.joints()[middle].is_bending() {
            let mut sides: Vec<Vec<usize>> = clusters.iter().map(|&c| world.cluster_members(c).unwrap()).collect();
            sides.iter_mut().for_each(|s| s.sort_unstable());
            sides.sort();
            assert_eq!(sides, vec![bones[..3].to_vec(), bones[3..].to_vec()], "clusters while bending");
            saw_two = true;
        }
    }
    assert!(saw_two, "never saw the two sides condensed while the middle joint bent");
    assert!(!bending.bends().is_empty() && bending.bends().iter().all(|b| b.joint == middle), "{:?}", bending.bends());
    let bend = world.joints()[middle].bend_angle().to_degrees();
    assert!(bend > 5.0, "net bend {bend}°");
    assert_eq!(world.clusters().len(), 1, "quiet again: one cluster");
    assert_eq!(world.cluster_members(world.clusters()[0]).unwrap().len(), 6);
    // Condensed, the bar keeps its bent shape.
    let angle_now = world.joints()[middle].deviation(world.bodies()).unwrap().length().to_degrees();
    assert!(angle_now < 0.5, "the middle joint is {angle_now}° off its bent target");
}

/// Bad condensation settings are refused.
#[test]
fn bad_condensation_settings_are_refused() {
    let mut bending = Bending::new();
    for bad in [
        CondenseSettings { wake_speed: f32::NAN, ..Default::default() },
        CondenseSettings { quiet_time: -1.0, ..Default::default() },
        CondenseSettings { quiet_spin: 0.0, ..Default::default() },
        CondenseSettings { quiet_deflection: f32::INFINITY, ..Default::default() },
    ] {
        assert!(bending.condense(bad).is_err(), "{bad:?}");
    }
    assert_eq!(bending.condensation(), None);
}
