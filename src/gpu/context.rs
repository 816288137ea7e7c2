//! The wgpu instance, adapter, device and queue every GPU kernel runs on.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use super::GpuError;

/// A GPU device ready for compute work: dentbend's own ([`new`](Self::new)) or an application's
/// ([`from_device`](Self::from_device)).
///
/// Cheap to clone (the wgpu handles are reference-counted; clones share the device-lost state).
/// For its own device the adapter comes from `wgpu::util::initialize_adapter_from_env_or_default`,
/// so `WGPU_ADAPTER_NAME=llvmpipe` picks Mesa's lavapipe, and only the downlevel-default limits are
/// requested so any adapter works.
#[derive(Clone)]
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
    /// The device's limits (for [`new`](Self::new) the downlevel defaults: 4 storage buffers
    /// per stage, 128 MiB per binding, 65,535 workgroups per dimension); batches are cut to them.
    pub limits: wgpu::Limits,
    lost: Arc<AtomicBool>,
    /// Whether dentbend created the device (and installed its device-lost callback).
    owned: bool,
}

impl std::fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuContext")
            .field("adapter", &self.info.name)
            .field("backend", &self.info.backend)
            .field("owned", &self.owned)
            .finish()
    }
}

/// Smallest buffer created, bytes: wgpu refuses empty bindings.
pub(crate) const MIN_BUFFER_BYTES: u64 = 16;

impl GpuContext {
    /// Longest wait for submitted work before [`GpuContext::wait`] gives up with an error
    /// instead of hanging (a stuck driver or a runaway shader).
    pub const WAIT_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(120);

    /// A buffer of `usage` (plus `COPY_DST`) holding `bytes`, zero-padded to at least 16 bytes
    /// and a multiple of 4. The contents go through the queue rather than `mapped_at_creation`,
    /// so a lost device makes this an error reported at the next wait or error scope, not a
    /// panic.
    pub fn buffer_with_contents(&self, label: &str, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
        let size = (bytes.len() as u64).max(MIN_BUFFER_BYTES).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: usage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        if bytes.len() as u64 == size {
            self.queue.write_buffer(&buffer, 0, bytes);
        } else {
            let mut padded = bytes.to_vec();
            padded.resize(size as usize, 0);
            self.queue.write_buffer(&buffer, 0, &padded);
        }
        buffer
    }

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
        Ok(Self { device, queue, info, timestamps: features == timing, limits, lost, owned: true })
    }

    /// Wraps an application's device and queue (e.g. Bevy's `RenderDevice::wgpu_device()` and
    /// `RenderQueue`), so dentbend's kernels and resident buffers live on the device the
    /// application renders with.
    ///
    /// The device's limits are checked against [`REQUIRED_LIMITS`](super::REQUIRED_LIMITS) (any
    /// device created with `wgpu::Limits::downlevel_defaults()` or better passes); timestamp
    /// queries are used only if the device has both `TIMESTAMP_QUERY` features. No device-wide
    /// callback is installed (the application's device-lost and uncaptured-error handlers stay
    /// as they are): a lost device is detected instead by a probe mapping in
    /// [`check_alive`](Self::check_alive) and [`wait`](Self::wait), and dentbend's own work runs
    /// inside error scopes.
    ///
    /// # Errors
    /// [`GpuError::MissingLimits`] naming the first limit the device falls short of.
    pub fn from_device(device: wgpu::Device, queue: wgpu::Queue) -> Result<Self, GpuError> {
        let limits = device.limits();
        super::limits::check_limits(&limits)?;
        let timing = wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
        let timestamps = device.features().contains(timing);
        let info = device.adapter_info();
        log::info!("dentbend on the application's device: {} ({:?})", info.name, info.backend);
        Ok(Self { device, queue, info, timestamps, limits, lost: Arc::new(AtomicBool::new(false)), owned: false })
    }

    /// Whether dentbend created this device ([`new`](Self::new)) rather than wrapping an
    /// application's ([`from_device`](Self::from_device)).
    pub fn owns_device(&self) -> bool {
        self.owned
    }

    /// A short description of the adapter, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan)`.
    pub fn adapter_name(&self) -> String {
        format!("{} ({:?})", self.info.name, self.info.backend)
    }

    /// Fails if the device has been lost. On its own device dentbend's device-lost callback
    /// raises a flag; on an application's device this probes: it maps a 4-byte buffer and
    /// polls once without blocking (a lost device fails the mapping at once).
    ///
    /// # Errors
    /// [`GpuError::DeviceLost`].
    pub fn check_alive(&self) -> Result<(), GpuError> {
        if !self.owned && !self.lost.load(Ordering::SeqCst) && self.probe_lost() {
            self.lost.store(true, Ordering::SeqCst);
        }
        self.check_flag()
    }

    /// Fails if the device is known to be lost, without touching the device (for recording).
    pub(crate) fn check_flag(&self) -> Result<(), GpuError> {
        if self.lost.load(Ordering::SeqCst) {
            let why = if self.owned { "see the log for the driver's reason" } else { "a probe mapping failed" };
            return Err(GpuError::DeviceLost(why.into()));
        }
        Ok(())
    }

    /// Whether a mapping of a fresh buffer fails, which it does at once on a lost device (on a
    /// live one it succeeds, or is still pending, after one non-blocking poll). Runs inside a
    /// validation scope, so the failure reaches no application error handler.
    fn probe_lost(&self) -> bool {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let probe = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dentbend device-lost probe"),
            size: wgpu::COPY_BUFFER_ALIGNMENT,
            usage: wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let (sender, receiver) = std::sync::mpsc::channel();
        probe.slice(..).map_async(wgpu::MapMode::Read, move |result| {
            let _ = sender.send(result.is_err());
        });
        let polled = self.device.poll(wgpu::PollType::Poll);
        let caught = pollster::block_on(scope.pop()).is_some();
        caught || polled.is_err() || receiver.try_recv().unwrap_or(false)
    }

    /// `error`, or [`GpuError::DeviceLost`] when the device turns out to be lost (what a failed
    /// submission or mapping on a lost device really means).
    ///
    /// Probes the device even when dentbend owns it: its device-lost callback only runs from a
    /// poll that finds the queue empty, which may not have happened yet.
    pub(crate) fn lost_or(&self, error: GpuError) -> GpuError {
        if !self.lost.load(Ordering::SeqCst) && self.probe_lost() {
            self.lost.store(true, Ordering::SeqCst);
        }
        self.check_flag().err().unwrap_or(error)
    }

    /// Blocks until all submitted work is done, at most [`WAIT_TIMEOUT`](Self::WAIT_TIMEOUT).
    ///
    /// # Errors
    /// [`GpuError::Wait`] (including a timeout) or [`GpuError::DeviceLost`].
    pub fn wait(&self) -> Result<(), GpuError> {
        self.check_alive()?;
        let wait = wgpu::PollType::Wait { submission_index: None, timeout: Some(Self::WAIT_TIMEOUT) };
        self.device.poll(wait).map_err(|e| GpuError::Wait(e.to_string()))?;
        self.check_alive()
    }

    /// Runs `f` inside validation and out-of-memory error scopes and turns what they caught into
    /// a [`GpuError`] naming `label`.
    ///
    /// # Errors
    /// [`GpuError::Validation`] or [`GpuError::OutOfMemory`] when wgpu reports one.
    pub fn scoped<T>(&self, label: &str, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        self.check_flag()?;
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
        self.check_flag()?;
        Ok(value)
    }
}
