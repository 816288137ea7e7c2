//! `dentbend dent` end to end: the real binary dents a mesh file and saves an OBJ with the same
//! topology, and bad input exits with code 2, one `error:` line, and no output file.

mod common;

use std::path::Path;

use common::{TempDir, dentbend, text};
use dentbend::glam::Vec3;

/// Vertex positions and face count of an OBJ file, read line by line.
fn read_obj(path: &Path) -> (Vec<Vec3>, usize) {
    let mut vertices = Vec::new();
    let mut faces = 0;
    for line in std::fs::read_to_string(path).unwrap().lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let xyz: Vec<f32> = words.take(3).map(|w| w.parse().unwrap()).collect();
                vertices.push(Vec3::new(xyz[0], xyz[1], xyz[2]));
            }
            Some("f") => faces += 1,
            _ => {}
        }
    }
    (vertices, faces)
}

/// `--translate` that rests the built-in sphere on the built-in block's top face, and that
/// face's height.
fn sphere_on_block() -> (String, f32) {
    let (_, block_top) = dentbend::mesh::builtin("block").unwrap().bounds();
    let (sphere_low, _) = dentbend::mesh::builtin("sphere").unwrap().bounds();
    (format!("0,{},0", block_top.y - sphere_low.y), block_top.y)
}

