//! `dentbend run plank` and `run arm`: a bending body is written as its skinned mesh (not its
//! sub-bodies), and `summary.json` lists the joints dynamic articulation made and the plastic
//! bends.

mod common;

use common::temp::TempDir;
use common::{dentbend, text};
use dentbend::gpu::GpuContext;

fn a_plank_run_writes_the_skinned_plank_and_its_joint() {
    let dir = TempDir::new("run-plank");
    let out = dir.path("plank");
    let out_text = out.to_str().unwrap();
    let args =
        ["run", "plank", "--size", "demo", "--frames", "20", "--every", "10", "--picture", "0,0", "--meshes", "all"];
    let output = dentbend(&[&args[..], &["--out", out_text]].concat());
    assert!(output.status.success(), "{}", text(&output.stderr));
    let meshes = out.join("meshes");
    for frame in ["0000", "0010", "0020"] {
        for extension in ["obj", "glb"] {
            let file = meshes.join(format!("plank_{frame}.{extension}"));
            assert!(file.is_file(), "missing {}", file.display());
        }
    }
    let names: Vec<String> =
        std::fs::read_dir(&meshes).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert!(names.iter().all(|n| !n.contains("bone")), "sub-body meshes written: {names:?}");
    // The skinned plank has every vertex of the rest plank (64 segments).
    let first = dentbend::mesh::load(meshes.join("plank_0000.obj")).unwrap();
    let rest = dentbend::mesh::plank(4.0, 0.3, 0.1, 64).unwrap();
    assert_eq!(first.vertex_count(), rest.vertex_count());

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for key in ["scene", "frames", "dt", "bodies", "ms_per_step", "steps", "dents"] {
        assert!(!summary[key].is_null(), "summary lacks {key}");
    }
    let joints = summary["joints"].as_array().unwrap();
    assert_eq!(joints.len(), 1, "{joints:?}");
    assert_eq!(joints[0]["body"], "plank");
    assert!(joints[0]["frame"].as_u64().is_some_and(|f| (1..=20).contains(&f)));
    let x = joints[0]["position"][0].as_f64().unwrap();
    assert!((x - 0.3).abs() < 0.05, "joint at x = {x}");
    let bends = summary["bends"].as_array().unwrap();
    assert!(!bends.is_empty() && bends.iter().all(|b| b["angle"].as_f64().is_some_and(|a| a > 0.0)));
    let bodies: Vec<&str> = summary["bodies"].as_array().unwrap().iter().map(|b| b.as_str().unwrap()).collect();
    assert!(bodies.contains(&"plank") && !bodies.iter().any(|b| b.contains('/')), "{bodies:?}");
}

/// `dentbend run scenes/bent_bar.toml`: a bending body from a scene file is written as its skinned
/// mesh, and its plastic joints bend (the ball hits at about frame 4 of 20).
fn a_scene_file_with_a_bending_body_runs() {
    let dir = TempDir::new("run-bent-bar");
    let out = dir.path("bent_bar");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/bent_bar.toml");
    let args = [
        "run",
        scene,
        "--frames",
        "20",
        "--every",
        "10",
        "--picture",
        "0,0",
        "--meshes",
        "all",
        "--out",
        out.to_str().unwrap(),
    ];
    let output = dentbend(&args);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let meshes = out.join("meshes");
    for frame in ["0000", "0010", "0020"] {
        let file = meshes.join(format!("bar_{frame}.obj"));
        assert!(file.is_file(), "missing {}", file.display());
    }
    let names: Vec<String> =
        std::fs::read_dir(&meshes).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert!(names.iter().all(|n| !n.contains("bone")), "sub-body meshes written: {names:?}");
    let last = dentbend::mesh::load(meshes.join("bar_0020.obj")).unwrap();
    assert!(last.positions().iter().all(|p| p.is_finite()));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["scene"], "bent_bar");
    let bodies: Vec<&str> = summary["bodies"].as_array().unwrap().iter().map(|b| b.as_str().unwrap()).collect();
    assert_eq!(bodies, ["ball", "bar"]);
    let bends = summary["bends"].as_array().unwrap();
    assert!(!bends.is_empty() && bends.iter().all(|b| b["angle"].as_f64().is_some_and(|a| a > 0.0)), "{bends:?}");
}

