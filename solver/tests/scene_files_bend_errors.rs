//! Bad `[body.bend]` tables are refused, without a panic, by a message that names the file, the
//! line of the offending value, the body and the field: fields a bending body cannot have, bad
//! weight numbers, bad skeletons (the bending library's errors placed on the bone), bad joints
//! and bad dynamic articulation.

use std::path::Path;

use dentbend_solver::scene::parse_scene;

mod common;

use common::temp::TempDir;

/// A 4 × 0.5 × 0.5 m bar with `body` lines before its `[body.bend]` table and `bend` lines in it.
fn bar(body: &str, bend: &str) -> String {
    format!(
        "frames = 10\n\n[[body]]\nname = \"bar\"\nmesh = \"box\"\nscale = [2.0, 0.25, 0.25]\n{body}\n\
         [body.bend]\nresolution = 32\n{bend}\n"
    )
}

/// Three chained bones along the bar, each line of `edits` replacing the line of the same key
/// in the bone it names: `(bone, "key = value")`.
fn bones(edits: &[(usize, &str)]) -> String {
    let mut text = String::new();
    for (k, (head, tail)) in [(-1.8, -0.6), (-0.6, 0.6), (0.6, 1.8)].iter().enumerate() {
        let mut lines = vec![format!("head = [{head:?}, 0.0, 0.0]"), format!("tail = [{tail:?}, 0.0, 0.0]")];
        if k > 0 {
            lines.push(format!("parent = {}", k - 1));
        }
        for (bone, edit) in edits.iter().filter(|(bone, _)| *bone == k) {
            let key = edit.split('=').next().unwrap().trim();
            lines.retain(|l| !l.starts_with(&format!("{key} ")));
            lines.push((*edit).to_owned());
            assert_eq!(*bone, k);
        }
        text += &format!("[[body.bend.bone]]\n{}\n", lines.join("\n"));
    }
    text
}

/// The 1-based line of the first line of `text` that contains `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap_or_else(|| panic!("no {needle} in\n{text}")) + 1
}

/// The 1-based line of the `[[body.bend.bone]]` header of bone `k`.
fn bone_line(text: &str, k: usize) -> usize {
    text.lines().enumerate().filter(|(_, l)| l.starts_with("[[body.bend.bone]]")).nth(k).expect("no such bone").0 + 1
}

/// Parses `text`, expects a refusal on the line holding `at`, naming body "bar" and `field`;
/// returns the message.
fn refused(text: &str, at: &str, field: &str) -> String {
    refused_on_line(text, line_of(text, at), field)
}

/// As [`refused`], on line `line`.
fn refused_on_line(text: &str, line: usize, field: &str) -> String {
    let message = match parse_scene(text, Path::new("bend.toml")) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    };
    assert!(message.starts_with(&format!("bend.toml:{line}:")), "expected line {line}: {message}\n{text}");
    assert!(message.contains("body \"bar\""), "no body in {message}");
    assert!(message.contains(&format!(" {field}: ")), "no field {field} in {message}");
    message
}

#[test]
fn rigid_only_fields_are_refused() {
    for kind in ["static", "kinematic"] {
        let message = refused(&bar(&format!("kind = \"{kind}\""), ""), "kind =", "kind");
        assert!(message.contains("dynamic"), "{message}");
    }
    for collider in ["ball", "cuboid", "tri-mesh"] {
        let message = refused(&bar(&format!("collider = \"{collider}\""), ""), "collider =", "collider");
        assert!(message.contains("capsule"), "{message}");
    }
    let message = refused(&bar("mass = 80.0", ""), "mass =", "mass");
    assert!(message.contains("density"), "{message}");
    let text = format!("{}[body.dent]\ncap = 0.1\n", bar("", ""));
    refused(&text, "[body.dent]", "dent");
    // What a bending body may have is accepted.
    for collider in ["auto", "convex-hull", "capsule"] {
        let text = bar(&format!("kind = \"dynamic\"\ncollider = \"{collider}\"\ndensity = 600.0"), "");
        parse_scene(&text, Path::new("ok.toml")).unwrap();
    }
}

#[test]
fn bad_weight_numbers_are_refused() {
    let with = |line: &str| bar("", "").replace("resolution = 32\n", &format!("{line}\n"));
    refused(&with("resolution = 4"), "resolution", "bend.resolution");
    refused(&with("resolution = 100000"), "resolution", "bend.resolution");
    refused(&with("resolution = -3"), "resolution", "bend.resolution");
    refused(&with("resolution = 64.5"), "resolution", "bend.resolution");
    refused(&bar("", "influences = 0"), "influences", "bend.influences");
    refused(&bar("", "influences = 9"), "influences", "bend.influences");
    refused(&bar("", "falloff = nan"), "falloff", "bend.falloff");
    refused(&bar("", "falloff = -1.0"), "falloff", "bend.falloff");
    refused(&bar("", "stifness = 3.0"), "stifness", "bend.stifness");
}

