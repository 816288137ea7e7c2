//! First pass of the exact Gaussian envelope. CPU twin of `shaders/envelope_rows.wgsl`.

use super::EnvelopeParams;

/// For each row j and column i: `out[j][i] = min_k (c·(i − k)² − ln P[j][k])` over cells with
/// `P > 0`, `+∞` when the row has none.
pub fn envelope_rows(params: &EnvelopeParams, profile: &[f32], out: &mut [f32]) {
    let _ = (params, profile, out);
    todo!("envelope_rows: being written")
}
