//! Bending bodies in scene files (`[body.bend]`): a given skeleton builds exactly those bones in
//! the scaled model frame, the automatic skeleton, every joint kind with its numbers, dynamic
//! articulation, and the example `scenes/bent_bar.toml` running with its joints bending.

use std::path::{Path, PathBuf};

use dentbend::bend::JointRule;
use dentbend::bend::{BoneDesc, auto_skeleton};
use dentbend::glam::{Affine3A, Quat, Vec3};
use dentbend_solver::coupling::{ArticulatedBody, DynamicArticulation};
use dentbend_solver::scene::{Scene, load_scene, parse_scene};
use dentbend_solver::sim::JointKind;

/// A 4 × 0.5 × 0.5 m bar (the 2 m `box` scaled by [2, 0.25, 0.25]) at rest without gravity,
/// with `body` lines after its scale and `bend` lines in its `[body.bend]` table (level set 32
/// cells long: 4 cells across the bar).
fn bar(body: &str, bend: &str) -> String {
    format!(
        "frames = 10\n[world]\ngravity = [0, 0, 0]\n\n[[body]]\nname = \"bar\"\nmesh = \"box\"\n\
         scale = [2.0, 0.25, 0.25]\n{body}\n[body.bend]\nresolution = 32\n{bend}\n"
    )
}

fn parse(text: &str) -> Scene {
    parse_scene(text, Path::new("bar.toml")).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn bending_body<'a>(scene: &'a Scene, name: &str) -> &'a ArticulatedBody {
    scene.bending.find(name).unwrap_or_else(|| panic!("no bending body \"{name}\""))
}

/// A file of the repository (the solver crate's parent folder).
fn repo_file(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(relative)
}

/// Three bones in a tree rooted at the middle one. Bone 1 lies wholly beyond x = 1, outside the
/// unscaled 2 m box by 0.2 m (more than its 0.07 m tolerance): it is accepted only because bones
/// are read in the frame after `scale`. The body's pose, velocity and material reach every
/// sub-body.
#[test]
fn a_given_skeleton_builds_those_bones() {
    let body = "position = [1.0, 2.0, 3.0]\nrotation = [0.0, 90.0, 0.0]\nvelocity = [0.5, 0.0, 0.0]\n\
                density = 500.0\nrestitution = 0.1\nfriction = 0.7\ncolor = [0.2, 0.4, 0.6]";
    let bones = "joint = { kind = \"rigid\" }\n\
                 [[body.bend.bone]]\nhead = [-1.2, 0.0, 0.0]\ntail = [1.2, 0.0, 0.0]\n\
                 [[body.bend.bone]]\nhead = [1.2, 0.0, 0.0]\ntail = [1.9, 0.0, 0.0]\nparent = 0\n\
                 [[body.bend.bone]]\nhead = [-1.2, 0.0, 0.0]\ntail = [-1.9, 0.05, 0.0]\nparent = 0\n";
    let scene = parse(&bar(body, bones));
    assert_eq!(scene.bending.bodies().len(), 1);
    let bent = bending_body(&scene, "bar");
    // The values are copied, not computed: exact equality.
    let expected = [
        BoneDesc::new(Vec3::new(-1.2, 0.0, 0.0), Vec3::new(1.2, 0.0, 0.0), None),
        BoneDesc::new(Vec3::new(1.2, 0.0, 0.0), Vec3::new(1.9, 0.0, 0.0), Some(0)),
        BoneDesc::new(Vec3::new(-1.2, 0.0, 0.0), Vec3::new(-1.9, 0.05, 0.0), Some(0)),
    ];
    assert_eq!(bent.skeleton().descs(), expected);
    let names: Vec<&str> = bent.body_indices().iter().map(|&i| scene.world.bodies()[i].name.as_str()).collect();
    assert_eq!(names, ["bar/bone0", "bar/bone1", "bar/bone2"]);
    assert!(scene.world.find("bar").is_none(), "the bending body itself is not a world body");
    let joints = scene.world.joints();
    assert_eq!(joints.len(), 2);
    assert!(joints.iter().all(|j| *j.kind() == JointKind::Rigid));

    // Model → world is the file's pose: 90° about +y, then the position (f32 rounding of ~3 m
    // values: 1e-5 m).
    let pose = Affine3A::from_rotation_translation(Quat::from_rotation_y(90f32.to_radians()), Vec3::new(1.0, 2.0, 3.0));
    for (bone, transform) in bent.skeleton().bones().iter().zip(bent.bone_transforms(&scene.world).unwrap()) {
        for p in [bone.head, bone.tail] {
            let (got, want) = (transform.transform_point3(p), pose.transform_point3(p));
            assert!(got.distance(want) < 1e-5, "{p} → {got}, expected {want}");
        }
    }
    let mut mass = 0.0;
    for &i in bent.body_indices() {
        let b = &scene.world.bodies()[i];
        assert!(b.linear_velocity.distance(Vec3::new(0.5, 0.0, 0.0)) < 1e-6, "{}", b.linear_velocity);
        assert_eq!((b.surface.restitution, b.surface.friction, b.color), (0.1, 0.7, [0.2, 0.4, 0.6]));
        mass += b.mass;
    }
    // Sub-body masses are scaled to add up to the closed mesh's exact mass: 4 × 0.5 × 0.5 m³ ×
    // 500 kg/m³ = 500 kg (to f32 sums of a few thousand triangles: 1e-4 relative).
    assert!((mass - 500.0).abs() < 0.05, "total mass {mass}");
}

