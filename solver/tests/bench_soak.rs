//! `dentbend-bench soak` end to end: the real binary dents the built-in block 50 times and its
//! JSON report has every key with sane values; the same seed gives the same surface; drawn
//! projectile sizes and depths, a wider cone and the GPU backend; bad input exits with code 2
//! and writes no report.

mod common;

use std::process::{Command, Output};

use common::{TempDir, text};
use serde_json::Value;

/// Dents per run: enough for several dents on each face, quick in a debug build.
const DENTS: u64 = 50;

/// Runs `dentbend-bench` with `args`.
fn bench(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dentbend-bench")).args(args).env_remove("RUST_LOG").output().unwrap()
}

/// The JSON report of a soak of the block with `seed`.
fn soak(seed: u64) -> Value {
    let dir = TempDir::new("soak");
    let json = dir.path("soak.json");
    let output =
        bench(&["soak", "--dents", &DENTS.to_string(), "--seed", &seed.to_string(), "--json", json.to_str().unwrap()]);
    assert!(output.status.success(), "soak failed: {}", text(&output.stderr));
    serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap()
}

fn number(report: &Value, path: &[&str]) -> f64 {
    let value = path.iter().fold(report, |v, key| &v[*key]);
    value.as_f64().unwrap_or_else(|| panic!("{path:?} is not a number: {value}"))
}

#[test]
fn soak_reports_every_key_without_failures() {
    let r = soak(7);
    assert_eq!(r["target"], "block");
    assert_eq!(r["dents"].as_u64(), Some(DENTS));
    assert_eq!(r["errors"].as_u64(), Some(0), "{}", r["error_messages"]);
    assert_eq!(r["non_finite"].as_u64(), Some(0));
    // Every hit is at most 30° off the inward normal, so its dent distance is at least
    // cos 30° of the head-on one, never zero: every hit dents.
    assert_eq!(r["dented"].as_u64(), Some(DENTS));

    let (median, p99, max) = (number(&r, &["median_ms"]), number(&r, &["p99_ms"]), number(&r, &["max_ms"]));
    assert!(0.0 < median && median <= p99 && p99 <= max, "median {median}, p99 {p99}, max {max}");

    // The block is built of right isosceles triangles, quality √3/2 each. 50 small dents leave
    // most of its 24,576 triangles untouched, so the worst cannot rise above √3/2; it must stay
    // a proper triangle (q > 0).
    let first = number(&r, &["min_triangle_quality", "first"]);
    let last = number(&r, &["min_triangle_quality", "last"]);
    assert!((first - 3f64.sqrt() / 2.0).abs() < 1e-6, "first {first}");
    assert!(0.0 < last && last <= first, "last {last}");

    // 4 × 1 × 4: 16 cubic units. Every dent pushes the surface inward, so the volume shrinks;
    // one dent moves vertices at most its distance d deep, over a patch narrower than twice the
    // ball's diameter (the ball's footprint, widened by σ = d/2 and 30° of glancing stretch), so
    // it removes at most d·(4r)², and the 50 dents together at most 2.6 % of the volume.
    assert!((number(&r, &["volume", "first"]) - 16.0).abs() < 1e-4);
    let (d, radius) = (number(&r, &["dent_distance"]), number(&r, &["projectile_radius"]));
    let bound = DENTS as f64 * d * (4.0 * radius).powi(2) / 16.0;
    let change = number(&r, &["volume_change"]);
    assert!(-bound < change && change < 0.0, "volume change {change}, bound {bound}");

    if cfg!(target_os = "linux") {
        let (first, last) = (number(&r, &["peak_rss_mb", "first"]), number(&r, &["peak_rss_mb", "last"]));
        assert!(first > 0.0 && last > 0.0, "peak RSS {first} / {last} MiB");
    } else {
        assert!(r["peak_rss_mb"].is_null());
    }
}

#[test]
fn soak_is_seeded() {
    let (a, b, other) = (soak(11), soak(11), soak(12));
    for key in ["volume", "min_triangle_quality", "mean_triangle_quality"] {
        assert_eq!(a[key]["last"], b[key]["last"], "{key} differs between two runs of one seed");
    }
    assert_ne!(a["volume"]["last"], other["volume"]["last"], "seeds 11 and 12 dented the same");
}

