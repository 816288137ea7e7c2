//! GPU twin of [`cpu::glance`](crate::cpu::glance): `shaders/glance.wgsl` maps the smoothed
//! heights of a whole batch of dents onto their collision planes and shears them, one dispatch.

use super::{Binding, GpuContext, GpuError, Kernel, buffers, shaders};
use crate::cpu::GlanceParams;

/// Invocations per workgroup along x (dent-map cells); `WORKGROUP` in `shaders/glance.wgsl`.
pub(crate) const WORKGROUP: u32 = 256;

/// Caller-owned buffers of one batch, in `@binding` order.
#[derive(Debug, Clone, Copy)]
pub struct GlanceBuffers<'a> {
    /// `array<GlanceParams>`, one per dent (`src_offset` and `dst_offset` place the dent in
    /// `heights` and `dent_map`).
    pub params: &'a wgpu::Buffer,
    /// The smoothed heights (f32, world units), `src_res²` per dent, row-major.
    pub heights: &'a wgpu::Buffer,
    /// The dent maps written: `[Δx, Δy, Δz, D₂]` (f32 × 4, world units), `dst_res²` per dent,
    /// row-major.
    pub dent_map: &'a wgpu::Buffer,
}

/// The compiled `shaders/glance.wgsl`, built once per device.
#[derive(Debug)]
pub struct GlanceKernel {
    kernel: Kernel,
}

impl GlanceKernel {
    /// Compiles the kernel.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader does not validate on this device.
    pub fn new(context: &GpuContext) -> Result<Self, GpuError> {
        let bindings = [Binding::Read, Binding::Read, Binding::ReadWrite];
        Ok(Self { kernel: Kernel::new(context, "glance", shaders::body("glance"), "main", &bindings)? })
    }

    /// Records one dispatch over a batch of `dents` dents whose largest map has `max_cells`
    /// (`dst_res²`) cells.
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] if the dispatch is too large for the device;
    /// [`GpuError::Validation`] if the buffers do not fit the bindings.
    pub fn encode(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        buffers: &GlanceBuffers<'_>,
        dents: u32,
        max_cells: u32,
    ) -> Result<(), GpuError> {
        if dents == 0 || max_cells == 0 {
            return Ok(());
        }
        let groups = max_cells.div_ceil(WORKGROUP);
        let limit = context.limits.max_compute_workgroups_per_dimension;
        for (what, needed) in [("glance workgroups per dent", groups), ("glance batch (dents)", dents)] {
            if needed > limit {
                return Err(GpuError::OverLimit { what: what.into(), needed: needed.into(), limit: limit.into() });
            }
        }
        let bind_group = context.scoped("glance bind", || {
            self.kernel.bind(context, &[buffers.params, buffers.heights, buffers.dent_map])
        })?;
        self.kernel.dispatch(encoder, &bind_group, [groups, dents, 1]);
        Ok(())
    }

    /// Runs a batch of `(params, heights)` dents (offsets are ignored and set here) and returns
    /// each dent's map, as [`cpu::glance`](crate::cpu::glance) writes it.
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] for a batch too large for one binding or dispatch; device errors.
    ///
    /// # Panics
    /// If a dent's `heights` does not hold `src_res²` values.
    pub fn run_batch(
        &self,
        context: &GpuContext,
        dents: &[(GlanceParams, &[f32])],
    ) -> Result<Vec<Vec<[f32; 4]>>, GpuError> {
        if dents.is_empty() {
            return Ok(Vec::new());
        }
        let mut params = Vec::with_capacity(dents.len());
        let mut heights = Vec::new();
        let mut cells = 0usize;
        for &(p, values) in dents {
            assert_eq!(values.len(), (p.src_res as usize).pow(2), "glance: heights must hold src_res² values");
            params.push(GlanceParams { src_offset: heights.len() as u32, dst_offset: cells as u32, ..p });
            heights.extend_from_slice(values);
            cells += (p.dst_res as usize).pow(2);
        }
        let map_bytes = (cells * size_of::<[f32; 4]>()) as u64;
        buffers::check_binding_size(context, "glance heights", (heights.len() * size_of::<f32>()) as u64)?;
        buffers::check_binding_size(context, "glance dent maps", map_bytes)?;
        let max_cells = params.iter().map(|p| p.dst_res * p.dst_res).max().unwrap_or(0);
        let params_buffer = buffers::storage(context, "glance params", &params);
        let heights_buffer = buffers::storage(context, "glance heights", &heights);
        let map_buffer = buffers::storage_zeroed(context, "glance dent maps", map_bytes);
        let bound = GlanceBuffers { params: &params_buffer, heights: &heights_buffer, dent_map: &map_buffer };
        let mut encoder = context.device.create_command_encoder(&Default::default());
        self.encode(context, &mut encoder, &bound, dents.len() as u32, max_cells)?;
        context.queue.submit([encoder.finish()]);
        let flat: Vec<[f32; 4]> = buffers::read_back(context, &map_buffer, cells)?;
        Ok(params.iter().map(|p| flat[p.dst_offset as usize..][..(p.dst_res as usize).pow(2)].to_vec()).collect())
    }
}