/// `skeleton = "auto"` makes `bones` bones along the principal axis of the scaled mesh; `bones`
/// alone means the same, and no skeleton at all is one automatic bone.
#[test]
fn the_automatic_skeleton_has_the_bones_asked_for() {
    let mut scaled = dentbend::mesh::builtin("box").unwrap();
    scaled.transform(Affine3A::from_scale(Vec3::new(2.0, 0.25, 0.25))).unwrap();
    for (bend, count) in [("skeleton = \"auto\"\nbones = 4", 4), ("bones = 3", 3), ("", 1)] {
        let scene = parse(&bar("", bend));
        let bent = bending_body(&scene, "bar");
        let expected = auto_skeleton(&scaled, count).unwrap();
        assert_eq!(bent.skeleton(), &expected, "{bend}");
        assert_eq!(scene.world.joints().len(), count - 1);
        // Along the 4 m axis, inset 5 % at each end: the chain spans 3.6 m.
        let bones = bent.skeleton().bones();
        let span = bones[0].head.distance(bones[count - 1].tail);
        assert!((span - 3.6).abs() < 1e-3, "{bend}: chain spans {span} m");
    }
}

/// Each joint kind, inline or as a `[body.bend.joint]` table, becomes that [`JointKind`] with
/// the file's numbers, on every joint of the skeleton.
#[test]
fn every_joint_kind_is_parsed_with_its_numbers() {
    let cases = [
        ("joint = { kind = \"rigid\" }", JointKind::Rigid),
        ("joint = { kind = \"ball\" }", JointKind::Ball),
        (
            "joint = { kind = \"plastic\", strength = 40.0, damping_constant = 0.5, damping_proportional = 4.0 }",
            JointKind::Bend(JointRule::Plastic { strength: 40.0, damping_constant: 0.5, damping_proportional: 4.0 }),
        ),
        (
            "[body.bend.joint]\nkind = \"elastic\"\nstiffness = 100.0\ndamping = 3.0",
            JointKind::Bend(JointRule::Elastic { stiffness: 100.0, damping: 3.0 }),
        ),
        (
            "joint = { kind = \"elastic-prismatic\", axis = [1.0, 0.0, 0.0], stiffness = 2000.0, damping = 0.0 }",
            JointKind::ElasticPrismatic { axis: Vec3::X, stiffness: 2000.0, damping: 0.0 },
        ),
    ];
    for (joint, expected) in cases {
        let scene = parse(&bar("", &format!("bones = 3\n{joint}")));
        let kinds: Vec<JointKind> = scene.world.joints().iter().map(|j| *j.kind()).collect();
        assert_eq!(kinds, [expected; 2], "{joint}");
    }
}

