//! Bending bodies in a world: the skinned mesh at rest, an elastic joint that springs back, joints
//! given their own kind, and clear errors (never panics) for bad bending descriptions.

use dentbend::bend::JointRule;
use dentbend::bend::{BoneDesc, WeightParams};
use dentbend::glam::Vec3;
use dentbend_solver::coupling::Simulation;
use dentbend_solver::coupling::{BendableDesc, Bending, DynamicArticulation, JointOverride, SkeletonSpec};
use dentbend_solver::scene::{SceneSize, builtin_scene};
use dentbend_solver::sim::{JointKind, World, WorldSettings};

/// A 2 × 0.2 × 0.2 m bar with a coarse level set (32 cells along it) so debug builds stay fast.
fn bar() -> BendableDesc {
    let mut desc = BendableDesc::new("bar", dentbend::mesh::plank(2.0, 0.2, 0.2, 16).unwrap());
    desc.skeleton = SkeletonSpec::Auto { bones: 2 };
    desc.weights = WeightParams { resolution: 32, ..WeightParams::default() };
    desc.joint = JointKind::Bend(JointRule::Elastic { stiffness: 100.0, damping: 3.0 });
    desc
}

fn empty_world() -> World {
    World::new(WorldSettings { gravity: Vec3::ZERO, ..WorldSettings::default() }).unwrap()
}

#[test]
fn the_skinned_mesh_is_the_rest_mesh_before_anything_moves() {
    // At the origin with no rotation every bone transform is the identity (translation c − c
    // is exactly zero), so each skinned vertex is Σ wᵢ·p: equal to p up to the f32 rounding of a
    // weight sum of 1 (a few ulps: 1e-6 of the 1 m half-length).
    let mut world = empty_world();
    let mut bending = Bending::new();
    bending.add(&mut world, bar()).unwrap();
    let body = &bending.bodies()[0];
    assert_eq!(body.body_indices().len(), 2);
    assert_eq!(world.bodies()[body.body_indices()[1]].name, "bar/bone1");
    assert_eq!(world.joints().len(), 1);
    let skinned = body.skinned_mesh(&world).unwrap();
    let worst = skinned
        .positions()
        .iter()
        .zip(body.rest_mesh().positions())
        .map(|(a, b)| a.distance(*b))
        .fold(0.0f32, f32::max);
    assert!(worst <= 1e-6, "skinned mesh moved {worst} m at rest");
    // The sub-bodies' masses add up to the bar's: 2 × 0.2 × 0.2 m × 1000 kg/m³ = 80 kg (the
    // voxel shares are scaled to the mesh's exact mass; 1 % for f32 sums).
    let mass: f32 = body.body_indices().iter().map(|&i| world.bodies()[i].mass).sum();
    assert!((mass - 80.0).abs() < 0.8, "mass {mass}");
}

#[test]
fn the_spring_scene_springs_back_to_its_rest_angle() {
    // A ball hits one end of the floating elastic bar at 4 m/s: the joint bends (peak > 2°)
    // and the damped spring (ζ ≈ 0.14, about 1.5 Hz) brings it back: after 3 s the angle is
    // below 10 % of the peak (the analytic decay is e^(−ζω·t) ≈ 0.02 of it).
    let scene = builtin_scene("spring", SceneSize::Demo).unwrap();
    let mut sim = Simulation::new(scene.world, None).unwrap().with_bending(scene.bending);
    let angle = |sim: &Simulation| {
        let joint = &sim.world().joints()[0];
        joint.deviation(sim.world().bodies()).unwrap().length().to_degrees()
    };
    let mut peak = 0.0f32;
    for _ in 0..180 {
        sim.step().unwrap();
        peak = peak.max(angle(&sim));
    }
    let last = angle(&sim);
    println!("peak {peak:.2}°, after 3 s {last:.3}°");
    assert!(peak > 2.0, "peak bend {peak}°");
    assert!(last < 0.1 * peak, "still bent {last}° of a {peak}° peak");
}

fn refused(desc: BendableDesc, what: &str) {
    let mut world = empty_world();
    let error = Bending::new().add(&mut world, desc).expect_err(what);
    println!("{what}: {error}");
    assert!(world.bodies().is_empty(), "{what}: the world changed");
}