#[test]
fn soak_refuses_bad_input_and_writes_nothing() {
    let dir = TempDir::new("soak-bad");
    let json = dir.path("soak.json");
    for args in [["--dents", "0"], ["--target", "no-such-mesh.obj"]] {
        let output = bench(&["soak", args[0], args[1], "--json", json.to_str().unwrap()]);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        let stderr = text(&output.stderr);
        assert!(stderr.starts_with("error: ") && stderr.lines().count() == 1, "{args:?}: {stderr}");
        assert!(!json.exists(), "{args:?} wrote a report");
    }
}

/// `--projectile-scale`, `--depth` and `--cone-deg` on the block (4 × 1 × 4: size 4, thickness
/// 1): every ball's radius and dent distance are drawn up to the stated maxima, which the report
/// names; big, deep, steep hits turn no face over (the guard limits a dent that would); the
/// medians of the first and last dents (times and vertices moved) are there and ordered like
/// the others.
#[test]
fn soak_draws_sizes_and_depths_and_turns_no_face_over() {
    let dir = TempDir::new("soak-drawn");
    let json = dir.path("soak.json");
    let args = ["--projectile-scale", "0.1", "--depth", "0.05", "--cone-deg", "60", "--json"];
    let output = bench(&[&["soak", "--dents", "20"][..], &args, &[json.to_str().unwrap()]].concat());
    assert!(output.status.success(), "soak failed: {}", text(&output.stderr));
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(r["errors"].as_u64(), Some(0), "{}", r["error_messages"]);
    assert_eq!(r["backend"], "cpu");
    assert_eq!((number(&r, &["target_size"]), number(&r, &["target_thickness"])), (4.0, 1.0));
    assert_eq!((number(&r, &["projectile_scale"]), number(&r, &["depth"])), (0.1f32 as f64, 0.05f32 as f64));
    // f32 products: 0.1 × 4 and 0.05 × 1, to an ulp.
    assert!((number(&r, &["projectile_radius"]) - 0.4).abs() < 1e-6);
    assert!((number(&r, &["dent_distance"]) - 0.05).abs() < 1e-7);
    assert_eq!(number(&r, &["cone_deg"]), 60.0);
    assert_eq!(r["flipped_faces"].as_u64(), Some(0));
    let max = number(&r, &["max_ms"]);
    for key in ["median_first_ms", "median_last_ms"] {
        let m = number(&r, &[key]);
        assert!(0.0 < m && m <= max, "{key} {m}, max {max}");
    }
    // Every dent moved something, and no median exceeds the vertices the closed block has at
    // the end (T/2 + 2 for T triangles, refinement included).
    let checkpoints = r["checkpoints"].as_array().expect("checkpoints");
    let vertices_at_end = number(checkpoints.last().expect("a checkpoint"), &["triangles"]) / 2.0 + 2.0;
    for end in ["first", "last"] {
        let moved = number(&r, &["moved_vertices_median", end]);
        assert!(0.0 < moved && moved <= vertices_at_end, "moved_vertices_median.{end} {moved} of {vertices_at_end}");
    }
}

#[test]
fn soak_refuses_bad_sizes_and_backends() {
    for args in
        [["--projectile-scale", "0"], ["--depth", "nan"], ["--depth", "11"], ["--cone-deg", "90"], ["--backend", "tpu"]]
    {
        let output = bench(&["soak", "--dents", "1", args[0], args[1]]);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        let stderr = text(&output.stderr);
        assert!(stderr.starts_with("error: ") && stderr.contains(args[0]), "{args:?}: {stderr}");
    }
}

/// `--backend gpu` dents through the crate's GPU backend where an adapter exists (Mesa's
/// software Vulkan in CI), and otherwise stops with a clear error, never a panic.
#[test]
fn soak_on_the_gpu_backend_runs_or_names_the_missing_adapter() {
    let dir = TempDir::new("soak-gpu");
    let json = dir.path("soak.json");
    let output = bench(&["soak", "--dents", "2", "--backend", "gpu", "--json", json.to_str().unwrap()]);
    if output.status.success() {
        let r: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        assert_eq!(r["backend"], "gpu");
        assert_eq!(r["errors"].as_u64(), Some(0), "{}", r["error_messages"]);
        assert_eq!(r["dented"].as_u64(), Some(2));
    } else {
        assert_eq!(output.status.code(), Some(2));
        let stderr = text(&output.stderr);
        assert!(stderr.contains("--backend gpu needs a GPU adapter"), "{stderr}");
        assert!(!json.exists());
    }
}