/// A bone table's own `joint` makes the joint at that bone's head (where it hangs from its
/// parent) of that kind; the other joints keep `[body.bend] joint`'s (rigid by default). Both the
/// `[[body.bend.bone]]` and the inline `skeleton = [ … ]` forms.
#[test]
fn a_bones_own_joint_overrides_the_bodys() {
    let plastic =
        JointKind::Bend(JointRule::Plastic { strength: 3.0, damping_constant: 0.5, damping_proportional: 2.0 });
    let own = "joint = { kind = \"plastic\", strength = 3.0, damping_constant = 0.5, damping_proportional = 2.0 }";
    let tables = format!(
        "[[body.bend.bone]]\nhead = [-1.8, 0.0, 0.0]\ntail = [-0.6, 0.0, 0.0]\n\
         [[body.bend.bone]]\nhead = [-0.6, 0.0, 0.0]\ntail = [0.6, 0.0, 0.0]\nparent = 0\n\
         [[body.bend.bone]]\nhead = [0.6, 0.0, 0.0]\ntail = [1.8, 0.0, 0.0]\nparent = 1\n{own}\n"
    );
    let inline = format!(
        "skeleton = [{{ head = [-1.8, 0.0, 0.0], tail = [-0.6, 0.0, 0.0] }}, \
         {{ head = [-0.6, 0.0, 0.0], tail = [0.6, 0.0, 0.0], parent = 0 }}, \
         {{ head = [0.6, 0.0, 0.0], tail = [1.8, 0.0, 0.0], parent = 1, {own} }}]"
    );
    for (bend, default) in [
        (tables.clone(), JointKind::Rigid),
        (format!("joint = {{ kind = \"ball\" }}\n{tables}"), JointKind::Ball),
        (inline, JointKind::Rigid),
    ] {
        let scene = parse(&bar("", &bend));
        let bones = bending_body(&scene, "bar").body_indices().to_vec();
        let kind_at = |child: usize| {
            let joint = scene.world.joints().iter().find(|j| j.b() == bones[child]).expect("a joint at the bone");
            *joint.kind()
        };
        assert_eq!((kind_at(1), kind_at(2)), (default, plastic), "{bend}");
        assert_eq!(scene.world.joints().len(), 2);
    }
}

/// `[body.bend.dynamic]` becomes the body's dynamic articulation; `max_joints` defaults to the
/// library's 16.
#[test]
fn dynamic_articulation_is_parsed() {
    let plastic =
        JointKind::Bend(JointRule::Plastic { strength: 12.0, damping_constant: 0.25, damping_proportional: 2.0 });
    let table = "[body.bend.dynamic]\nspeed_threshold = 2.5\nmin_bone_length = 0.3\n\
                 joint = { kind = \"plastic\", strength = 12.0, damping_constant = 0.25, damping_proportional = 2.0 }";
    let scene = parse(&bar("", &format!("{table}\nmax_joints = 3")));
    let expected = DynamicArticulation { speed_threshold: 2.5, joint: plastic, min_bone_length: 0.3, max_joints: 3 };
    assert_eq!(bending_body(&scene, "bar").dynamic(), Some(&expected));
    let scene = parse(&bar("", table));
    let dynamic = bending_body(&scene, "bar").dynamic().copied().unwrap();
    assert_eq!(dynamic, DynamicArticulation::new(2.5, plastic, 0.3));
    assert_eq!(dynamic.max_joints, 16);
    // Without the table there is none.
    assert_eq!(bending_body(&parse(&bar("", "")), "bar").dynamic(), None);
}

/// `scenes/bent_bar.toml`: the bar has the file's three bones joined by plastic joints; run 40
/// frames (the ball hits at about frame 4), its skinned mesh stays finite with every rest
/// vertex, and both joints bend. A free 87.5 kg bar hit in the middle by 20 kg at 6 m/s bends
/// about 18° at each joint of strength 10 N·m·s; 5° leaves room for solver changes while still
/// telling a bend from the few tenths of a degree of numerical drift of a joint that holds.
#[test]
fn the_example_file_runs_and_bends() {
    let Scene { mut world, mut bending, frames, .. } = load_scene(&repo_file("scenes/bent_bar.toml")).unwrap();
    assert_eq!(frames, 60);
    let bar = bending.find("bar").expect("a bending body \"bar\"");
    let heads: Vec<f32> = bar.skeleton().bones().iter().map(|b| b.head.x).collect();
    assert_eq!(heads, [-1.8, -0.6, 0.6]);
    let rest_vertices = bar.rest_mesh().vertex_count();
    let plastic =
        JointKind::Bend(JointRule::Plastic { strength: 10.0, damping_constant: 0.5, damping_proportional: 4.0 });
    assert!(world.joints().iter().all(|j| *j.kind() == plastic) && world.joints().len() == 2);
    for _ in 0..40 {
        bending.step(&mut world).unwrap();
    }
    let meshes = bending.skinned_meshes(&world).unwrap();
    assert_eq!(meshes.len(), 1);
    let (name, mesh, _) = &meshes[0];
    assert_eq!((name.as_str(), mesh.vertex_count()), ("bar", rest_vertices));
    assert!(mesh.positions().iter().chain(mesh.normals()).all(|p| p.is_finite()));
    for joint in world.joints() {
        let angle = joint.bend_angle().to_degrees();
        assert!(angle > 5.0 && angle < 60.0, "joint bent {angle}°");
    }
    assert!(!bending.bends().is_empty());
}
