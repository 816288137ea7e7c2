//! `dentbend dentmap` end to end: the real binary writes every stage with consistent shapes,
//! records the parameters it used, and rejects bad input with one `error:` line and exit code 2.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{TempDir, dentbend, text};
use dentbend::glam::Vec3;
use dentbend::io::read_npy_f32;
use serde_json::Value;

fn vec3(value: &Value) -> Vec3 {
    let a: Vec<f32> = value.as_array().unwrap().iter().map(|v| v.as_f64().unwrap() as f32).collect();
    assert_eq!(a.len(), 3, "{value}");
    Vec3::new(a[0], a[1], a[2])
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Runs `dentmap` into a fresh directory and checks it succeeded.
fn run_ok(dir: &TempDir, extra: &[&str]) -> (PathBuf, Output) {
    let out = dir.path("out");
    let mut args = vec!["dentmap", "--projectile", "bunny", "--dent-distance", "0.2", "--out", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let output = dentbend(&args);
    assert!(output.status.success(), "dentmap failed: {}", text(&output.stderr));
    (out, output)
}

#[test]
fn bunny_writes_every_stage_with_consistent_shapes() {
    let dir = TempDir::new("bunny");
    let (out, output) = run_ok(&dir, &[]);
    let stdout = text(&output.stdout);
    assert!(stdout.starts_with("dentmap: bunny, "), "{stdout}");
    assert_eq!(stdout.lines().count(), 1, "{stdout}");

    for file in ["zbuffer", "envelope", "smoothed", "dentmap"] {
        for ext in ["npy", "png"] {
            assert!(out.join(format!("{file}.{ext}")).is_file(), "{file}.{ext} missing");
        }
    }
    let json = read_json(&out.join("dentmap.json"));
    for key in
        ["dent_distance", "sigma", "heat_iters", "clamp_iters", "widen", "theta_deg", "zbuffer_grid", "dentmap_grid"]
    {
        assert!(json.get(key).is_some(), "dentmap.json lacks {key}: {json}");
    }
    for grid in ["zbuffer_grid", "dentmap_grid"] {
        for key in ["origin", "axis_x", "axis_y", "axis_z", "cell_size", "res"] {
            assert!(json[grid].get(key).is_some(), "{grid} lacks {key}");
        }
    }
    // The values actually used, defaults included.
    let f = |key: &str| json[key].as_f64().unwrap();
    assert!((f("dent_distance") - 0.2).abs() < 1e-6);
    assert!((f("sigma") - 0.1).abs() < 1e-6, "σ defaults to d/2");
    assert_eq!(json["heat_iters"], 8);
    assert_eq!(json["clamp_iters"], 16);
    assert_eq!(f("widen"), 0.0);
    assert!(f("theta_deg").abs() < 1e-3, "head-on by default");

    let res = json["zbuffer_grid"]["res"].as_u64().unwrap() as usize;
    let res_d = json["dentmap_grid"]["res"].as_u64().unwrap() as usize;
    assert!(res >= 25, "automatic resolution {res}");
    for stage in ["zbuffer", "envelope", "smoothed"] {
        let (shape, values) = read_npy_f32(out.join(format!("{stage}.npy"))).unwrap();
        assert_eq!(shape, vec![res, res], "{stage}");
        assert!(values.iter().all(|v| v.is_finite() && *v >= 0.0), "{stage}");
    }
    let (shape, vectors) = read_npy_f32(out.join("dentmap.npy")).unwrap();
    assert_eq!(shape, vec![res_d, res_d, 3]);
    assert!(vectors.iter().all(|v| v.is_finite()));
    for stage in ["zbuffer", "envelope", "smoothed"] {
        let png = image::open(out.join(format!("{stage}.png"))).unwrap();
        assert_eq!((png.width() as usize, png.height() as usize), (res, res), "{stage}.png");
    }
    let png = image::open(out.join("dentmap.png")).unwrap();
    assert_eq!((png.width() as usize, png.height() as usize), (res_d, res_d));

    // The profile peaks at d.
    let (_, zbuffer) = read_npy_f32(out.join("zbuffer.npy")).unwrap();
    let peak = zbuffer.iter().copied().fold(0.0f32, f32::max);
    assert!((peak - 0.2).abs() <= 1e-5 * 0.2, "zbuffer max {peak}");
    // Head-on along +z, the dent pushes along +z with length d at most.
    let longest = vectors.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2]).length()).fold(0.0, f32::max);
    assert!(longest > 0.19 && longest < 0.2 * (1.0 + 1e-4), "longest displacement {longest}");
}

