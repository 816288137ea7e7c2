//! The render world's half: dentbend's [`GpuContext`](dentbend::gpu::GpuContext) on Bevy's
//! `RenderDevice`, the dentable meshes resident on it, and each frame's dent batch recorded and
//! written into Bevy's mesh allocator slabs.

mod readbacks;
mod resident;
mod skinned;
mod staged;
mod startup;
mod system;
mod target;

pub(crate) use resident::ResidentDents;
pub(crate) use startup::start_on_bevys_device;
pub(crate) use system::make_dents;
