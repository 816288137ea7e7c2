//! `dentbend run` writes `damage.json`; `dentbend replay DIR/damage.json --out DIR2` rebuilds the
//! final meshes byte for byte (dented bodies, bending bodies, moved rigid bodies), and refuses a
//! damage file that is truncated, tampered with, of another version or of a changed scene with
//! one error line, writing nothing.

mod common;

use std::path::Path;

use common::temp::TempDir;
use common::{dentbend, text};

/// Runs `dentbend` with `args` and asserts success.
fn ok(args: &[&str]) -> String {
    let output = dentbend(args);
    assert!(output.status.success(), "dentbend {args:?}: {}", text(&output.stderr));
    text(&output.stdout)
}

/// The files of `dir/meshes` named for `frame`.
fn frame_files(dir: &Path, frame: u32) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir.join("meshes"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(&format!("{frame:04}.")))
        .collect();
    names.sort();
    names
}

/// Every file `replayed` wrote under meshes/ equals the run's of the same name, byte for byte,
/// and the run wrote no final-frame file the replay did not.
fn assert_same_meshes(run: &Path, replayed: &Path, frame: u32) {
    let names = frame_files(replayed, frame);
    assert!(!names.is_empty());
    assert_eq!(names, frame_files(run, frame), "the replay writes the run's final files");
    for name in &names {
        let (a, b) = (run.join("meshes").join(name), replayed.join("meshes").join(name));
        assert!(std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap(), "{name} differs");
    }
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn a_denting_run_replays_to_byte_identical_meshes() {
    let dir = TempDir::new("replay-ball-block");
    let (a, b) = (dir.path("a"), dir.path("b"));
    let run =
        ["run", "ball-block", "--size", "demo", "--picture", "0,0", "--meshes", "all", "--every", "1000", "--out"];
    ok(&[&run[..], &[a.to_str().unwrap()]].concat());
    let s = summary(&a);
    let dents = s["dents"].as_array().unwrap().len() as u64;
    assert!(dents > 0, "the scene dents");
    assert_eq!(s["damage"]["dents"], dents, "damage.json records every dent");
    let bytes = s["damage"]["bytes"].as_u64().unwrap();
    assert_eq!(bytes, std::fs::metadata(a.join("damage.json")).unwrap().len());
    let per_dent = s["damage"]["bytes_per_dent"].as_f64().unwrap();
    assert!((per_dent - bytes as f64 / dents as f64).abs() < 1e-9);
    let line =
        ok(&["replay", a.join("damage.json").to_str().unwrap(), "--meshes", "all", "--out", b.to_str().unwrap()]);
    assert!(line.contains("bytes/dent"), "{line}");
    let frame = s["frames"].as_u64().unwrap() as u32;
    assert_same_meshes(&a, &b, frame);
    // The dents are in what was compared: a dented body's last mesh is not its first.
    let target = s["dents"][0]["target"].as_str().unwrap();
    let first = std::fs::read(a.join("meshes").join(format!("{target}_0000.obj"))).unwrap();
    let last = std::fs::read(b.join("meshes").join(format!("{target}_{frame:04}.obj"))).unwrap();
    assert!(first != last);
}

#[test]
fn a_bending_run_replays_to_a_byte_identical_frame() {
    let dir = TempDir::new("replay-plank");
    let (a, b) = (dir.path("a"), dir.path("b"));
    ok(&["run", "plank", "--size", "demo", "--picture", "0,0", "--out", a.to_str().unwrap()]);
    let s = summary(&a);
    assert!(!s["bends"].as_array().unwrap().is_empty(), "the plank bends");
    ok(&["replay", a.join("damage.json").to_str().unwrap(), "--out", b.to_str().unwrap()]);
    assert_same_meshes(&a, &b, s["frames"].as_u64().unwrap() as u32);
}

/// Paper Figure 3's wall (demo size: it breaks at about frame 80 of 120): the replay rebuilds
/// the wall's rest from its dents and fracture and each piece from the fracture, and writes the
/// run's final files byte for byte, one per body and piece.
#[test]
fn a_fracturing_run_replays_to_byte_identical_meshes() {
    let dir = TempDir::new("replay-wall");
    let (a, b) = (dir.path("a"), dir.path("b"));
    let run = ["run", "wall", "--size", "demo", "--picture", "0,0", "--meshes", "all", "--every", "1000", "--out"];
    ok(&[&run[..], &[a.to_str().unwrap()]].concat());
    let s = summary(&a);
    let fractures = s["fractures"].as_array().unwrap();
    assert_eq!(fractures.len(), 1, "the wall breaks once");
    let pieces: Vec<&str> = fractures[0]["pieces"].as_array().unwrap().iter().map(|p| p.as_str().unwrap()).collect();
    assert!(pieces.len() >= 10, "{} pieces", pieces.len());
    ok(&["replay", a.join("damage.json").to_str().unwrap(), "--meshes", "all", "--out", b.to_str().unwrap()]);
    let frame = s["frames"].as_u64().unwrap() as u32;
    assert_same_meshes(&a, &b, frame);
    // Every piece and the broken wall are among what was compared.
    let names = frame_files(&b, frame);
    for body in pieces.iter().map(|p| p.replace('/', "_")).chain(["wall".to_owned()]) {
        assert!(names.contains(&format!("{body}_{frame:04}.obj")), "{body} not written: {names:?}");
    }
    // The default output (one glTF scene of the last frame) too.
    let (c, d) = (dir.path("c"), dir.path("d"));
    ok(&["run", "wall", "--size", "demo", "--picture", "0,0", "--out", c.to_str().unwrap()]);
    ok(&["replay", c.join("damage.json").to_str().unwrap(), "--out", d.to_str().unwrap()]);
    assert_same_meshes(&c, &d, frame);
}

/// Replays `damage` into `out`, expecting one error line containing `expected`, and nothing
/// written.
fn refused(damage: &Path, out: &Path, expected: &str) {
    let output = dentbend(&["replay", damage.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = text(&output.stderr);
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{stderr}");
    assert!(errors[0].contains(expected), "expected {expected:?} in {stderr}");
    assert!(!out.exists(), "a refused replay created {}", out.display());
}

#[test]
fn bad_damage_files_are_refused_and_write_nothing() {
    let dir = TempDir::new("replay-bad");
    let a = dir.path("a");
    ok(&["run", "ball-block", "--size", "demo", "--picture", "0,0", "--meshes", "none", "--out", a.to_str().unwrap()]);
    let good = std::fs::read(a.join("damage.json")).unwrap();
    let out = dir.path("b");
    let bad = dir.path("bad.json");
    let value: serde_json::Value = serde_json::from_slice(&good).unwrap();
    let dented = value["bodies"].as_array().unwrap().iter().position(|b| b["dents"].as_u64() > Some(0)).unwrap();

    std::fs::write(&bad, &good[..good.len() / 2]).unwrap();
    refused(&bad, &out, "truncated");

    let mut tampered = value.clone();
    let hash = tampered["bodies"][dented]["final"]["hash"].as_str().unwrap().to_owned();
    let first = if hash.starts_with('0') { '1' } else { '0' };
    let flipped = format!("{first}{}", &hash[1..]);
    tampered["bodies"][dented]["final"]["hash"] = flipped.into();
    std::fs::write(&bad, serde_json::to_vec(&tampered).unwrap()).unwrap();
    refused(&bad, &out, "tampered");

    let mut other_base = value.clone();
    other_base["bodies"][dented]["base"]["hash"] = "0123456789abcdef".into();
    std::fs::write(&bad, serde_json::to_vec(&other_base).unwrap()).unwrap();
    refused(&bad, &out, "recorded on another mesh");

    let mut newer = value.clone();
    newer["version"] = 99.into();
    std::fs::write(&bad, serde_json::to_vec(&newer).unwrap()).unwrap();
    refused(&bad, &out, "version 99 is not supported");

    let mut other_scene = value.clone();
    other_scene["scene"]["spec"] = "pair".into();
    std::fs::write(&bad, serde_json::to_vec(&other_scene).unwrap()).unwrap();
    refused(&bad, &out, "lists bodies");
}

#[test]
fn a_scene_file_changed_since_the_run_is_refused() {
    let dir = TempDir::new("replay-scene-file");
    let scene = dir.path("example.toml");
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/example.toml");
    std::fs::copy(&source, &scene).unwrap();
    let (a, b) = (dir.path("a"), dir.path("b"));
    let args = ["run", scene.to_str().unwrap(), "--frames", "60", "--picture", "0,0", "--out", a.to_str().unwrap()];
    ok(&args);
    ok(&["replay", a.join("damage.json").to_str().unwrap(), "--out", b.to_str().unwrap()]);
    assert_same_meshes(&a, &b, 60);
    let mut text = std::fs::read_to_string(&scene).unwrap();
    text.push_str("\n# edited after the run\n");
    std::fs::write(&scene, text).unwrap();
    refused(&a.join("damage.json"), &dir.path("c"), "was recorded on scene file");
}
