//! Second pass of the exact Gaussian envelope. CPU twin of `shaders/envelope_cols.wgsl`.

use super::EnvelopeParams;
use super::envelope_rows::{LineScratch, lower_envelope};

/// Columns gathered per block: 16 f32 = one 64-byte cache line of each row.
const BLOCK: usize = 16;

/// For each column i and row j: `envelope[j][i] = exp(−min_k (c·(j − k)² + rows[k][i]))`, 0
/// where every term is `+∞`.
///
/// `rows` is the output of [`envelope_rows`](super::envelope_rows), `envelope` the exact upper
/// envelope `max_k P_k·exp(−c·|x − x_k|²)` in the profile's units; both `res × res`, row-major.
/// The shader runs one invocation per column; here columns are copied out in blocks of 16 so
/// that every row is read a cache line at a time, and each column is then swept by the same
/// line routine as the rows, cell for cell the result of a per-column sweep.
///
/// # Panics
///
/// If either slice is shorter than `res²`.
pub fn envelope_cols(params: &EnvelopeParams, rows: &[f32], envelope: &mut [f32]) {
    let n = params.res as usize;
    if n == 0 {
        return;
    }
    let (rows, envelope) = (&rows[..n * n], &mut envelope[..n * n]);
    let mut scratch = LineScratch::new(n, params.c);
    // lines[w*n + j] = rows[j][i0 + w]: the block's columns, each contiguous.
    let mut lines = vec![0.0f32; BLOCK * n];
    for i0 in (0..n).step_by(BLOCK) {
        let w = BLOCK.min(n - i0);
        let lines = &mut lines[..w * n];
        for (j, row) in rows.chunks_exact(n).enumerate() {
            for (col, &g) in row[i0..i0 + w].iter().enumerate() {
                lines[col * n + j] = g;
            }
        }
        for line in lines.chunks_exact_mut(n) {
            lower_envelope(line, &mut scratch);
        }
        // One exp per output cell; exp(−∞) = 0 where the column had no source.
        for (j, row) in envelope.chunks_exact_mut(n).enumerate() {
            for (col, e) in row[i0..i0 + w].iter_mut().enumerate() {
                *e = (-lines[col * n + j]).exp();
            }
        }
    }
}
