//! The wgpu instance, adapter, device and queue every GPU kernel runs on.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use super::GpuError;

/// Longest wait for submitted work before [`GpuContext::wait`] gives up with an error instead of
/// hanging (a stuck driver or a runaway shader).
pub const WAIT_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(120);

/// A GPU device ready for compute work.
///
/// Created once (it is cheap to share by reference); the adapter comes from
/// `wgpu::util::initialize_adapter_from_env_or_default`, so `WGPU_ADAPTER_NAME=llvmpipe` picks
/// Mesa's lavapipe, and only the downlevel-default limits are requested so any adapter works.
pub struct GpuContext {
    /// The device kernels and buffers are created on.
    pub device: wgpu::Device,
    /// The queue work is submitted to.
    pub queue: wgpu::Queue,
    /// Name, backend and driver of the adapter in use.
    pub info: wgpu::AdapterInfo,
    /// Whether timestamp queries (also between passes) are enabled: requested whenever the
    /// adapter has them, for per-kernel GPU times.
    pub timestamps: bool,
    /// The limits the device was created with (downlevel defaults: 4 storage buffers per stage,
    /// 128 MiB per binding, 65,535 workgroups per dimension).
    pub limits: wgpu::Limits,
    lost: Arc<AtomicBool>,
}

impl std::fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuContext").field("adapter", &self.info.name).field("backend", &self.info.backend).finish()
    }
}

impl GpuContext {
    /// Finds an adapter and creates a device on it, logging the adapter's name once.
    ///
    /// # Errors
    /// [`GpuError::NoAdapter`] or [`GpuError::RequestDevice`].
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Self, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = wgpu::util::initialize_adapter_from_env_or_default(&instance, None)
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let limits = wgpu::Limits::downlevel_defaults();
        let timing = wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
        let features = adapter.features() & timing;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("dentbend"),
                required_features: features,
                required_limits: limits.clone(),
                experimental_features: wgpu::ExperimentalFeatures::disabled(),
                memory_hints: wgpu::MemoryHints::Performance,
                trace: wgpu::Trace::Off,
            })
            .await
            .map_err(|e| GpuError::RequestDevice(e.to_string()))?;
        let lost = Arc::new(AtomicBool::new(false));
        let flag = lost.clone();
        device.set_device_lost_callback(move |reason, message| {
            flag.store(true, Ordering::SeqCst);
            log::error!("GPU device lost ({reason:?}): {message}");
        });
        device.on_uncaptured_error(Arc::new(|error| log::error!("uncaptured GPU error: {error}")));
        log::info!("dentbend GPU adapter: {} ({:?}, {})", info.name, info.backend, info.driver);
        Ok(Self { device, queue, info, timestamps: features == timing, limits, lost })
    }

    /// A short description of the adapter, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan)`.
    pub fn adapter_name(&self) -> String {
        format!("{} ({:?})", self.info.name, self.info.backend)
    }

    /// Fails if the device has been lost.
    ///
    /// # Errors
    /// [`GpuError::DeviceLost`].
    pub fn check_alive(&self) -> Result<(), GpuError> {
        if self.lost.load(Ordering::SeqCst) {
            return Err(GpuError::DeviceLost("see the log for the driver's reason".into()));
        }
        Ok(())
    }

    /// Blocks until all submitted work is done, at most [`WAIT_TIMEOUT`].
    ///
    /// # Errors
    /// [`GpuError::Wait`] (including a timeout) or [`GpuError::DeviceLost`].
    pub fn wait(&self) -> Result<(), GpuError> {
        self.check_alive()?;
        let wait = wgpu::PollType::Wait { submission_index: None, timeout: Some(WAIT_TIMEOUT) };
        self.device.poll(wait).map_err(|e| GpuError::Wait(e.to_string()))?;
        self.check_alive()
    }

    /// Runs `f` inside validation and out-of-memory error scopes and turns what they caught into
    /// a [`GpuError`] naming `label`.
    ///
    /// # Errors
    /// [`GpuError::Validation`] or [`GpuError::OutOfMemory`] when wgpu reports one.
    pub fn scoped<T>(&self, label: &str, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = f();
        let validation = pollster::block_on(validation.pop());
        let oom = pollster::block_on(oom.pop());
        if let Some(error) = validation {
            return Err(GpuError::Validation { label: label.into(), message: error.to_string() });
        }
        if oom.is_some() {
            return Err(GpuError::OutOfMemory(label.into()));
        }
        self.check_alive()?;
        Ok(value)
    }
}
