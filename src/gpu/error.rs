//! Errors of the GPU path.

/// Everything that can go wrong on the GPU.
#[derive(Debug, Clone, thiserror::Error)]
pub enum GpuError {
    /// No adapter could be found (no GPU and no software Vulkan driver such as lavapipe).
    #[error("no GPU adapter found ({0}); install a Vulkan driver (e.g. Mesa's lavapipe) or use DENTBEND_BACKEND=cpu")]
    NoAdapter(String),
    /// The adapter refused to create a device with the downlevel-default limits.
    #[error("the GPU adapter could not create a device: {0}")]
    RequestDevice(String),
    /// wgpu reported a validation error (a bug in a shader or its bindings, or an over-limit
    /// request).
    #[error("GPU validation error in {label}: {message}")]
    Validation {
        /// What was being created or run.
        label: String,
        /// wgpu's message.
        message: String,
    },
    /// The device ran out of memory.
    #[error("the GPU ran out of memory in {0}")]
    OutOfMemory(String),
    /// A request exceeds the device's limits (buffer size, dispatch size).
    #[error("{what} needs {needed}, over the device limit of {limit}")]
    OverLimit {
        /// What was too large.
        what: String,
        /// Amount requested.
        needed: u64,
        /// The device's limit.
        limit: u64,
    },
    /// An application's device falls short of a limit the kernels need (see
    /// [`REQUIRED_LIMITS`](super::REQUIRED_LIMITS)).
    #[error("the GPU device's {limit} is {available}; dentbend's kernels need at least {needed}")]
    MissingLimits {
        /// The [`wgpu::Limits`] field.
        limit: &'static str,
        /// The least value the kernels need.
        needed: u64,
        /// The device's value.
        available: u64,
    },
    /// The device was lost (driver reset, GPU removed).
    #[error("the GPU device was lost: {0}")]
    DeviceLost(String),
    /// Waiting for the GPU or mapping a read-back buffer failed.
    #[error("waiting for the GPU failed: {0}")]
    Wait(String),
    /// `DENTBEND_BACKEND` holds something other than `cpu`, `gpu` or `auto`.
    #[error("DENTBEND_BACKEND={0} is not one of cpu, gpu, auto")]
    BadBackend(String),
}
