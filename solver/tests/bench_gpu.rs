//! `dentbend-bench gpu --stages kernels|all` end to end: the GPU batch with the kernels alone and
//! with every stage around them (refinement, fitted falloff, volume rim, guard), each reporting
//! its stage set and a throughput, the kernels' per-stage times only where they are timed alone.
//! Without an adapter it stops with an error (a failure when `DENTBEND_REQUIRE_GPU=1`, as in CI).

mod common;

use std::process::Command;

use common::{TempDir, text};
use serde_json::Value;

/// The report of `dentbend-bench gpu` on two blocks, 16² grids, batches of 2, with `stages`;
/// `None` when no adapter exists and none is required.
fn gpu_report(stages: &str) -> Option<Value> {
    let dir = TempDir::new("bench-gpu");
    let json = dir.path("gpu.json");
    let args = ["gpu", "--res", "16", "--batch", "2", "--targets", "2", "--min-time", "0", "--stages", stages];
    let output = Command::new(env!("CARGO_BIN_EXE_dentbend-bench"))
        .args(args)
        .args(["--json", json.to_str().unwrap()])
        .env_remove("RUST_LOG")
        .output()
        .unwrap();
    let required = std::env::var("DENTBEND_REQUIRE_GPU").as_deref() == Ok("1");
    if !output.status.success() && !required {
        assert!(!json.exists(), "a failed run wrote a report");
        return None;
    }
    assert!(output.status.success(), "dentbend-bench gpu --stages {stages}: {}", text(&output.stderr));
    Some(serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap())
}

#[test]
fn both_stage_sets_report_their_throughput() {
    let (Some(kernels), Some(all)) = (gpu_report("kernels"), gpu_report("all")) else { return };
    for (report, name) in [(&kernels, "kernels"), (&all, "all")] {
        assert_eq!(report["stages"], name);
        let row = &report["rows"][0];
        assert!(row["gpu_dents_per_s"].as_f64().is_some_and(|r| r > 0.0), "{report}");
        assert!(row["cpu_dents_per_s"].as_f64().is_some_and(|r| r > 0.0), "{report}");
    }
    assert!(kernels["rows"][0]["kernels_s"].as_object().is_some_and(|k| k.contains_key("heat")), "{kernels}");
    assert!(all["rows"][0]["kernels_s"].as_object().is_some_and(|k| k.is_empty()), "{all}");
}

#[test]
fn an_unknown_stage_set_is_refused() {
    let output = Command::new(env!("CARGO_BIN_EXE_dentbend-bench"))
        .args(["gpu", "--stages", "some"])
        .env_remove("RUST_LOG")
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).contains("kernels"), "{}", text(&output.stderr));
}
