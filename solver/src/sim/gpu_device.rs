//! The GPU device the rigid core's denter (and the coupling layer's skinner) may run on:
//! [`gpu::GpuContext`](dentbend::gpu::GpuContext) with the `gpu` feature; without it an uninhabited
//! type, so `None` (the CPU twins) is the only choice and the API keeps its shape.

#[cfg(feature = "gpu")]
pub use dentbend::gpu::GpuContext as GpuDevice;

/// No GPU in this build (the `gpu` feature is off): no value of this type exists.
#[cfg(not(feature = "gpu"))]
#[derive(Debug)]
pub enum GpuDevice {}
