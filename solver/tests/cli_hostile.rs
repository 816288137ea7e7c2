//! The command line against hostile input: every refusal is one `error:` line and exit
//! code 2, and leaves files as they were — existing files untouched, no partial or stray files.

mod common;

use std::path::Path;

use common::temp::TempDir;
use common::{dentbend, text};

/// Asserts a refusal: exit code 2, exactly one `error:` line, containing every one of `words`.
fn assert_refused(output: &std::process::Output, words: &[&str]) {
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{stderr}");
    for word in words {
        assert!(errors[0].contains(word), "`{word}` missing from: {}", errors[0]);
    }
}

/// Every file under `dir`, relative paths, sorted.
fn files_under(dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(next) = stack.pop() {
        for entry in std::fs::read_dir(&next).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                found.push(path.strip_prefix(dir).unwrap().display().to_string());
            }
        }
    }
    found.sort();
    found
}

#[test]
fn an_unsupported_picture_format_leaves_the_existing_file_untouched() {
    let dir = TempDir::new("hostile-format");
    for name in ["existing.jpg", "existing.gif", "existing.tiff", "existing"] {
        let path = dir.path(name);
        std::fs::write(&path, b"precious").unwrap();
        let output = dentbend(&["render", "--mesh", "sphere", "--size", "32,32", "--out", path.to_str().unwrap()]);
        assert_refused(&output, &["--out", ".png"]);
        assert_eq!(std::fs::read(&path).unwrap(), b"precious", "{name} was changed");
    }
    assert_eq!(files_under(dir.root()).len(), 4, "stray files: {:?}", files_under(dir.root()));
}

