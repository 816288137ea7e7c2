//! The GPU path: a wgpu device, one compute pipeline per WGSL kernel in `shaders/`, and the
//! buffers they share. Every kernel has a CPU twin in [`crate::cpu`] with the same stem.

pub mod buffers;
mod context;
mod dent_backend;
mod denter;
pub mod displace;
pub mod envelope_cols;
pub mod envelope_rows;
mod error;
pub mod glance;
pub mod heat;
pub mod interleave;
mod kernel;
mod kernel_device;
mod limits;
pub mod moved;
pub mod normals;
mod recorder;
mod shaders;
pub mod skin;
pub mod zbuffer;

pub use context::{GpuContext, WAIT_TIMEOUT};
pub use dent_backend::GpuBackend;
pub use denter::{GpuBatchError, GpuDentInfo, GpuDenter, GpuDenterOptions, GpuStages};
pub use error::GpuError;
pub use interleave::{InterleaveError, VertexLayout};
pub use kernel::{Binding, Kernel, SHARED_WGSL};
pub use kernel_device::{KernelDevice, shared_context};
pub use limits::{REQUIRED_LIMITS, RequiredLimit, check_limits};
pub use moved::{MovedVertices, PendingMoved};
pub use recorder::KernelTimes;
pub use shaders::{SHADERS, shader_source};
