//! The GPU test runner (tests/common/gpu.rs) tells the truth: this file runs its own probe tests
//! again in a child process that sees no GPU (`WGPU_BACKEND` names a backend this platform does
//! not have), where a GPU test must be reported as ignored with the reason and counted as
//! ignored in the summary, the CPU half of a both-backends test must still run, and with
//! `DENTBEND_REQUIRE_GPU=1` the GPU tests must fail.

mod common;

use std::process::Command;

use common::text;
use dentbend::gpu::GpuContext;

/// The child process runs the tests whose names contain this, only.
const PROBES: &str = "probe_";

/// A GPU test for the child to report on: handed a context, it has an adapter.
fn probe_needs_a_gpu(context: &'static GpuContext) {
    assert!(!context.adapter_name().is_empty());
}

/// A both-backends test for the child to report on.
fn probe_runs_on_either_backend(context: Option<&'static GpuContext>) {
    assert!(context.is_none_or(|c| !c.adapter_name().is_empty()));
}

/// Runs this file's probe tests in a process that sees no GPU; its exit code and stdout.
fn probes_without_a_gpu(require_gpu: bool) -> (Option<i32>, String) {
    // A backend wgpu is built without here, so no adapter can be found.
    let absent = if cfg!(target_os = "macos") { "dx12" } else { "metal" };
    let mut command = Command::new(std::env::current_exe().unwrap());
    command.args([PROBES, "--test-threads", "1"]).env("WGPU_BACKEND", absent).env_remove("WGPU_ADAPTER_NAME");
    if require_gpu {
        command.env("DENTBEND_REQUIRE_GPU", "1");
    } else {
        command.env_remove("DENTBEND_REQUIRE_GPU");
    }
    let output = command.output().unwrap();
    (output.status.code(), text(&output.stdout))
}

fn without_a_gpu_gpu_tests_are_reported_ignored_with_the_reason() {
    let (code, stdout) = probes_without_a_gpu(false);
    assert_eq!(code, Some(0), "{stdout}");
    for gpu_test in ["probe_needs_a_gpu", "probe_runs_on_either_backend::gpu"] {
        let line = stdout.lines().find(|l| l.starts_with(&format!("test {gpu_test} "))).expect(&stdout);
        assert!(line.ends_with("ignored (no usable GPU; DENTBEND_REQUIRE_GPU=1 makes this a failure)"), "{line}");
    }
    let cpu_half = stdout.lines().find(|l| l.starts_with("test probe_runs_on_either_backend::cpu ")).expect(&stdout);
    assert!(cpu_half.ends_with(" ok"), "{cpu_half}");
    assert!(stdout.contains("test result: ok. 1 passed; 0 failed; 2 ignored;"), "{stdout}");
}

fn with_dentbend_require_gpu_a_missing_gpu_fails() {
    let (code, stdout) = probes_without_a_gpu(true);
    assert_eq!(code, Some(101), "{stdout}");
    assert!(stdout.contains("DENTBEND_REQUIRE_GPU=1 but no GPU is usable"), "{stdout}");
    assert!(stdout.contains("test result: FAILED. 1 passed; 2 failed; 0 ignored;"), "{stdout}");
}

gpu_test_main! {
    plain: [without_a_gpu_gpu_tests_are_reported_ignored_with_the_reason, with_dentbend_require_gpu_a_missing_gpu_fails],
    gpu: [probe_needs_a_gpu],
    both: [probe_runs_on_either_backend],
}
