//! The GPU path: a wgpu device, one compute pipeline per WGSL kernel in `shaders/`, and the
//! buffers they share. Every kernel has a CPU twin in [`crate::cpu`] with the same stem.
//!
//! What an engine needs is public: [`GpuDenter`], [`GpuBackend`], [`GpuContext`], skinning
//! ([`skin`]) and vertex interleaving ([`interleave`]). The stages one by one (each kernel, its
//! buffers, the shader sources) are public only with the `kernels` feature, for parity tests and
//! kernel benchmarks; they carry no stability promise.

/// Declares modules that are public with the `kernels` feature and crate-private without it.
macro_rules! kernel_modules {
    ($($name:ident),* $(,)?) => {$(
        #[cfg(feature = "kernels")]
        pub mod $name;
        #[cfg(not(feature = "kernels"))]
        #[allow(dead_code, reason = "what the stages use is used; the rest is public with `kernels`")]
        pub(crate) mod $name;
    )*};
}

kernel_modules!(
    buffers,
    displace,
    envelope_cols,
    envelope_rows,
    glance,
    heat,
    kernel,
    moved,
    normals,
    shaders,
    zbuffer
);

mod context;
mod dent_backend;
mod denter;
mod error;
pub mod interleave;
mod kernel_device;
mod limits;
mod recorder;
pub mod skin;

pub use context::GpuContext;
pub use dent_backend::GpuBackend;
pub use denter::{GpuBatchError, GpuDentInfo, GpuDenter, GpuDenterOptions};
kernels_use!(denter::GpuStages);
pub use error::GpuError;
pub use interleave::{InterleaveError, VertexLayout};
#[cfg(feature = "kernels")]
pub use kernel::{Binding, Kernel, SHARED_WGSL};
#[cfg(not(feature = "kernels"))]
pub(crate) use kernel::{Binding, Kernel, SHARED_WGSL};
pub use kernel_device::{KernelDevice, shared_context};
pub use limits::{REQUIRED_LIMITS, RequiredLimit, check_limits};
pub use moved::{MovedVertices, PendingMoved};
kernels_use!(recorder::KernelTimes);
#[cfg(feature = "kernels")]
pub use shaders::{SHADERS, shader_source};