#[test]
fn a_failed_write_leaves_no_partial_file_and_the_old_one_intact() {
    let dir = TempDir::new("hostile-write");
    // The summary's place is taken by a folder: the run fails at its last write.
    let out = dir.path("run");
    std::fs::create_dir_all(out.join("summary.json")).unwrap();
    let output = dentbend(&["run", "pair", "--frames", "2", "--picture", "0,0", "--out", out.to_str().unwrap()]);
    assert_refused(&output, &["summary.json"]);
    let hidden: Vec<String> =
        files_under(&out).into_iter().filter(|f| f.contains("/.") || f.starts_with('.')).collect();
    assert!(hidden.is_empty(), "temporary files left behind: {hidden:?}");
    // A picture over an existing one is replaced whole.
    let picture = dir.path("p.png");
    std::fs::write(&picture, b"old").unwrap();
    let output = dentbend(&["render", "--mesh", "sphere", "--size", "16,8", "--out", picture.to_str().unwrap()]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert_eq!(image::open(&picture).unwrap().width(), 16);
    assert_eq!(files_under(dir.root()).iter().filter(|f| !f.starts_with("run")).count(), 1);
}

#[test]
fn body_names_that_share_a_file_are_refused_before_anything_is_written() {
    let dir = TempDir::new("hostile-names");
    let scene = dir.path("twins.toml");
    let body = |name: &str, x: f32| format!("[[body]]\nname = \"{name}\"\nmesh = \"sphere\"\nposition = [{x}, 0, 0]\n");
    std::fs::write(&scene, format!("frames = 2\n{}{}", body("a/b", 0.0), body("a_b", 3.0))).unwrap();
    let out = dir.path("out");
    let output = dentbend(&["run", scene.to_str().unwrap(), "--meshes", "all", "--out", out.to_str().unwrap()]);
    assert_refused(&output, &["\"a/b\"", "\"a_b\"", "rename"]);
    assert!(!out.exists(), "{} was created", out.display());
}

#[test]
fn absurd_counts_are_refused_up_front_with_the_estimate() {
    let dir = TempDir::new("hostile-counts");
    let out = dir.path("out");
    let out_text = out.to_str().unwrap();
    // A billion frames: about 200 GB of step records.
    let output = dentbend(&["run", "pair", "--frames", "1000000000", "--out", out_text]);
    assert_refused(&output, &["too large", "GB", "--allow-large"]);
    assert!(!out.exists());
    // A scene file's frames likewise.
    let scene = dir.path("long.toml");
    std::fs::write(&scene, "frames = 1000000000\n[[body]]\nname = \"ball\"\nmesh = \"sphere\"\n").unwrap();
    assert_refused(&dentbend(&["run", scene.to_str().unwrap(), "--out", out_text]), &["too large", "--allow-large"]);
    // Every built-in mesh written at every frame of a long run: too many files.
    let output = dentbend(&["run", "rain", "--meshes", "all", "--every", "1", "--out", out_text]);
    assert_refused(&output, &["files", "--allow-large"]);
    assert!(!out.exists());
    // Zero frames and pictures beyond 8192 × 8192.
    assert_refused(&dentbend(&["run", "pair", "--frames", "0", "--out", out_text]), &["--frames", "at least 1"]);
    let output = dentbend(&["run", "pair", "--picture", "100000,100000", "--out", out_text]);
    assert_refused(&output, &["too large"]);
    let output = dentbend(&[
        "render",
        "--mesh",
        "sphere",
        "--size",
        "16384,16384",
        "--out",
        dir.path("x.png").to_str().unwrap(),
    ]);
    assert_refused(&output, &["too large"]);
    assert!(!out.exists() && !dir.path("x.png").exists());
}

#[test]
fn too_many_bodies_in_a_scene_file_are_refused_before_their_meshes_load() {
    let dir = TempDir::new("hostile-bodies");
    let scene = dir.path("crowd.toml");
    let bodies: String = (0..10_001)
        .map(|k| format!("[[body]]\nname = \"b{k}\"\nmesh = \"box\"\nposition = [{}, 0, 0]\n", 3 * k))
        .collect();
    std::fs::write(&scene, bodies).unwrap();
    let output = dentbend(&["run", scene.to_str().unwrap(), "--out", dir.path("out").to_str().unwrap()]);
    assert_refused(&output, &["10001 bodies", "10000"]);
}

#[test]
fn gltf_buffers_and_scene_meshes_stay_inside_their_folder() {
    let dir = TempDir::new("hostile-paths");
    let assets = dir.path("assets");
    std::fs::create_dir_all(&assets).unwrap();
    std::fs::write(dir.path("secret.bin"), [0u8; 64]).unwrap();
    // A glTF whose buffer points two folders up.
    let gltf = assets.join("evil.gltf");
    std::fs::write(
        &gltf,
        r#"{"asset":{"version":"2.0"},"buffers":[{"uri":"../secret.bin","byteLength":64}],
            "bufferViews":[{"buffer":0,"byteLength":36}],
            "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],
            "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]}"#,
    )
    .unwrap();
    let output = dentbend(&["render", "--mesh", gltf.to_str().unwrap(), "--out", dir.path("x.png").to_str().unwrap()]);
    assert_refused(&output, &["../secret.bin", ".."]);
    // A scene file naming a mesh outside its folder, by `..` and by an absolute path.
    std::fs::write(dir.path("outside.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
        .unwrap();
    let out = dir.path("out");
    for mesh in ["../outside.obj".to_owned(), dir.path("outside.obj").display().to_string()] {
        let scene = assets.join("scene.toml");
        std::fs::write(&scene, format!("frames = 1\n[[body]]\nname = \"t\"\nmesh = \"{mesh}\"\n")).unwrap();
        let args = ["run", scene.to_str().unwrap(), "--picture", "0,0", "--out", out.to_str().unwrap()];
        assert_refused(&dentbend(&args), &["--trust-paths"]);
        assert!(!out.exists());
        // The opt-out for trusted files.
        let output = dentbend(&[&args[..], &["--trust-paths"]].concat());
        assert!(output.status.success(), "{}", text(&output.stderr));
        std::fs::remove_dir_all(&out).unwrap();
    }
    // A folder where a mesh should be.
    std::fs::create_dir_all(assets.join("folder.obj")).unwrap();
    let scene = assets.join("scene.toml");
    std::fs::write(&scene, "frames = 1\n[[body]]\nname = \"t\"\nmesh = \"folder.obj\"\n").unwrap();
    assert_refused(&dentbend(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]), &["is a directory"]);
}

#[test]
fn magnitudes_beyond_the_supported_range_name_the_real_problem() {
    let dir = TempDir::new("hostile-magnitudes");
    let out = dir.path("dented.obj");
    let out_text = out.to_str().unwrap();
    let big = dir.path("big.obj");
    std::fs::write(&big, "v 1e38 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n").unwrap();
    let dent = |extra: &[&str]| {
        let base = ["dent", "--target", "block", "--point", "0,0.5,0", "--normal", "0,-1,0", "--out", out_text];
        dentbend(&[&base[..], extra].concat())
    };
    let big_text = big.to_str().unwrap();
    assert_refused(&dent(&["--projectile", big_text, "--dent-distance", "0.1"]), &["beyond ±1e6", "coordinate"]);
    assert_refused(&dent(&["--projectile", "sphere", "--scale", "1e30", "--dent-distance", "0.1"]), &["beyond ±1e6"]);
    assert_refused(&dent(&["--projectile", "sphere", "--dent-distance", "1e30"]), &["--dent-distance", "at most 1e6"]);
    assert_refused(
        &dent(&["--projectile", "sphere", "--dent-distance", "0.1", "--velocity", "0,-1e30,0"]),
        &["faster than"],
    );
    assert_refused(&dentbend(&["render", "--mesh", big_text, "--out", dir.path("p.png").to_str().unwrap()]), &["±1e6"]);
    assert!(!out.exists() && !dir.path("p.png").exists());
    // Scene files: each value at its line.
    for (field, value, words) in [
        ("position", "[1e30, 0, 0]", &["position", "±1e6"][..]),
        ("velocity", "[0, -1e30, 0]", &["velocity", "1e5"][..]),
        ("angular_velocity", "[0, 1e9, 0]", &["angular_velocity", "1e4"][..]),
    ] {
        let scene = dir.path("fast.toml");
        std::fs::write(&scene, format!("frames = 1\n[[body]]\nname = \"b\"\nmesh = \"sphere\"\n{field} = {value}\n"))
            .unwrap();
        let output = dentbend(&["run", scene.to_str().unwrap(), "--out", dir.path("o").to_str().unwrap()]);
        assert_refused(&output, &[&[":5:"][..], words].concat());
    }
}

#[test]
fn every_builtin_scene_at_its_defaults_stays_within_the_output_budget() {
    let dir = TempDir::new("hostile-defaults");
    let out = dir.path("out");
    for scene in dentbend_solver::scene::BUILTIN_SCENES {
        let output = dentbend(&["run", scene, "--estimate", "--out", out.to_str().unwrap()]);
        let stdout = text(&output.stdout);
        assert!(output.status.success(), "{scene}: {}", text(&output.stderr));
        assert!(stdout.contains("within the budget"), "{scene}: {stdout}");
    }
    assert!(!out.exists(), "--estimate wrote {}", out.display());
    // And the estimate is honest: a real run writes within a factor of two of it.
    let output =
        dentbend(&["run", "rain", "--size", "demo", "--frames", "20", "--estimate", "--out", out.to_str().unwrap()]);
    let stdout = text(&output.stdout);
    let files: u64 = stdout.split(" in ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    let output = dentbend(&["run", "rain", "--size", "demo", "--frames", "20", "--out", out.to_str().unwrap()]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let written = files_under(&out);
    let bytes: u64 = written.iter().map(|f| std::fs::metadata(out.join(f)).unwrap().len()).sum();
    assert_eq!(written.len() as u64, files, "{written:?}");
    let estimated = stdout.split("about ").nth(1).unwrap();
    let (value, unit) = estimated.split_once(' ').unwrap();
    let scale = match unit.split(' ').next().unwrap() {
        "MB" => 1e6,
        "kB" => 1e3,
        "GB" => 1e9,
        other => panic!("unit {other}"),
    };
    let estimated_bytes = value.parse::<f64>().unwrap() * scale;
    let ratio = estimated_bytes / bytes as f64;
    assert!((0.5..=2.0).contains(&ratio), "estimated {estimated_bytes} B, wrote {bytes} B");
}

#[test]
fn a_successful_gpu_run_on_a_headless_machine_prints_no_driver_errors() {
    // As on CI and render farms: no display, no XDG_RUNTIME_DIR. `auto` takes the GPU when an
    // adapter exists (lavapipe on CI) and the CPU otherwise; either way the run succeeds and
    // stderr has no `error:` line from a driver's layer.
    let dir = TempDir::new("hostile-noise");
    let picture = dir.path("sphere.png");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_dentbend"))
        .args(["render", "--mesh", "sphere", "--size", "64,64", "--backend", "auto", "--out"])
        .arg(&picture)
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("DISPLAY")
        .env_remove("NODEVICE_SELECT")
        .env_remove("RUST_LOG")
        .output()
        .unwrap();
    let stderr = text(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(!stderr.lines().any(|l| l.trim_start().starts_with("error")), "driver noise: {stderr}");
    assert!(picture.is_file());
}
