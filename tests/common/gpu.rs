//! The GPU context for tests: skipped with a printed reason when no adapter exists, unless
//! `DENTBEND_REQUIRE_GPU=1` (set in CI, which installs lavapipe), where absence fails the test.

use dentbend::gpu::{GpuContext, shared_context};

/// The shared context, or `None` (after printing why) when the test should skip.
pub fn context() -> Option<&'static GpuContext> {
    match shared_context() {
        Ok(context) => Some(context),
        Err(error) if std::env::var("DENTBEND_REQUIRE_GPU").as_deref() == Ok("1") => {
            panic!("DENTBEND_REQUIRE_GPU=1 but no GPU is usable: {error}")
        }
        Err(error) => {
            eprintln!("skipping GPU test: {error}");
            None
        }
    }
}
