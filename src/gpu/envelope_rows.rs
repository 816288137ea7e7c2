//! GPU twin of [`cpu::envelope_rows`](crate::cpu::envelope_rows): `shaders/envelope_rows.wgsl`,
//! the first pass of the exact Gaussian envelope, one invocation per grid row of every dent of a
//! batch.
//!
//! Also holds what both envelope passes share: the workgroup width, the hull scratch buffer's
//! size and the batch packing used by the `run_batch` conveniences.

use super::{Binding, GpuContext, GpuError, Kernel, buffers, shaders};
use crate::cpu::EnvelopeParams;

/// Invocations per workgroup along x (grid lines) of both envelope kernels; matches
/// `@workgroup_size(64, 1, 1)` in `shaders/envelope_rows.wgsl` and `shaders/envelope_cols.wgsl`.
pub(crate) const WORKGROUP: u32 = 64;

/// Bytes of one hull entry of the envelope kernels' scratch buffer (the WGSL `Piece`: source
/// index, offset and breakpoint term, three f32).
pub(crate) const PIECE_BYTES: u64 = 12;

/// Size in bytes of the hull scratch buffer that either envelope kernel needs for a batch of
/// `cells` cells in all (one entry per cell: a line of `res` cells keeps at most `res` parabolas).
/// Both passes may share one scratch buffer: each overwrites before it reads.
pub fn scratch_bytes(cells: u64) -> u64 {
    cells * PIECE_BYTES
}

/// The caller-owned buffers of one envelope dispatch, in binding order.
#[derive(Debug, Clone, Copy)]
pub struct EnvelopeBuffers<'a> {
    /// `array<EnvelopeParams>`, one per dent, `cell_offset` locating the dent's grid (in cells)
    /// inside `input`, `output` and `scratch`.
    pub params: &'a wgpu::Buffer,
    /// The input grids, f32 per cell, each dent `res × res` row-major: the profile P for
    /// [`EnvelopeRows`], the rows pass's output for
    /// [`EnvelopeCols`](super::envelope_cols::EnvelopeCols).
    pub input: &'a wgpu::Buffer,
    /// The output grids, same layout as `input`.
    pub output: &'a wgpu::Buffer,
    /// Hull scratch of at least [`scratch_bytes`]`(total cells)` bytes; contents irrelevant.
    pub scratch: &'a wgpu::Buffer,
}

/// The compiled `envelope_rows` kernel.
#[derive(Debug)]
pub struct EnvelopeRows {
    kernel: Kernel,
}

impl EnvelopeRows {
    /// Compiles the kernel.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader does not validate on this device.
    pub fn new(context: &GpuContext) -> Result<Self, GpuError> {
        let kernel = Kernel::new(context, "envelope_rows", shaders::body("envelope_rows"), "main", &BINDINGS)?;
        Ok(Self { kernel })
    }

    /// Records one dispatch that overwrites, for each of the `batch` dents described in
    /// `buffers.params`, its `output` grid by `min_k (c·(i − k)² − ln P[j][k])` over the cells of
    /// each row j with `0 < P < ∞` (`+∞` where a row has none), exactly as
    /// [`cpu::envelope_rows`](crate::cpu::envelope_rows). `max_res` is the largest `res` of the
    /// batch, cells.
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] if `batch` or `max_res` needs more workgroups than the device
    /// allows in one dimension.
    pub fn encode(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        buffers: &EnvelopeBuffers,
        batch: u32,
        max_res: u32,
    ) -> Result<(), GpuError> {
        encode_lines(&self.kernel, context, encoder, buffers, batch, max_res)
    }

    /// Runs a batch: uploads each dent's `res × res` profile P (the first `res²` values of its
    /// slice; the `cell_offset` given is ignored), encodes one dispatch, submits, and returns each
    /// dent's `−ln` envelope along rows, as [`cpu::envelope_rows`](crate::cpu::envelope_rows).
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] if the batch exceeds a binding or dispatch limit; validation,
    /// out-of-memory and device-lost errors from wgpu.
    ///
    /// # Panics
    /// If a dent's slice is shorter than its `res²`.
    pub fn run_batch(
        &self,
        context: &GpuContext,
        dents: &[(EnvelopeParams, &[f32])],
    ) -> Result<Vec<Vec<f32>>, GpuError> {
        run_lines(context, "envelope_rows", dents, |encoder, buffers, batch, max_res| {
            self.encode(context, encoder, buffers, batch, max_res)
        })
    }
}