#[test]
fn bad_bending_descriptions_are_refused_with_errors() {
    let bones = |list: Vec<BoneDesc>| SkeletonSpec::Bones(list);
    let x = |a: f32, b: f32, parent| BoneDesc::new(Vec3::X * a, Vec3::X * b, parent);
    refused(BendableDesc { skeleton: bones(vec![x(f32::NAN, 0.5, None)]), ..bar() }, "NaN bone");
    refused(BendableDesc { skeleton: bones(vec![x(0.2, 0.2, None)]), ..bar() }, "zero-length bone");
    let outside = BoneDesc::new(Vec3::new(0.0, 3.0, 0.0), Vec3::new(1.0, 3.0, 0.0), None);
    refused(BendableDesc { skeleton: bones(vec![outside]), ..bar() }, "bone outside the mesh");
    refused(BendableDesc { skeleton: bones(vec![x(-0.8, 0.0, Some(1)), x(0.0, 0.8, Some(0))]), ..bar() }, "cycle");
    refused(BendableDesc { skeleton: bones(vec![]), ..bar() }, "no bones");
    refused(BendableDesc { skeleton: SkeletonSpec::Auto { bones: 0 }, ..bar() }, "zero auto bones");
    refused(BendableDesc { density: -1.0, ..bar() }, "negative density");
    refused(BendableDesc { position: Vec3::NAN, ..bar() }, "NaN position");
    refused(BendableDesc { name: String::new(), ..bar() }, "empty name");
    refused(BendableDesc { weights: WeightParams { resolution: 1, ..WeightParams::default() }, ..bar() }, "resolution");
    refused(
        BendableDesc { joint: JointKind::Bend(JointRule::Elastic { stiffness: -1.0, damping: 0.0 }), ..bar() },
        "bad joint",
    );
    let dynamic = |threshold, length| Some(DynamicArticulation::new(threshold, JointKind::Rigid, length));
    refused(BendableDesc { dynamic: dynamic(f32::NAN, 0.1), ..bar() }, "NaN threshold");
    refused(BendableDesc { dynamic: dynamic(1.0, 0.0), ..bar() }, "zero minimum bone length");
    // A name taken twice.
    let mut world = empty_world();
    let mut bending = Bending::new();
    bending.add(&mut world, bar()).unwrap();
    let count = world.bodies().len();
    assert!(bending.add(&mut world, bar()).is_err());
    assert_eq!(world.bodies().len(), count);
}

/// Joint overrides give single joints their own kind (by child bone; the rest keep the body's),
/// and bad ones are refused with an error naming the override, before the world changes: a
/// child out of range, the root bone (it hangs from no joint), a joint given twice, and bad
/// numbers.
#[test]
fn joint_overrides_give_single_joints_their_own_kind() {
    let plastic =
        JointKind::Bend(JointRule::Plastic { strength: 2.0, damping_constant: 0.5, damping_proportional: 4.0 });
    let three = |overrides: Vec<JointOverride>| BendableDesc {
        skeleton: SkeletonSpec::Auto { bones: 3 },
        joint: JointKind::Rigid,
        joint_overrides: overrides,
        ..bar()
    };
    let mut world = empty_world();
    let mut bending = Bending::new();
    bending.add(&mut world, three(vec![JointOverride { child: 2, joint: plastic }])).unwrap();
    let bones = bending.bodies()[0].body_indices().to_vec();
    let kind_at = |child: usize| *world.joints().iter().find(|j| j.b() == bones[child]).unwrap().kind();
    assert_eq!((kind_at(1), kind_at(2)), (JointKind::Rigid, plastic));

    let refused_with = |overrides: Vec<JointOverride>, words: &[&str]| {
        let mut world = empty_world();
        let message = Bending::new().add(&mut world, three(overrides.clone())).expect_err("accepted").to_string();
        println!("{overrides:?}: {message}");
        assert!(world.bodies().is_empty() && world.joints().is_empty(), "{message}: the world changed");
        for word in words {
            assert!(message.contains(word), "no \"{word}\" in {message}");
        }
    };
    let at = |child: usize, joint: JointKind| JointOverride { child, joint };
    refused_with(vec![at(1, plastic), at(3, plastic)], &["joint_overrides[1].child", "3 (of 3 bones)", "not a bone"]);
    refused_with(vec![at(usize::MAX, JointKind::Ball)], &["joint_overrides[0].child", "not a bone"]);
    refused_with(vec![at(0, JointKind::Ball)], &["joint_overrides[0].child", "root bone"]);
    refused_with(vec![at(2, JointKind::Ball), at(2, plastic)], &["joint_overrides[1].child", "second kind"]);
    let nan =
        JointKind::Bend(JointRule::Plastic { strength: f32::NAN, damping_constant: 0.5, damping_proportional: 4.0 });
    refused_with(vec![at(1, nan)], &["joint_overrides[0].joint.strength", "NaN"]);
    let negative = JointKind::Bend(JointRule::Elastic { stiffness: 10.0, damping: -1.0 });
    refused_with(vec![at(2, negative)], &["joint_overrides[0].joint.damping", "-1"]);
}
