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

/// A device and queue the test creates itself, as an application would, with `limits`, for
/// [`GpuContext::from_device`]: `None` (after printing why) when no adapter exists, unless
/// `DENTBEND_REQUIRE_GPU=1`, where that fails the test.
pub fn own_device(limits: wgpu::Limits) -> Option<(wgpu::Device, wgpu::Queue)> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(wgpu::util::initialize_adapter_from_env_or_default(&instance, None));
    let adapter = match adapter {
        Ok(adapter) => adapter,
        Err(error) if std::env::var("DENTBEND_REQUIRE_GPU").as_deref() == Ok("1") => {
            panic!("DENTBEND_REQUIRE_GPU=1 but no GPU adapter exists: {error}")
        }
        Err(error) => {
            eprintln!("skipping GPU test: no adapter ({error})");
            return None;
        }
    };
    let descriptor = wgpu::DeviceDescriptor {
        label: Some("the application's device"),
        required_limits: limits,
        ..Default::default()
    };
    Some(pollster::block_on(adapter.request_device(&descriptor)).expect("a device with the requested limits"))
}
