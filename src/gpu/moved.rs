//! GPU twin of [`cpu::moved`](crate::cpu::moved): compacts the vertices of one resident target
//! that the last batch moved (the `w` flag `displace` sets) into a short list, and reads back only
//! that list, for a physics engine to refit its collider.
//!
//! The kernel appends through an atomic counter, so slots come in no fixed order; the host sorts
//! them by vertex index, which makes the result equal to the CPU twin's.

use glam::Vec3;

use super::{Binding, GpuContext, GpuError, Kernel, buffers};
use crate::cpu::MovedParams;

/// Invocations per workgroup along x. Keep in sync with `WORKGROUP` in `shaders/moved.wgsl`.
pub const WORKGROUP: u32 = 64;

/// The vertices of one target that moved in the last batch, in ascending index order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MovedVertices {
    /// Vertex indices within the target (as in its mesh).
    pub indices: Vec<u32>,
    /// Their new positions, world units, one per index.
    pub positions: Vec<Vec3>,
}

impl MovedVertices {
    /// Sorts compacted `[index, x bits, y bits, z bits]` slots into ascending index order.
    pub fn from_slots(mut slots: Vec<[u32; 4]>) -> Self {
        slots.sort_unstable_by_key(|s| s[0]);
        let indices = slots.iter().map(|s| s[0]).collect();
        let positions =
            slots.iter().map(|s| Vec3::new(f32::from_bits(s[1]), f32::from_bits(s[2]), f32::from_bits(s[3])));
        Self { indices, positions: positions.collect() }
    }
}

/// The `moved` kernel, compiled once.
#[derive(Debug)]
pub struct Moved {
    kernel: Kernel,
}

impl Moved {
    /// Compiles the kernel.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader does not compile on this device.
    pub fn new(context: &GpuContext) -> Result<Self, GpuError> {
        let bindings = [Binding::Uniform, Binding::Read, Binding::ReadWrite, Binding::ReadWrite];
        let kernel = Kernel::new(context, "moved", super::shaders::body("moved"), "main", &bindings)?;
        Ok(Self { kernel })
    }

    /// Compacts the moved vertices of the target `params` names in `positions` (`vec4` per
    /// vertex: xyz world units, w moved flag) and reads back the count, then only that many slots
    /// (16 bytes each): two small waits, no read-back of unmoved vertices.
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] when the target has more than 65,535 × [`WORKGROUP`] vertices or
    /// its list exceeds the binding limit; device errors.
    pub fn run(
        &self,
        context: &GpuContext,
        params: MovedParams,
        positions: &wgpu::Buffer,
    ) -> Result<MovedVertices, GpuError> {
        let groups = params.vertex_count.div_ceil(WORKGROUP);
        let limit = context.limits.max_compute_workgroups_per_dimension;
        if groups > limit {
            let what = "moved workgroups (vertices / WORKGROUP)".into();
            return Err(GpuError::OverLimit { what, needed: groups.into(), limit: limit.into() });
        }
        if groups == 0 {
            return Ok(MovedVertices::default());
        }
        let list_bytes = u64::from(params.vertex_count) * 16;
        buffers::check_binding_size(context, "moved list", list_bytes)?;
        let list = buffers::storage_zeroed(context, "moved list", list_bytes);
        let used = buffers::storage_zeroed(context, "moved count", 4);
        context
            .scoped("moved", || {
                let mut encoder = context.device.create_command_encoder(&Default::default());
                let uniform = buffers::uniform(context, "moved params", &params);
                let bind = self.kernel.bind(context, &[&uniform, positions, &list, &used]);
                self.kernel.dispatch(&mut encoder, &bind, [groups, 1, 1]);
                context.queue.submit([encoder.finish()]);
            })
            .map_err(|e| context.lost_or(e))?;
        let count: Vec<u32> = buffers::read_back(context, &used, 1)?;
        let count = count[0].min(params.vertex_count) as usize;
        let slots: Vec<[u32; 4]> = buffers::read_back(context, &list, count)?;
        Ok(MovedVertices::from_slots(slots))
    }
}
