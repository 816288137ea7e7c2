//! Skeletons: validation with clear errors, the check against a mesh (a bone may poke out but not
//! float beside the body), bone splits and the automatic chain along the principal axis.

use dentbend::bend::{BendError, BoneDesc, Skeleton, auto_skeleton};
use dentbend::glam::Vec3;
use dentbend::mesh;

fn bone(head: [f32; 3], tail: [f32; 3], parent: Option<usize>) -> BoneDesc {
    BoneDesc::new(Vec3::from_array(head), Vec3::from_array(tail), parent)
}

/// A 4-bone chain along x from −4 to 4.
fn chain() -> Skeleton {
    Skeleton::new(
        (0..4usize)
            .map(|i| bone([i as f32 * 2.0 - 4.0, 0.0, 0.0], [i as f32 * 2.0 - 2.0, 0.0, 0.0], i.checked_sub(1)))
            .collect(),
    )
    .unwrap()
}

/// The error of `Skeleton::new(bones)` and its message, failing if it succeeds.
fn error_of(bones: Vec<BoneDesc>) -> (BendError, String) {
    let error = Skeleton::new(bones).expect_err("the skeleton should be refused");
    let message = error.to_string();
    (error, message)
}

#[test]
fn valid_tree_has_joints_at_child_heads() {
    let s = Skeleton::new(vec![
        bone([0.0, 0.0, 0.0], [0.0, 2.0, 0.0], None),
        bone([0.0, 2.0, 0.0], [1.0, 3.0, 0.0], Some(0)),
        bone([0.0, 1.9, 0.0], [-1.0, 3.0, 0.0], Some(0)),
    ])
    .unwrap();
    assert_eq!(s.len(), 3);
    assert_eq!(s.root(), 0);
    assert_eq!(s.children(0), vec![1, 2]);
    let joints = s.joints();
    assert_eq!(joints.len(), 2);
    assert_eq!((joints[1].parent, joints[1].child, joints[1].point), (0, 2, Vec3::new(0.0, 1.9, 0.0)));
}

#[test]
fn non_finite_coordinates_are_refused() {
    let (e, message) =
        error_of(vec![bone([0.0; 3], [1.0, 0.0, 0.0], None), bone([1.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], Some(0))]);
    assert!(matches!(e, BendError::NonFiniteBone { bone: 1, end: "tail", .. }), "{e:?}");
    assert!(message.contains("bone 1") && message.contains("tail"), "{message}");
    let (e, _) = error_of(vec![bone([f32::INFINITY, 0.0, 0.0], [1.0, 0.0, 0.0], None)]);
    assert!(matches!(e, BendError::NonFiniteBone { bone: 0, end: "head", .. }), "{e:?}");
}

#[test]
fn zero_length_bone_is_refused() {
    let (e, message) =
        error_of(vec![bone([0.0; 3], [4.0, 0.0, 0.0], None), bone([4.0, 0.0, 0.0], [4.0, 0.0, 0.0], Some(0))]);
    assert!(matches!(e, BendError::ZeroLengthBone { bone: 1, .. }), "{e:?}");
    assert!(message.contains("bone 1") && message.contains("length"), "{message}");
    // Relative to the skeleton's extent: 1e-7 of a 4 m skeleton is too short too.
    let (e, _) =
        error_of(vec![bone([0.0; 3], [4.0, 0.0, 0.0], None), bone([4.0, 0.0, 0.0], [4.0, 4e-7, 0.0], Some(0))]);
    assert!(matches!(e, BendError::ZeroLengthBone { bone: 1, .. }), "{e:?}");
    // A single short bone alone is fine (its own extent is its scale) unless it is degenerate.
    assert!(Skeleton::new(vec![bone([0.0; 3], [1e-4, 0.0, 0.0], None)]).is_ok());
    assert!(matches!(error_of(vec![bone([1.0; 3], [1.0; 3], None)]).0, BendError::ZeroLengthBone { bone: 0, .. }));
}

#[test]
fn parent_out_of_range_is_refused() {
    let (e, message) =
        error_of(vec![bone([0.0; 3], [1.0, 0.0, 0.0], None), bone([1.0, 0.0, 0.0], [2.0, 0.0, 0.0], Some(5))]);
    assert!(matches!(e, BendError::ParentOutOfRange { bone: 1, parent: 5, count: 2 }), "{e:?}");
    assert!(message.contains("bone 1") && message.contains("parent index 5"), "{message}");
}

