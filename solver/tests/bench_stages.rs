//! `dentbend-bench stages` end to end: the real binary times the paper's dent and the dent with
//! every game stage on, head-on and glancing, on the built-in block; its JSON report has every
//! key, and bad input exits with code 2 and writes no report. (Times are not asserted: they are
//! the benchmark's output, not a property.)

mod common;

use std::process::{Command, Output};

use common::{TempDir, text};
use serde_json::Value;

fn bench(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dentbend-bench")).args(args).env_remove("RUST_LOG").output().unwrap()
}

#[test]
fn stages_reports_both_impacts_and_their_ratios() {
    let dir = TempDir::new("stages");
    let json = dir.path("stages.json");
    let output = bench(&["stages", "--dents", "3", "--target", "block", "--json", json.to_str().unwrap()]);
    assert!(output.status.success(), "stages failed: {}", text(&output.stderr));
    let report: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["target"], "block");
    assert_eq!(report["dents"].as_u64(), Some(3));
    let rows = report["rows"].as_array().expect("rows");
    let impacts: Vec<&str> = rows.iter().map(|r| r["impact"].as_str().unwrap()).collect();
    assert_eq!(impacts, ["head-on", "glancing-60"]);
    for row in rows {
        let (paper, game, ratio) =
            (row["paper_ms"].as_f64().unwrap(), row["game_ms"].as_f64().unwrap(), row["ratio"].as_f64().unwrap());
        assert!(paper > 0.0 && game > 0.0, "{row}");
        // The ratio is the two medians' (to f64 rounding).
        assert!((ratio - game / paper).abs() <= 1e-12 * ratio, "{row}");
    }
}

#[test]
fn stages_refuses_bad_input_and_writes_nothing() {
    let dir = TempDir::new("stages-bad");
    let json = dir.path("stages.json");
    for args in [["--dents", "0", "--target", "block"], ["--dents", "3", "--target", "no-such-mesh.obj"]] {
        let mut all = vec!["stages"];
        all.extend(args);
        all.extend(["--json", json.to_str().unwrap()]);
        let output = bench(&all);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", text(&output.stderr));
        assert!(!json.exists(), "{args:?} wrote a report");
    }
}