/// `summary.json` says where the bending bodies were skinned: with `--backend gpu` on the GPU
/// every step (each step's `skinning_ms` positive), with `--backend cpu` on the CPU twin for the
/// output frames only (each step's `skinning_ms` 0); the output frames' meshes are written
/// either way.
fn the_summary_says_where_skinning_ran(context: Option<&'static GpuContext>) {
    let dir = TempDir::new("run-plank-skin");
    let backend = if context.is_some() { "gpu" } else { "cpu" };
    let out = dir.path(backend);
    let args =
        ["run", "plank", "--size", "demo", "--frames", "3", "--every", "3", "--picture", "0,0", "--meshes", "all"];
    let output = dentbend(&[&args[..], &["--backend", backend, "--out", out.to_str().unwrap()]].concat());
    assert!(output.status.success(), "{backend}: {}", text(&output.stderr));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["skin_on"], backend);
    // The output frames' plank meshes, read back from the GPU or skinned on the CPU.
    for frame in ["0000", "0003"] {
        let plank = dentbend::mesh::load(out.join(format!("meshes/plank_{frame}.obj"))).unwrap();
        assert_eq!(plank.vertex_count(), dentbend::mesh::plank(4.0, 0.3, 0.1, 64).unwrap().vertex_count());
    }
    let steps = summary["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 3);
    for step in steps {
        let ms = step["skinning_ms"].as_f64().unwrap_or_else(|| panic!("{backend}: {step}"));
        assert!(if backend == "gpu" { ms > 0.0 && ms.is_finite() } else { ms == 0.0 }, "{backend}: {step}");
    }
    let mean = summary["ms_per_step"]["skinning_mean"].as_f64().unwrap();
    assert!(mean.is_finite(), "{backend}: skinning_mean {mean}");
}

/// `dentbend run arm` (Figure 15): the condensed armadillo is written as one skinned mesh (neither
/// its sub-bodies nor the clusters' stand-ins are listed or written), and `summary.json` lists no
/// made joints and bends of exactly the four arm joints: the skeleton's joints are made in bone
/// order, so with 12 torso bones in the demo they are the world joints 11–14 (the joints inside
/// the torso are 0–10, the glue to the stand 15).
fn an_arm_run_lists_the_bends_of_its_four_arm_joints() {
    let dir = TempDir::new("run-arm");
    let out = dir.path("arm");
    let args = ["run", "arm", "--size", "demo", "--frames", "60", "--every", "60", "--picture", "0,0"];
    let output = dentbend(&[&args[..], &["--meshes", "dentable", "--out", out.to_str().unwrap()]].concat());
    assert!(output.status.success(), "{}", text(&output.stderr));
    let mut names: Vec<String> = std::fs::read_dir(out.join("meshes"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["armadillo_0000.glb", "armadillo_0000.obj", "armadillo_0060.glb", "armadillo_0060.obj"]);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let bodies: Vec<&str> = summary["bodies"].as_array().unwrap().iter().map(|b| b.as_str().unwrap()).collect();
    assert_eq!(bodies, ["stand", "ball", "armadillo"]);
    assert_eq!(summary["joints"].as_array().map(Vec::len), Some(0));
    let bends = summary["bends"].as_array().unwrap();
    let mut joints: Vec<u64> = bends.iter().map(|b| b["joint"].as_u64().unwrap()).collect();
    joints.sort_unstable();
    joints.dedup();
    assert_eq!(joints, [11, 12, 13, 14], "{bends:?}");
    assert!(bends.iter().all(|b| b["angle"].as_f64().is_some_and(|a| a > 0.0) && b["frame"].as_u64().is_some()));
}

gpu_test_main! {
    plain: [
        a_plank_run_writes_the_skinned_plank_and_its_joint,
        a_scene_file_with_a_bending_body_runs,
        an_arm_run_lists_the_bends_of_its_four_arm_joints,
    ],
    both: [the_summary_says_where_skinning_ran],
}
