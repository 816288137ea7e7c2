//! Second pass of the exact Gaussian envelope. CPU twin of `shaders/envelope_cols.wgsl`.

use super::EnvelopeParams;

/// For each column i and row j: `envelope[j][i] = exp(−min_k (c·(j − k)² + rows[k][i]))`, 0
/// where every term is `+∞`.
pub fn envelope_cols(params: &EnvelopeParams, rows: &[f32], envelope: &mut [f32]) {
    let _ = (params, rows, envelope);
    todo!("envelope_cols: being written")
}