#[test]
fn cycles_are_refused() {
    // 0 is a root; 1 → 2 → 3 → 1 is a cycle.
    let (e, message) = error_of(vec![
        bone([0.0; 3], [1.0, 0.0, 0.0], None),
        bone([1.0, 0.0, 0.0], [2.0, 0.0, 0.0], Some(3)),
        bone([2.0, 0.0, 0.0], [3.0, 0.0, 0.0], Some(1)),
        bone([3.0, 0.0, 0.0], [4.0, 0.0, 0.0], Some(2)),
    ]);
    match &e {
        BendError::Cycle { cycle, .. } => {
            let mut sorted = cycle.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, vec![1, 2, 3]);
        }
        other => panic!("expected a cycle, got {other:?}"),
    }
    assert!(message.contains("cycle") && message.contains("→"), "{message}");
    // A bone that is its own parent.
    let (e, _) = error_of(vec![bone([0.0; 3], [1.0, 0.0, 0.0], Some(0))]);
    assert!(matches!(e, BendError::Cycle { bone: 0, .. }), "{e:?}");
}

#[test]
fn forests_and_detached_joints_are_refused() {
    let (e, message) =
        error_of(vec![bone([0.0; 3], [1.0, 0.0, 0.0], None), bone([5.0, 0.0, 0.0], [6.0, 0.0, 0.0], None)]);
    assert!(matches!(&e, BendError::MultipleRoots { roots } if roots == &[0, 1]), "{e:?}");
    assert!(message.contains("2 roots"), "{message}");
    // Child head 1 m from a parent bone, child 1 m long: more than half its length away.
    let (e, message) =
        error_of(vec![bone([0.0; 3], [1.0, 0.0, 0.0], None), bone([1.0, 1.0, 0.0], [1.0, 2.0, 0.0], Some(0))]);
    assert!(matches!(e, BendError::DetachedJoint { bone: 1, parent: 0, .. }), "{e:?}");
    assert!(message.contains("bone 1"), "{message}");
    assert!(matches!(Skeleton::new(Vec::new()), Err(BendError::NoBones)));
}

#[test]
fn bone_floating_outside_the_mesh_is_refused() {
    let cube = mesh::subdivided_box(Vec3::splat(2.0), [4, 4, 4]).unwrap();
    let outside = Skeleton::new(vec![bone([3.0, 0.0, 0.0], [5.0, 0.0, 0.0], None)]).unwrap();
    match outside.check_against(&cube) {
        Err(BendError::BoneOutsideMesh { bone: 0, distance, tolerance }) => {
            assert!((distance - 2.0).abs() < 1e-4, "distance {distance}");
            assert!(tolerance > 0.0 && tolerance < 0.1);
        }
        other => panic!("expected BoneOutsideMesh, got {other:?}"),
    }
    let message = outside.check_against(&cube).unwrap_err().to_string();
    assert!(message.contains("bone 0") && message.contains("outside"), "{message}");
    // The same bone with a tolerance beyond its 2 m gap passes.
    assert!(outside.check_against_with(&cube, 2.5).is_ok());
    assert!(matches!(outside.check_against_with(&cube, f32::NAN), Err(BendError::InvalidParameter { .. })));
}

#[test]
fn bones_inside_poking_out_or_touching_pass() {
    let cube = mesh::subdivided_box(Vec3::splat(2.0), [4, 4, 4]).unwrap();
    let s = Skeleton::new(vec![
        bone([-0.5, 0.0, 0.0], [0.5, 0.0, 0.0], None),      // inside
        bone([0.5, 0.0, 0.0], [0.5, 3.0, 0.0], Some(0)),    // pokes out through the top
        bone([-0.5, 0.0, 0.0], [-1.02, 0.0, 0.6], Some(0)), // ends just outside a side
    ])
    .unwrap();
    s.check_against(&cube).unwrap();
    // Wholly outside but within the 2 % tolerance (cube diagonal 3.46 m → 0.069 m).
    let grazing = Skeleton::new(vec![bone([1.05, -0.5, 0.0], [1.05, 0.5, 0.0], None)]).unwrap();
    grazing.check_against(&cube).unwrap();
}

#[test]
fn split_projects_the_point_and_reparents_children() {
    let mut s = chain();
    let before = s.clone();
    // Bone 1 runs from x = −2 to 0; the point is off the axis above x = −0.5.
    let (first, second) = s.split_bone(1, Vec3::new(-0.5, 0.7, -0.3)).unwrap();
    assert_eq!((first, second), (1, 4));
    let bones = s.bones();
    assert_eq!(bones[1].head, Vec3::new(-2.0, 0.0, 0.0));
    assert!((bones[1].tail - Vec3::new(-0.5, 0.0, 0.0)).length() < 1e-6, "{:?}", bones[1].tail);
    assert_eq!((bones[4].head, bones[4].tail, bones[4].parent), (bones[1].tail, Vec3::ZERO, Some(1)));
    // Bone 2 hung from bone 1's tail: it now hangs from the second half. Others unchanged.
    assert_eq!(bones[2].parent, Some(4));
    assert_eq!(bones[1].parent, Some(0));
    for i in [0, 3] {
        assert_eq!(bones[i], before.bones()[i]);
    }
    assert_eq!(s.joints().len(), 4);
}