/// Binding kinds of both envelope kernels: params, input, output, hull scratch.
pub(super) const BINDINGS: [Binding; 4] = [Binding::Read, Binding::Read, Binding::ReadWrite, Binding::ReadWrite];

/// Records one dispatch of an envelope `kernel`: one invocation per grid line, x = line index,
/// y = dent index.
pub(super) fn encode_lines(
    kernel: &Kernel,
    context: &GpuContext,
    encoder: &mut wgpu::CommandEncoder,
    buffers: &EnvelopeBuffers,
    batch: u32,
    max_res: u32,
) -> Result<(), GpuError> {
    let groups_x = max_res.div_ceil(WORKGROUP);
    let limit = context.limits.max_compute_workgroups_per_dimension;
    for (what, needed) in [("envelope dispatch: workgroups along x", groups_x), ("envelope dispatch: dents", batch)] {
        if needed > limit {
            return Err(GpuError::OverLimit { what: what.into(), needed: needed.into(), limit: limit.into() });
        }
    }
    if batch == 0 || groups_x == 0 {
        return Ok(());
    }
    let bind_group = kernel.bind(context, &[buffers.params, buffers.input, buffers.output, buffers.scratch]);
    kernel.dispatch(encoder, &bind_group, [groups_x, batch, 1]);
    Ok(())
}

/// Packs `dents` into flat buffers (cell offsets assigned in order), encodes with `encode`
/// (given the buffers, the batch size and the largest `res`), submits, and returns each dent's
/// `res²` output values.
pub(super) fn run_lines(
    context: &GpuContext,
    label: &str,
    dents: &[(EnvelopeParams, &[f32])],
    encode: impl FnOnce(&mut wgpu::CommandEncoder, &EnvelopeBuffers, u32, u32) -> Result<(), GpuError>,
) -> Result<Vec<Vec<f32>>, GpuError> {
    let cells: u64 = dents.iter().map(|(p, _)| u64::from(p.res).pow(2)).sum();
    buffers::check_binding_size(context, &format!("{label} grid"), cells * 4)?;
    buffers::check_binding_size(context, &format!("{label} hull scratch"), scratch_bytes(cells))?;
    let mut params = Vec::with_capacity(dents.len());
    let mut input = Vec::with_capacity(cells as usize);
    for (p, grid) in dents {
        // Within the binding size checked above, so within u32.
        params.push(EnvelopeParams { cell_offset: input.len() as u32, ..*p });
        input.extend_from_slice(&grid[..(p.res as usize).pow(2)]);
    }
    let batch = u32::try_from(dents.len()).unwrap_or(u32::MAX);
    let max_res = dents.iter().map(|(p, _)| p.res).max().unwrap_or(0);
    let output = context.scoped(label, || -> Result<wgpu::Buffer, GpuError> {
        let params = buffers::storage(context, &format!("{label} params"), &params);
        let input = buffers::storage(context, &format!("{label} input"), &input);
        let output = buffers::storage_zeroed(context, &format!("{label} output"), cells * 4);
        let scratch = buffers::storage_zeroed(context, &format!("{label} hull scratch"), scratch_bytes(cells));
        let mut encoder = context.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
        let bound = EnvelopeBuffers { params: &params, input: &input, output: &output, scratch: &scratch };
        encode(&mut encoder, &bound, batch, max_res)?;
        context.queue.submit([encoder.finish()]);
        Ok(output)
    })??;
    let flat: Vec<f32> = buffers::read_back(context, &output, input.len())?;
    Ok(params.iter().map(|p| flat[p.cell_offset as usize..][..(p.res as usize).pow(2)].to_vec()).collect())
}