#[test]
fn bad_automatic_skeletons_are_refused() {
    refused(&bar("", "skeleton = \"auto\"\nbones = 0"), "bones", "bend.bones");
    refused(&bar("", "bones = 100000"), "bones", "bend.bones");
    refused(&bar("", "bones = -2"), "bones", "bend.bones");
    refused(&bar("", "skeleton = \"manual\""), "skeleton", "bend.skeleton");
    refused(&bar("", "skeleton = []"), "skeleton", "bend.skeleton");
    // `bones` counts the automatic bones only.
    refused(&bar("", &format!("bones = 3\n{}", bones(&[]))), "bones = 3", "bend.bones");
    refused(&bar("", &format!("skeleton = \"auto\"\n{}", bones(&[]))), "[[body.bend.bone]]", "bend.bone");
}

/// The bending library's skeleton errors, on the bone (and part of it) they name.
#[test]
fn bad_given_skeletons_are_refused_at_the_bone() {
    // Whole-bone errors point at the bone's header.
    let text = bar("", &bones(&[(1, "tail = [-0.6, 0.0, 0.0]")]));
    let message = refused_on_line(&text, bone_line(&text, 1), "bend.bone[1]");
    assert!(message.contains("length"), "{message}");
    // 0.2 m beyond the bar's end, more than the 0.08 m tolerance; within its joint gap limit.
    let text = bar("", &bones(&[(2, "head = [2.2, 0.0, 0.0]"), (2, "tail = [6.0, 0.0, 0.0]")]));
    let message = refused_on_line(&text, bone_line(&text, 2), "bend.bone[2]");
    assert!(message.contains("outside the mesh"), "{message}");
    let cases = [
        ((1, "parent = 2"), "parent = 2", "bend.bone[1].parent", "cycle"),
        ((2, "parent = 7"), "parent = 7", "bend.bone[2].parent", "out of range"),
        ((0, "parent = 0"), "parent = 0", "bend.bone[0].parent", "cycle"),
        ((1, "head = [-0.6, 2.0, 0.0]"), "parent = 0", "bend.bone[1].parent", "from its parent bone"),
        ((0, "head = [nan, 0.0, 0.0]"), "nan", "bend.bone[0].head", "non-finite"),
        ((1, "parent = -1"), "parent = -1", "bend.bone.parent", "parent"),
    ];
    for (edit, at, field, words) in cases {
        let message = refused(&bar("", &bones(&[edit])), at, field);
        assert!(message.contains(words), "no \"{words}\" in {message}");
    }
    // Two roots: the second root is pointed at.
    let text = bar("", &bones(&[])).replacen("parent = 1\n", "", 1);
    let message = refused_on_line(&text, bone_line(&text, 2), "bend.bone");
    assert!(message.contains("2 roots"), "{message}");
    // A bone table with a typo, and the inline array form with a bad bone.
    refused(&bar("", &bones(&[(1, "parnt = 0")])), "parnt", "bend.bone.parnt");
    let inline = "skeleton = [{ head = [-1.0, 0.0, 0.0], tail = [1.0, 0.0, 0.0] }, \
                  { head = [1.0, 0.0, 0.0], tail = [1.0, 0.0, 0.0], parent = 0 }]";
    refused(&bar("", inline), "skeleton =", "bend.skeleton[1]");
}

#[test]
fn bad_joints_are_refused() {
    let joint = |table: &str| bar("", &format!("bones = 2\njoint = {{ {table} }}"));
    refused(&joint("kind = \"spring\""), "joint =", "bend.joint.kind");
    let message = refused(&joint("kind = \"plastic\", strength = 4.0"), "joint =", "bend.joint.damping_constant");
    assert!(message.contains("needs"), "{message}");
    refused(
        &joint("kind = \"plastic\", strength = -4.0, damping_constant = 0.0, damping_proportional = 0.0"),
        "joint =",
        "bend.joint.strength",
    );
    let message = refused(
        &joint("kind = \"elastic\", stiffness = 10.0, damping = 1.0, strength = 3.0"),
        "joint =",
        "bend.joint.strength",
    );
    assert!(message.contains("does not apply to an elastic joint"), "{message}");
    refused(&joint("kind = \"elastic\", stiffness = inf, damping = 1.0"), "joint =", "bend.joint.stiffness");
    refused(&joint("kind = \"elastic\", stiffness = 10.0, damping = -1.0"), "joint =", "bend.joint.damping");
    refused(
        &joint("kind = \"elastic-prismatic\", axis = [0.0, 0.0, 0.0], stiffness = 10.0, damping = 1.0"),
        "joint =",
        "bend.joint.axis",
    );
    refused(&joint("kind = \"elastic-prismatic\", stiffness = 10.0, damping = 1.0"), "joint =", "bend.joint.axis");
    refused(&joint("kind = \"ball\", axis = [1.0, 0.0, 0.0]"), "joint =", "bend.joint.axis");
    // The table form points at the line.
    let text = bar(
        "",
        "bones = 2\n[body.bend.joint]\nkind = \"plastic\"\nstrength = nan\ndamping_constant = 0.0\ndamping_proportional = 0.0",
    );
    refused(&text, "strength = nan", "bend.joint.strength");
}