#[test]
fn split_keeps_children_near_the_head_on_the_first_half() {
    let mut s = Skeleton::new(vec![
        bone([0.0; 3], [4.0, 0.0, 0.0], None),
        bone([1.0, 0.0, 0.0], [1.0, 1.0, 0.0], Some(0)),
        bone([3.0, 0.0, 0.0], [3.0, 1.0, 0.0], Some(0)),
    ])
    .unwrap();
    let (a, b) = s.split_bone(0, Vec3::new(2.0, 0.0, 0.0)).unwrap();
    assert_eq!(s.bones()[1].parent, Some(a));
    assert_eq!(s.bones()[2].parent, Some(b));
}

#[test]
fn split_near_an_end_or_with_bad_input_fails_and_changes_nothing() {
    let mut s = chain();
    let before = s.clone();
    for point in [Vec3::new(-3.95, 0.0, 0.0), Vec3::new(-2.04, 1.0, 0.0), Vec3::new(-6.0, 0.0, 0.0)] {
        match s.split_bone(0, point) {
            Err(BendError::SplitNearEnd { bone: 0, t, .. }) => assert!(!(0.05..=0.95).contains(&t), "t {t}"),
            other => panic!("{point}: expected SplitNearEnd, got {other:?}"),
        }
    }
    let message = s.split_bone(0, Vec3::new(-3.99, 0.0, 0.0)).unwrap_err().to_string();
    assert!(message.contains("bone 0"), "{message}");
    assert!(matches!(s.split_bone(9, Vec3::ZERO), Err(BendError::BoneOutOfRange { bone: 9, count: 4 })));
    assert!(matches!(s.split_bone(0, Vec3::NAN), Err(BendError::InvalidParameter { .. })));
    assert_eq!(s, before);
}

#[test]
fn nearest_bone_finds_the_hit_bone() {
    let s = chain();
    let (bone, t, distance) = s.nearest_bone(Vec3::new(1.5, 0.3, 0.0)).unwrap();
    assert_eq!(bone, 2);
    assert!((t - 0.75).abs() < 1e-6 && (distance - 0.3).abs() < 1e-6);
    assert!(s.nearest_bone(Vec3::NAN).is_none());
}

#[test]
fn scene_file_bones_round_trip() {
    #[derive(serde::Deserialize)]
    struct Body {
        bones: Skeleton,
    }
    #[derive(serde::Deserialize)]
    struct Scene {
        body: Body,
    }
    let text = "[[body.bones]]\nhead = [0, 0, 0]\ntail = [1, 0, 0]\n\n[[body.bones]]\nhead = [1, 0, 0]\ntail = [2, 0.5, 0]\nparent = 0\n";
    let scene: Scene = toml::from_str(text).unwrap();
    assert_eq!(scene.body.bones.len(), 2);
    assert_eq!(scene.body.bones.bones()[1].tail, Vec3::new(2.0, 0.5, 0.0));
    let json = serde_json::to_string(&scene.body.bones).unwrap();
    let back: Skeleton = serde_json::from_str(&json).unwrap();
    assert_eq!(back, scene.body.bones);
    // Validation runs on deserialisation too.
    let bad = "[[body.bones]]\nhead = [0, 0, 0]\ntail = [1, 0, 0]\nparent = 3\n";
    let error = toml::from_str::<Scene>(bad).err().expect("parent 3 is out of range").to_string();
    assert!(error.contains("parent index 3"), "{error}");
}

#[test]
fn auto_skeleton_follows_the_long_axis() {
    // Plank: 8 along x, 0.25 along y, 0.5 along z.
    let plank = mesh::plank(8.0, 0.5, 0.25, 32).unwrap();
    let s = auto_skeleton(&plank, 3).unwrap();
    assert_eq!(s.len(), 3);
    let (first, last) = (&s.bones()[0], &s.bones()[2]);
    // Inset 5 % of 8 at each end: the chain spans x = −3.6 … 3.6 on the axis.
    assert!((first.head - Vec3::new(-3.6, 0.0, 0.0)).length() < 1e-3, "{}", first.head);
    assert!((last.tail - Vec3::new(3.6, 0.0, 0.0)).length() < 1e-3, "{}", last.tail);
    assert_eq!(s.bones()[1].parent, Some(0));
    s.check_against(&plank).unwrap();
    // A cylinder along y, shifted: the axis follows the solid.
    let mut tube = mesh::cylinder(0.5, 6.0, 16, 8).unwrap();
    tube.transform(dentbend::glam::Affine3A::from_translation(Vec3::new(1.0, 2.0, 3.0))).unwrap();
    let s = auto_skeleton(&tube, 1).unwrap();
    let b = &s.bones()[0];
    assert!(b.direction().dot(Vec3::Y) > 0.9999, "{}", b.direction());
    assert!((b.point_at(0.5) - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-3);
    assert!(matches!(auto_skeleton(&plank, 0), Err(BendError::InvalidParameter { name: "bones", .. })));
}
