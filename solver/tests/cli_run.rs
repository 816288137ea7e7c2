//! `dentbend run`: the files a scene run writes, and clear errors that write nothing.

mod common;

use common::temp::TempDir;
use common::{dentbend, text};

#[test]
fn a_run_writes_meshes_frames_and_a_summary() {
    let dir = TempDir::new("run-pair");
    let out = dir.path("pair");
    let out_text = out.to_str().unwrap();
    let output = dentbend(&[
        "run", "pair", "--size", "demo", "--frames", "40", "--every", "20", "--meshes", "all", "--out", out_text,
    ]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    for frame in ["0000", "0020", "0040"] {
        for body in ["left", "right"] {
            for extension in ["obj", "glb"] {
                let file = out.join("meshes").join(format!("{body}_{frame}.{extension}"));
                assert!(file.is_file(), "missing {}", file.display());
            }
        }
        let picture = image::open(out.join("frames").join(format!("{frame}.png"))).unwrap();
        assert_eq!((picture.width(), picture.height()), (960, 640));
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["frames"], 40);
    let split = &summary["ms_per_step"];
    for key in ["dynamics_mean", "denting_mean", "total_mean"] {
        assert!(split[key].as_f64().is_some_and(|v| v >= 0.0), "{key}: {split}");
    }
    // Figure 1: the balls meet once and dent each other, each record naming both bodies.
    let dents = summary["dents"].as_array().unwrap();
    assert_eq!(dents.len(), 2, "{dents:?}");
    let mut targets: Vec<&str> = dents.iter().map(|d| d["target"].as_str().unwrap()).collect();
    targets.sort_unstable();
    assert_eq!(targets, ["left", "right"]);
    for dent in dents {
        for key in ["frame", "projectile", "point", "normal", "relative_velocity", "dent_distance"] {
            assert!(!dent[key].is_null(), "dent lacks {key}: {dent}");
        }
        assert!(dent["dent_distance"].as_f64().unwrap() > 0.0);
    }
}

#[test]
fn a_bad_scene_is_one_error_line_and_writes_nothing() {
    let dir = TempDir::new("run-bad");
    let scene = dir.path("bad.toml");
    std::fs::write(&scene, "frames = 10\n[[body]]\nname = \"ball\"\nmesh = \"sphere\"\nvelocity = [nan, 0, 0]\n")
        .unwrap();
    let out = dir.path("out");
    for spec in [scene.to_str().unwrap(), "no-such-scene"] {
        let output = dentbend(&["run", spec, "--out", out.to_str().unwrap()]);
        assert_eq!(output.status.code(), Some(2));
        let stderr = text(&output.stderr);
        let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(errors.len(), 1, "{stderr}");
        assert!(!out.exists(), "{} was created", out.display());
    }
    let output = dentbend(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let stderr = text(&output.stderr);
    assert!(stderr.contains("bad.toml") && stderr.contains("velocity") && stderr.contains(":5"), "{stderr}");
}

/// `dentbend run --help` names every built-in scene (the list is written out in its text).
#[test]
fn the_help_names_every_built_in_scene() {
    let output = dentbend(&["run", "--help"]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let help = text(&output.stdout);
    for name in dentbend_solver::scene::BUILTIN_SCENES {
        assert!(help.contains(name), "`run --help` does not name the built-in scene {name}");
    }
}