#[test]
fn sphere_dents_block() {
    let dir = TempDir::new("sphere-block");
    let out = dir.path("dented.obj");
    let (translate, top) = sphere_on_block();
    let point = format!("0,{top},0");
    let output = dentbend(&[
        "dent",
        "--target",
        "block",
        "--projectile",
        "sphere",
        "--translate",
        &translate,
        "--point",
        &point,
        "--normal=0,-1,0",
        "--dent-distance",
        "0.2",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = text(&output.stdout);
    assert!(output.status.success(), "dent failed: {}", text(&output.stderr));
    assert!(stdout.starts_with("dent: moved "), "{stdout}");
    assert_eq!(stdout.lines().count(), 1, "{stdout}");

    let block = dentbend::mesh::builtin("block").unwrap();
    let (dented, faces) = read_obj(&out);
    assert_eq!(dented.len(), block.vertex_count());
    assert_eq!(faces, block.face_count());
    let moved: Vec<f32> = dented.iter().zip(block.positions()).map(|(a, b)| a.distance(*b)).collect();
    let deepest = moved.iter().copied().fold(0.0, f32::max);
    assert!((deepest - 0.2).abs() < 0.02, "deepest vertex moved by {deepest}, expected ≈ 0.2");
    // The dent goes down, into the block, at the contact point.
    let (i, _) = moved.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).unwrap();
    assert!(dented[i].y < block.positions()[i].y);
    assert!(moved.iter().filter(|&&m| m > 1e-6).count() < block.vertex_count(), "not every vertex moves");
    let no_temp_left = std::fs::read_dir(dir.root()).unwrap().count() == 1;
    assert!(no_temp_left, "temporary files left beside the output");
}

#[test]
fn projectile_from_a_file_with_linear_falloff() {
    let dir = TempDir::new("file");
    let (translate, top) = sphere_on_block();
    let offset: Vec<f32> = translate.split(',').map(|w| w.parse().unwrap()).collect();
    let mut ball = dentbend::mesh::builtin("sphere").unwrap();
    ball.transform(dentbend::glam::Affine3A::from_translation(Vec3::new(0.0, offset[1], 0.0))).unwrap();
    let ball_path = dir.path("ball.obj");
    dentbend::mesh::save(&ball_path, &ball).unwrap();
    let out = dir.path("linear.obj");
    let point = format!("0,{top},0");
    let output = dentbend(&[
        "dent",
        "--target",
        "block",
        "--projectile",
        ball_path.to_str().unwrap(),
        "--point",
        &point,
        "--normal=0,-1,0",
        "--dent-distance",
        "0.1",
        "--res",
        "48",
        "--falloff",
        "linear",
        "--falloff-scale",
        "0.5",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = text(&output.stderr);
    assert!(output.status.success(), "dent failed: {stderr}");
    assert!(text(&output.stdout).contains("48×48 cells"), "{}", text(&output.stdout));
    // A falloff twice as steep as 1 − z/d, but on a block ten times thicker than the dent: no
    // wall can fold, so nothing is warned (the warning reads the body, not the falloff).
    assert_eq!(stderr.matches("warning: ").count(), 0, "{stderr}");
    assert_eq!(read_obj(&out).0.len(), dentbend::mesh::builtin("block").unwrap().vertex_count());
}

#[test]
fn bad_input_exits_with_code_2_and_writes_nothing() {
    let dir = TempDir::new("bad");
    let out = dir.path("out.obj");
    let out_s = out.to_str().unwrap().to_owned();
    let garbage = dir.path("garbage.obj");
    std::fs::write(&garbage, "this is not\nan OBJ file\nf 1 2 3 4 x\n").unwrap();
    let garbage_s = garbage.to_str().unwrap().to_owned();
    let missing_s = dir.path("missing.obj").to_str().unwrap().to_owned();
    let (translate, top) = sphere_on_block();
    let point = format!("0,{top},0");
    let args = |overrides: &[(&str, &str)], drop: &[&str]| -> Vec<String> {
        let mut pairs: Vec<(String, String)> = [
            ("--target", "block"),
            ("--projectile", "sphere"),
            ("--translate", translate.as_str()),
            ("--point", point.as_str()),
            ("--normal", "0,-1,0"),
            ("--dent-distance", "0.2"),
            ("--out", out_s.as_str()),
        ]
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
        for (k, v) in overrides {
            match pairs.iter_mut().find(|(key, _)| key == k) {
                Some(pair) => pair.1 = v.to_string(),
                None => pairs.push((k.to_string(), v.to_string())),
            }
        }
        pairs.retain(|(k, _)| !drop.contains(&k.as_str()));
        std::iter::once("dent".to_owned()).chain(pairs.into_iter().map(|(k, v)| format!("{k}={v}"))).collect()
    };
    let cases: Vec<(Vec<String>, &str)> = vec![
        (args(&[("--normal", "0,0,0")], &[]), "zero normal"),
        (args(&[("--normal", "1,2")], &[]), "two components"),
        (args(&[("--normal", "nan,0,1")], &[]), "NaN normal"),
        (args(&[("--point", "a,b,c")], &[]), "not numbers"),
        (args(&[("--point", "0,inf,0")], &[]), "infinite point"),
        (args(&[("--dent-distance", "-1")], &[]), "negative d"),
        (args(&[("--res", "0")], &[]), "res 0"),
        (args(&[("--res", "100000")], &[]), "res 100000"),
        (args(&[("--velocity", "0,1,0")], &[]), "separating"),
        (args(&[("--falloff", "cubic")], &[]), "unknown falloff"),
        (args(&[("--falloff-scale", "0.5")], &[]), "scale without linear"),
        (args(&[("--falloff", "linear"), ("--falloff-scale", "0")], &[]), "zero scale"),
        (args(&[("--target", &missing_s)], &[]), "missing target"),
        (args(&[("--projectile", &missing_s)], &[]), "missing projectile"),
        (args(&[("--target", &garbage_s)], &[]), "garbage target"),
        (args(&[("--projectile", &garbage_s)], &[]), "garbage projectile"),
        (args(&[("--translate", "0,-40,0")], &[]), "projectile behind the plane"),
        (args(&[], &["--point"]), "no point"),
        // A missing folder is created (as `dentmap` and `run` do); one below a file cannot be.
        (args(&[("--out", dir.path("garbage.obj/sub/out.obj").to_str().unwrap())], &[]), "unwritable output"),
        (args(&[("--out", dir.root().to_str().unwrap())], &[]), "output is a directory"),
    ];
    for (args, what) in &cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let output = dentbend(&args);
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{what}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{what}: one line expected, got {stderr:?}");
        assert!(stderr.starts_with("error: "), "{what}: {stderr}");
        assert!(!out.exists(), "{what}: output written anyway");
        let left: Vec<_> = std::fs::read_dir(dir.root()).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left.len(), 1, "{what}: files left behind: {left:?}");
    }
}

/// The dent lands on the impact point; one 30 units beside the block touches nothing.
#[test]
fn a_miss_is_a_warning_not_an_error() {
    let dir = TempDir::new("miss");
    let out = dir.path("miss.obj");
    let (_, top) = sphere_on_block();
    let point = format!("30,{top},0");
    let output = dentbend(&[
        "dent",
        "--target",
        "block",
        "--projectile",
        "sphere",
        "--translate",
        "30,2,0",
        "--point",
        &point,
        "--normal=0,-1,0",
        "--dent-distance",
        "0.2",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = text(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(text(&output.stdout).starts_with("dent: moved 0 of "), "{}", text(&output.stdout));
    assert!(stderr.starts_with("warning: the dent moved no vertex"), "{stderr}");
    let block = dentbend::mesh::builtin("block").unwrap();
    assert_eq!(read_obj(&out).0, block.positions());
}

#[test]
fn help_documents_the_interface() {
    let output = dentbend(&["dent", "--help"]);
    assert!(output.status.success());
    let help = text(&output.stdout);
    for flag in [
        "--target",
        "--projectile",
        "--rotate",
        "--point",
        "--normal",
        "--velocity",
        "--dent-distance",
        "--res",
        "--sigma",
        "--heat-iters",
        "--clamp-iters",
        "--widen",
        "--falloff",
        "--out",
    ] {
        assert!(help.contains(flag), "help lacks {flag}");
    }
}

/// A 2 m cube of 12 triangles as an OBJ file.
fn coarse_cube(path: &Path) {
    let corners: Vec<Vec3> =
        (0..8).map(|k| Vec3::new([-1., 1.][k & 1], [-1., 1.][(k >> 1) & 1], [-1., 1.][k >> 2])).collect();
    // Two triangles per face, each wound outwards (checked by the volume below).
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let faces: Vec<[u32; 3]> = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
    let cube = dentbend::TriMesh::new(corners, faces).unwrap();
    assert!((cube.volume() - 8.0).abs() < 1e-5);
    dentbend::mesh::save(path, &cube).unwrap();
}

#[test]
fn refine_lets_a_coarse_cube_take_the_dent_and_says_how_much_it_added() {
    let dir = TempDir::new("refine");
    let cube = dir.path("cube.obj");
    coarse_cube(&cube);
    let run = |refine: &str, out: &Path| {
        dentbend(&[
            "dent",
            "--target",
            cube.to_str().unwrap(),
            "--projectile",
            "sphere",
            "--scale",
            "0.5",
            "--translate",
            "0,1.5,0",
            "--point",
            "0,1,0",
            "--normal=0,-1,0",
            "--dent-distance",
            "0.1",
            "--refine",
            refine,
            "--out",
            out.to_str().unwrap(),
        ])
    };
    // Off: the 12 triangles take no dent (and the command says so).
    let off = dir.path("off.obj");
    let output = run("off", &off);
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(text(&output.stderr).contains("moved no vertex"), "{}", text(&output.stderr));
    assert_eq!(read_obj(&off).1, 12);

    for refine in ["auto", "0.05"] {
        let out = dir.path(&format!("{refine}.obj"));
        let output = run(refine, &out);
        let stdout = text(&output.stdout);
        assert!(output.status.success(), "--refine {refine}: {}", text(&output.stderr));
        let (vertices, faces) = read_obj(&out);
        assert!(faces > 100, "--refine {refine}: {faces} faces");
        let added = format!("refined first: +{} triangles, +{} vertices", faces - 12, vertices.len() - 8);
        assert!(stdout.contains(&added), "--refine {refine}: {stdout}");
        // The top face's vertices (not the side ones refinement added below its edges).
        let top = |p: &&Vec3| p.y > 0.5 && p.x.abs() < 0.99 && p.z.abs() < 0.99;
        let deepest = vertices.iter().filter(top).map(|p| 1.0 - p.y).fold(0.0f32, f32::max);
        assert!((deepest - 0.1).abs() < 0.002, "--refine {refine}: deepest {deepest}");
    }

    for bad in ["-1", "nan", "sometimes"] {
        let out = dir.path("bad.obj");
        let output = run(bad, &out);
        assert_eq!(output.status.code(), Some(2), "--refine {bad}");
        assert!(text(&output.stderr).contains("--refine"), "--refine {bad}: {}", text(&output.stderr));
        assert!(!out.exists());
    }
}

/// Runs `dentbend dent` of a 0.5-radius ball 0.1 deep into the top of the 2 m cube `target`
/// at (0.3, 1, 0.2), written to `out`.
fn dent_top(target: &str, out: &Path) -> std::process::Output {
    let out = out.to_str().unwrap();
    dentbend(&[
        "dent",
        "--target",
        target,
        "--projectile",
        "sphere",
        "--scale",
        "0.5",
        "--translate",
        "0.3,1.5,0.2",
        "--point",
        "0.3,1,0.2",
        "--normal=0,-1,0",
        "--dent-distance",
        "0.1",
        "--out",
        out,
    ])
}

#[test]
fn an_obj_asset_keeps_its_uvs_normals_groups_and_materials() {
    let dir = TempDir::new("asset-obj");
    let input = dir.path("crate.obj");
    let mut obj = "mtllib crate.mtl\no crate\nusemtl wood\n".to_owned();
    obj.push_str(&dentbend::mesh::obj_asset_text(&dentbend::mesh::builtin_asset("crate").unwrap()));
    std::fs::write(&input, &obj).unwrap();
    let out = dir.path("dented.obj");
    let output = dent_top(input.to_str().unwrap(), &out);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let written = std::fs::read_to_string(&out).unwrap();
    let count = |prefix: &str| written.lines().filter(|l| l.starts_with(prefix)).count();
    let (vertices, faces) = (count("v "), count("f "));
    assert!(vertices > 24 && faces > 12, "{vertices} vertices, {faces} faces: not refined");
    assert_eq!((count("vt "), count("vn ")), (vertices, vertices));
    for line in ["mtllib crate.mtl", "o crate", "usemtl wood"] {
        assert!(written.lines().any(|l| l == line), "{line} lost");
    }
    let asset = dentbend::mesh::parse_obj_asset(&written).unwrap();
    assert_eq!(asset.mesh().vertex_count(), vertices);
    // The bottom side (y = −1) is far from the dent: its four corners keep its normal, and the
    // sides' vertices beside them theirs (hard edges).
    let bottom: Vec<usize> = (0..vertices).filter(|&v| asset.mesh().positions()[v].y == -1.0).collect();
    let normals: Vec<Vec3> = bottom.iter().map(|&v| asset.shading_normals()[v]).collect();
    assert_eq!(normals.iter().filter(|n| **n == Vec3::NEG_Y).count(), 4, "{normals:?}");
    assert!(normals.iter().all(|n| n.abs().max_element() == 1.0), "{normals:?}");
}

#[test]
fn a_gltf_asset_comes_out_as_glb_with_its_texcoords() {
    let dir = TempDir::new("asset-glb");
    let input = dir.path("crate.glb");
    dentbend::mesh::save_asset(&input, &dentbend::mesh::builtin_asset("crate").unwrap()).unwrap();
    let out = dir.path("dented.glb");
    let output = dent_top(input.to_str().unwrap(), &out);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let bytes = std::fs::read(&out).unwrap();
    let json_length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let json = String::from_utf8_lossy(&bytes[20..20 + json_length]);
    assert!(json.contains("\"TEXCOORD_0\"") && json.contains("\"NORMAL\""), "{json}");
    let asset = dentbend::mesh::parse_gltf_asset(&bytes).unwrap();
    assert!(asset.mesh().face_count() > 12, "not refined");
    assert_eq!(asset.attributes().uvs.len(), 1);
    assert!(asset.attributes().uvs[0].iter().all(|uv| (0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y)));
}

/// `--impacts`: three impacts from one JSON file in one call, each with its own depth (and one
/// with its own projectile pose), dent the block's top at each point and nowhere else; bad
/// files exit with code 2, one `error:` line naming the entry, and no output.
#[test]
fn an_impacts_file_dents_many_points_in_one_call() {
    let dir = TempDir::new("impacts");
    let out = dir.path("dented.obj");
    let (_, top) = sphere_on_block();
    let (sphere_low, _) = dentbend::mesh::builtin("sphere").unwrap().bounds();
    // The sphere at half size rests on the top at x = −0.6 with its own pose.
    let half = format!("[-0.6, {}, 0]", top - 0.5 * sphere_low.y);
    let impacts = dir.path("impacts.json");
    let points = [(0.0, 0.15), (0.6, 0.05), (-0.6, 0.1)];
    std::fs::write(
        &impacts,
        format!(
            r#"[
                {{"point": [0, {top}, 0], "normal": [0, -1, 0], "depth": 0.15}},
                {{"point": [0.6, {top}, 0], "normal": [0, -1, 0], "velocity": [0.3, -2, 0], "depth": 0.05}},
                {{"point": [-0.6, {top}, 0], "normal": [0, -1, 0], "depth": 0.1, "scale": 0.5, "translate": {half}}}
            ]"#
        ),
    )
    .unwrap();
    let impacts_s = impacts.to_str().unwrap();
    let out_s = out.to_str().unwrap();
    let dent_with_impacts = |more: &[&str]| {
        let mut args = vec!["dent", "--target", "block", "--projectile", "sphere", "--impacts", impacts_s];
        args.extend(["--dent-distance", "0.2", "--out", out_s]);
        args.extend(more);
        dentbend(&args)
    };
    let output = dent_with_impacts(&["--refine", "off"]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(text(&output.stdout).contains("3 impacts"), "{}", text(&output.stdout));
    let before = dentbend::mesh::builtin("block").unwrap().positions().to_vec();
    let (after, _) = read_obj(&out);
    assert_eq!(before.len(), after.len(), "--refine off keeps the vertices");
    // Under each point the top sinks by a good part of that impact's depth; no vertex moves
    // farther than the three depths together (each dent moves a vertex by at most its own; the
    // broad ones overlap). OBJ text rounding: 1e-5.
    for (x, depth) in points {
        let sunk = before
            .iter()
            .zip(&after)
            .filter(|(b, _)| (b.y - top).abs() < 1e-5 && (b.x - x).abs() < 0.05 && b.z.abs() < 0.05)
            .map(|(b, a)| b.y - a.y)
            .fold(0.0f32, f32::max);
        assert!(sunk > 0.5 * depth, "at x = {x}: sunk {sunk} for a {depth} dent");
    }
    let total: f32 = points.iter().map(|p| p.1).sum();
    let farthest = before.iter().zip(&after).map(|(b, a)| b.distance(*a)).fold(0.0f32, f32::max);
    assert!(farthest <= total + 1e-5, "a vertex moved {farthest}, more than the {total} of all three dents");
    // Bad files: a zero normal in entry 1, a missing field, not a list, an unknown field.
    let cases = [
        (r#"[{"point": [0, 1, 0], "normal": [0, -1, 0]}, {"point": [0, 1, 0], "normal": [0, 0, 0]}]"#, "impact 1"),
        (r#"[{"point": [0, 1, 0]}]"#, "normal"),
        (r#"{"point": [0, 1, 0]}"#, "list"),
        (r#"[{"point": [0, 1, 0], "normal": [0, -1, 0], "speed": 3}]"#, "speed"),
        (r#"[{"point": [0, 1, 0], "normal": [0, -1, 0], "depth": -1}]"#, "impact 0"),
        ("[]", "1 to"),
    ];
    std::fs::remove_file(&out).unwrap();
    for (body, says) in cases {
        std::fs::write(&impacts, body).unwrap();
        let output = dent_with_impacts(&[]);
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{body}: {stderr}");
        assert!(
            stderr.starts_with("error: ") && stderr.lines().count() == 1 && stderr.contains(says),
            "{body}: {stderr}"
        );
        assert!(!out.exists(), "{body}: output written anyway");
    }
}
