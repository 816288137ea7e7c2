//! GPU twin of [`cpu::envelope_cols`](crate::cpu::envelope_cols): `shaders/envelope_cols.wgsl`,
//! the second pass of the exact Gaussian envelope, one invocation per grid column of every dent
//! of a batch. Shares its buffers, scratch and workgroup width with
//! [`envelope_rows`](super::envelope_rows).

use super::envelope_rows::{BINDINGS, EnvelopeBuffers, encode_lines, run_lines};
use super::{GpuContext, GpuError, Kernel, shaders};
use crate::cpu::EnvelopeParams;

/// The compiled `envelope_cols` kernel.
#[derive(Debug)]
pub struct EnvelopeCols {
    kernel: Kernel,
}

impl EnvelopeCols {
    /// Compiles the kernel.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader does not validate on this device.
    pub fn new(context: &GpuContext) -> Result<Self, GpuError> {
        let kernel = Kernel::new(context, "envelope_cols", shaders::body("envelope_cols"), "main", &BINDINGS)?;
        Ok(Self { kernel })
    }

    /// Records one dispatch that overwrites, for each of the `batch` dents described in
    /// `buffers.params`, its `output` grid by `exp(−min_k (c·(j − k)² + rows[k][i]))` down each
    /// column i (0 where the column has no finite entry), exactly as
    /// [`cpu::envelope_cols`](crate::cpu::envelope_cols); `buffers.input` holds the rows pass's
    /// output. `max_res` is the largest `res` of the batch, cells.
    ///
    /// Recorded after [`EnvelopeRows::encode`](super::envelope_rows::EnvelopeRows::encode) in the
    /// same encoder, it sees that pass's output (each dispatch is its own compute pass) and may
    /// reuse its scratch buffer.
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

    /// Runs a batch: uploads each dent's `res × res` rows-pass output (the first `res²` values of
    /// its slice, `+∞` where a row had no source; the `cell_offset` given is ignored), encodes one
    /// dispatch, submits, and returns each dent's envelope E in the profile's units, as
    /// [`cpu::envelope_cols`](crate::cpu::envelope_cols).
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
        run_lines(context, "envelope_cols", dents, |encoder, buffers, batch, max_res| {
            self.encode(context, encoder, buffers, batch, max_res)
        })
    }
}