#[test]
fn zbuffer_origin_is_the_most_advanced_point() {
    let dir = TempDir::new("origin");
    let bunny = dentbend::mesh::builtin("bunny").unwrap();
    let scale = {
        let (lo, hi) = bunny.bounds();
        lo.distance(hi)
    };
    for (extra, label) in [
        (vec![], "default"),
        (vec!["--normal", "0,1,0"], "normal +y"),
        (vec!["--normal", "0,0,1", "--velocity", "1,0,1"], "glancing 45°"),
        (vec!["--rotate", "30,-20,10", "--normal=-1,0,0"], "rotated, normal -x"),
    ] {
        let (out, _) = run_ok(&dir, &extra);
        let json = read_json(&out.join("dentmap.json"));
        let grid = &json["zbuffer_grid"];
        let origin = vec3(&grid["origin"]);
        let axis_z = vec3(&grid["axis_z"]);
        let mut projectile = bunny.clone();
        if let Some(deg) = json.get("rotate_deg").map(vec3).filter(|r| *r != Vec3::ZERO) {
            let r = deg * (std::f32::consts::PI / 180.0);
            let m = dentbend::glam::Mat3::from_rotation_z(r.z)
                * dentbend::glam::Mat3::from_rotation_y(r.y)
                * dentbend::glam::Mat3::from_rotation_x(r.x);
            projectile.transform(dentbend::glam::Affine3A::from_mat3(m)).unwrap();
        }
        let tip =
            projectile.positions().iter().copied().max_by(|a, b| a.dot(axis_z).total_cmp(&b.dot(axis_z))).unwrap();
        assert!(
            (origin.dot(axis_z) - tip.dot(axis_z)).abs() <= 1e-5 * scale,
            "{label}: origin {origin} is not at the tip {tip} along {axis_z}"
        );
        assert!(origin.distance(tip) <= 1e-4 * scale, "{label}: origin {origin}, tip vertex {tip}");
        if label == "glancing 45°" {
            let theta = json["theta_deg"].as_f64().unwrap();
            assert!((theta - 45.0).abs() < 1e-3, "θ = {theta}");
            assert!(json["dentmap_grid"]["res"].as_u64() > grid["res"].as_u64(), "glancing map is stretched");
        }
        std::fs::remove_dir_all(&out).unwrap();
    }
}

#[test]
fn fixed_resolution_and_options_are_recorded() {
    let dir = TempDir::new("res64");
    let (out, _) =
        run_ok(&dir, &["--res", "64", "--sigma", "0.05", "--heat-iters", "3", "--clamp-iters", "5", "--widen", "2.5"]);
    let json = read_json(&out.join("dentmap.json"));
    assert_eq!(json["zbuffer_grid"]["res"], 64);
    assert!((json["sigma"].as_f64().unwrap() - 0.05).abs() < 1e-7);
    assert_eq!(json["heat_iters"], 3);
    assert_eq!(json["clamp_iters"], 5);
    assert!((json["widen"].as_f64().unwrap() - 2.5).abs() < 1e-7);
    for stage in ["zbuffer", "envelope", "smoothed"] {
        let (shape, _) = read_npy_f32(out.join(format!("{stage}.npy"))).unwrap();
        assert_eq!(shape, vec![64, 64]);
    }
}

/// Runs `dentmap` with `args` replacing the defaults and checks the failure.
fn assert_fails(args: &[&str], out: &Path, what: &str) {
    let output = dentbend(args);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{what}: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "{what}: one line expected, got {stderr:?}");
    assert!(stderr.starts_with("error: "), "{what}: {stderr}");
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    assert!(!out.join("dentmap.json").exists(), "{what}: output written anyway");
}

#[test]
fn bad_input_exits_with_code_2_and_one_line() {
    let dir = TempDir::new("bad");
    let out = dir.path("out");
    let out_s = out.to_str().unwrap().to_owned();
    let garbage = dir.path("garbage.obj");
    std::fs::write(&garbage, "this is not\nan OBJ file\nf 1 2 3 4 x\n").unwrap();
    let missing = dir.path("missing.obj");
    let base = |extra: &[&str]| -> Vec<String> {
        let mut args: Vec<String> =
            ["dentmap", "--projectile", "bunny", "--dent-distance", "0.2", "--out", &out_s].map(String::from).to_vec();
        args.extend(extra.iter().map(|s| s.to_string()));
        args
    };
    let cases: Vec<(Vec<String>, &str)> = vec![
        (base(&["--normal", "0,0,0"]), "zero normal"),
        (base(&["--normal", "1,2"]), "two components"),
        (base(&["--normal", "a,b,c"]), "not numbers"),
        (base(&["--normal", "nan,0,1"]), "NaN"),
        (base(&["--velocity", "inf,0,1"]), "infinite"),
        (base(&["--velocity", "0,0,-1"]), "separating"),
        (base(&["--res", "0"]), "res 0"),
        (base(&["--res", "100000"]), "res 100000"),
        (base(&["--sigma", "-1"]), "negative sigma"),
        (base(&["--rotate", "1,2"]), "bad rotation"),
        (
            ["dentmap", "--projectile", "bunny", "--dent-distance", "-1", "--out", &out_s].map(String::from).to_vec(),
            "negative d",
        ),
        (
            ["dentmap", "--projectile", missing.to_str().unwrap(), "--dent-distance", "0.2", "--out", &out_s]
                .map(String::from)
                .to_vec(),
            "missing file",
        ),
        (
            ["dentmap", "--projectile", garbage.to_str().unwrap(), "--dent-distance", "0.2", "--out", &out_s]
                .map(String::from)
                .to_vec(),
            "garbage OBJ",
        ),
        (["dentmap", "--projectile", "bunny", "--out", &out_s].map(String::from).to_vec(), "no dent distance"),
    ];
    for (args, what) in &cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        assert_fails(&args, &out, what);
    }
    // An output "directory" that is a file cannot be written.
    let file = dir.path("a-file");
    std::fs::write(&file, "x").unwrap();
    let output =
        dentbend(&["dentmap", "--projectile", "bunny", "--dent-distance", "0.2", "--out", file.to_str().unwrap()]);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.starts_with("error: ") && stderr.lines().count() == 1, "{stderr}");
}

#[test]
fn help_documents_the_interface() {
    let output = dentbend(&["dentmap", "--help"]);
    assert!(output.status.success());
    let help = text(&output.stdout);
    for flag in [
        "--projectile",
        "--rotate",
        "--normal",
        "--velocity",
        "--dent-distance",
        "--res",
        "--sigma",
        "--heat-iters",
        "--clamp-iters",
        "--widen",
        "--out",
        "Rz·Ry·Rx",
    ] {
        assert!(help.contains(flag), "help lacks {flag}");
    }
}
