//! GPU tests that tell the truth. A test file that needs a GPU is a `harness = false` test
//! (its `[[test]]` entry in Cargo.toml) whose `main` is `gpu_test_main!`:
//! its tests run under `libtest-mimic`, which takes libtest's arguments (`--list`, `--exact`,
//! `--ignored`, name filters, `--test-threads`) and prints libtest's summary. A GPU test is
//! handed the shared context; when no adapter is usable it is reported as ignored with the
//! reason, unless `DENTBEND_REQUIRE_GPU=1` (set in CI, which installs lavapipe), where it fails.
//! The adapter is probed once, by the first GPU test that runs.
//!
//! Unlike libtest, `libtest-mimic` does not capture what passing tests print.

use std::process::ExitCode;
use std::sync::Once;

use dentbend::gpu::{GpuContext, GpuError, shared_context};
use libtest_mimic::{Arguments, Completion, Failed, Trial};

/// One test of a file whose `main` is [`run_tests`].
pub enum Test {
    /// Needs no GPU: runs as under libtest.
    Plain(&'static str, fn()),
    /// Needs a GPU: handed the shared context; ignored (with the reason) without one, failed
    /// without one when `DENTBEND_REQUIRE_GPU=1`.
    Gpu(&'static str, fn(&'static GpuContext)),
    /// Checks a behaviour on both backends: as `<name>::cpu`, handed `None`, always; as
    /// `<name>::gpu`, handed the shared context, a GPU test.
    Both(&'static str, fn(Option<&'static GpuContext>)),
}

/// Runs `tests` as libtest would (sorted by name, arguments from the command line) and returns
/// the exit code: 101 when a test failed.
pub fn run_tests(tests: Vec<Test>) -> ExitCode {
    let args = Arguments::from_args();
    let mut trials: Vec<Trial> = tests.into_iter().flat_map(trials).collect();
    trials.sort_by(|a, b| a.name().cmp(b.name()));
    libtest_mimic::run(&args, trials).exit_code()
}

/// Whether a missing GPU fails the GPU tests instead of skipping them.
pub fn gpu_required() -> bool {
    std::env::var("DENTBEND_REQUIRE_GPU").as_deref() == Ok("1")
}

fn trials(test: Test) -> Vec<Trial> {
    match test {
        Test::Plain(name, body) => vec![Trial::test(name, move || {
            body();
            Ok(())
        })],
        Test::Gpu(name, body) => vec![gpu_trial(name.to_owned(), body)],
        Test::Both(name, body) => vec![
            Trial::test(format!("{name}::cpu"), move || {
                body(None);
                Ok(())
            }),
            gpu_trial(format!("{name}::gpu"), move |context| body(Some(context))),
        ],
    }
}

/// A trial that runs `body` with the shared context, or reports why it cannot.
fn gpu_trial(name: String, body: impl FnOnce(&'static GpuContext) + Send + 'static) -> Trial {
    Trial::ignorable_test(name, move || match shared_context() {
        Ok(context) => {
            body(context);
            Ok(Completion::Completed)
        }
        Err(error) if gpu_required() => {
            Err(Failed::from(format!("DENTBEND_REQUIRE_GPU=1 but no GPU is usable: {error}")))
        }
        Err(error) => {
            explain_once(error);
            Ok(Completion::ignored_with("no usable GPU; DENTBEND_REQUIRE_GPU=1 makes this a failure"))
        }
    })
}

/// Says once per test binary why its GPU tests are ignored.
fn explain_once(error: &GpuError) {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| eprintln!("GPU tests ignored: {error}"));
}

/// The shared context, for helpers of GPU tests (which are handed it too).
///
/// # Panics
/// When no GPU is usable: only GPU tests ([`Test::Gpu`], the GPU half of [`Test::Both`]) may
/// call this, and they run only when one is.
pub fn context() -> &'static GpuContext {
    shared_context().unwrap_or_else(|error| panic!("no GPU is usable ({error}): call this from GPU tests only"))
}

/// A device and queue the test creates itself, as an application would, with `limits`, for
/// [`GpuContext::from_device`], on the adapter the shared context found.
///
/// # Panics
/// As [`context`], and when the adapter refuses `limits`.
pub fn own_device(limits: wgpu::Limits) -> (wgpu::Device, wgpu::Queue) {
    context();
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(wgpu::util::initialize_adapter_from_env_or_default(&instance, None))
        .expect("the adapter the shared context was made on");
    let descriptor = wgpu::DeviceDescriptor {
        label: Some("the application's device"),
        required_limits: limits,
        ..Default::default()
    };
    pollster::block_on(adapter.request_device(&descriptor)).expect("a device with the requested limits")
}

/// `fn main` for a test file with GPU tests: each test function listed by kind, as in
/// [`Test`]. A function left out of the lists is dead code, which the build reports.
///
/// It is exported at the test crate's root, so a test file invokes it by its bare name:
///
/// ```ignore
/// gpu_test_main! {
///     plain: [backend_names_parse],
///     gpu: [a_kernel_round_trips_data],
///     both: [renderer_picks_the_gpu_for_a_context_and_the_cpu_without],
/// }
/// ```
#[macro_export]
macro_rules! gpu_test_main {
    (
        $(plain: [$($plain:ident),* $(,)?] $(,)?)?
        $(gpu: [$($gpu:ident),* $(,)?] $(,)?)?
        $(both: [$($both:ident),* $(,)?] $(,)?)?
    ) => {
        fn main() -> std::process::ExitCode {
            use $crate::common::gpu::Test;
            $crate::common::gpu::run_tests(vec![
                $($(Test::Plain(stringify!($plain), $plain),)*)?
                $($(Test::Gpu(stringify!($gpu), $gpu),)*)?
                $($(Test::Both(stringify!($both), $both),)*)?
            ])
        }
    };
}