/// A bone's own `joint` (the joint at its head) is checked like `[body.bend] joint`, its errors
/// named by the bone; the root bone hangs from no joint and may not have one.
#[test]
fn bad_joints_of_bones_are_refused() {
    let plastic = "joint = { kind = \"plastic\", strength = 2.0, damping_constant = 0.0, damping_proportional = 1.0 }";
    parse_scene(&bar("", &bones(&[(2, plastic)])), Path::new("ok.toml")).unwrap();
    let message = refused(&bar("", &bones(&[(0, plastic)])), "joint =", "bend.bone[0].joint");
    assert!(message.contains("root bone"), "{message}");
    let bad = plastic.replace("strength = 2.0", "strength = -2.0");
    refused(&bar("", &bones(&[(1, &bad)])), "joint =", "bend.bone[1].joint.strength");
    let message =
        refused(&bar("", &bones(&[(2, "joint = { kind = \"plastic\" }")])), "joint =", "bend.bone[2].joint.strength");
    assert!(message.contains("needs"), "{message}");
    refused(&bar("", &bones(&[(1, "joint = { kind = \"hinge\" }")])), "joint =", "bend.bone.joint.kind");
    // The inline form names the skeleton's entry.
    let inline = "skeleton = [{ head = [-1.0, 0.0, 0.0], tail = [0.0, 0.0, 0.0] }, \
                  { head = [0.0, 0.0, 0.0], tail = [1.0, 0.0, 0.0], parent = 0, joint = { kind = \"elastic\", stiffness = 0.0, damping = 1.0 } }]";
    refused(&bar("", inline), "skeleton =", "bend.skeleton[1].joint.stiffness");
}

#[test]
fn bad_dynamic_articulation_is_refused() {
    let plastic = "joint = { kind = \"plastic\", strength = 1.0, damping_constant = 0.0, damping_proportional = 1.0 }";
    let dynamic = |lines: &str| bar("", &format!("[body.bend.dynamic]\n{lines}"));
    let good = format!("speed_threshold = 2.0\nmin_bone_length = 0.3\n{plastic}");
    parse_scene(&dynamic(&good), Path::new("ok.toml")).unwrap();
    let with = |from: &str, to: &str| dynamic(&good.replace(from, to));
    refused(
        &with("speed_threshold = 2.0", "speed_threshold = -1.0"),
        "speed_threshold",
        "bend.dynamic.speed_threshold",
    );
    refused(&with("speed_threshold = 2.0", "speed_threshold = nan"), "speed_threshold", "bend.dynamic.speed_threshold");
    refused(&with("min_bone_length = 0.3", "min_bone_length = 0.0"), "min_bone_length", "bend.dynamic.min_bone_length");
    refused(&dynamic(&format!("{good}\nmax_joints = 0")), "max_joints", "bend.dynamic.max_joints");
    refused(&with("strength = 1.0", "strength = 0.0"), "joint =", "bend.dynamic.joint.strength");
    let message = refused(&with(&format!("\n{plastic}"), ""), "[body.bend.dynamic]", "bend.dynamic");
    assert!(message.contains("joint"), "{message}");
}

/// Errors only building the body finds (after every value passed its own check) still name the
/// body: an open mesh (no level set), and a sub-body name already taken.
#[test]
fn errors_building_the_body_name_it() {
    let dir = TempDir::new("scene-bend-open");
    // A 4 × 0.5 × 0.5 box without its +x end (rows along x pass through the hole).
    let corners = (0..8).map(|k| {
        let pick = |bit: usize, v: f32| if k & bit == 0 { -v } else { v };
        format!("v {} {} {}\n", pick(1, 2.0), pick(2, 0.25), pick(4, 0.25))
    });
    let faces =
        [[1, 3, 4], [1, 4, 2], [5, 6, 8], [5, 8, 7], [1, 2, 6], [1, 6, 5], [1, 5, 7], [1, 7, 3], [3, 7, 8], [3, 8, 4]];
    let obj: String = corners.chain(faces.iter().map(|[a, b, c]| format!("f {a} {b} {c}\n"))).collect();
    std::fs::write(dir.path("open.obj"), obj).unwrap();
    let text = "frames = 10\n\n[[body]]\nname = \"bar\"\nmesh = \"open.obj\"\n[body.bend]\nbones = 2\n";
    let message = match parse_scene(text, &dir.path("open.toml")) {
        Ok(_) => panic!("an open mesh was accepted"),
        Err(e) => e.to_string(),
    };
    assert!(
        message.contains(":6:") && message.contains("body \"bar\": bend: ") && message.contains("not closed"),
        "{message}"
    );

    let plain = "[[body]]\nname = \"bar/bone0\"\nmesh = \"sphere\"\nposition = [0.0, 5.0, 0.0]\n";
    let taken = bar("", "").replacen("frames = 10\n", &format!("frames = 10\n{plain}"), 1);
    let message = refused(&taken, "name = \"bar\"", "name");
    assert!(message.contains("bar/bone0"), "{message}");
}
