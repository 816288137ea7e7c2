// envelope_rows: first pass of the exact Gaussian envelope (ARCHITECTURE.md §4 "Broadening").
//
// For every row j and column i of every dent of the batch:
//   rows[j][i] = min_k (c·(i − k)² − ln P[j][k])  over the cells k of row j with 0 < P < ∞,
//   rows[j][i] = +∞ (bits 0x7f800000) where row j has no such cell.
// It is the lower envelope of identical parabolas (a Felzenszwalb–Huttenlocher generalized
// distance transform), O(res) per row. CPU twin: src/cpu/envelope_rows.rs (`envelope_rows` and
// its line routine `lower_envelope`); the line routine is shaders/shared/envelope_line.wgsl,
// prepended to this file, and this file supplies its hooks for rows.
//
// Bindings (group 0):
//   0 params:  array<EnvelopeParams>, read   one per dent: res (cells per side), c = 1/(2σ²)
//                                            (1/cell², σ in cells), cell_offset
//   1 profile: array<f32>, read              P per cell, each dent res×res row-major from its
//                                            cell_offset
//   2 rows:    array<f32>, read_write        the result, same layout as profile
//   3 hull:    array<Piece>, read_write      scratch, at least as many entries as cells; entry k
//                                            (1-based) of row j's hull is at
//                                            cell_offset + (k − 1)·res + j (see hull_slot)
// Dispatch: one invocation per grid row, x = row index j within the dent, y = dent index of the
// batch; workgroups [ceil(max res / 64), batch, 1].
// Host constants it must match (src/gpu/envelope_rows.rs): WORKGROUP = 64 (@workgroup_size),
// PIECE_BYTES = 12 (size of Piece), and the +∞ the CPU twin writes (f32::INFINITY, INF_BITS).

@group(0) @binding(0) var<storage, read> params: array<EnvelopeParams>;
@group(0) @binding(1) var<storage, read> profile: array<f32>;
@group(0) @binding(2) var<storage, read_write> rows: array<f32>;
@group(0) @binding(3) var<storage, read_write> hull: array<Piece>;

// Cell q of row `line`: −ln P of a source cell (CPU: the `out_row` fill of `envelope_rows`);
// +∞ for zero, NaN and +∞ cells, which are no parabola.
fn line_offset(p: EnvelopeParams, line: u32, q: u32) -> f32 {
    let cell = profile[p.cell_offset + line * p.res + q];
    if cell > 0.0 && is_finite(cell) {
        return -log(cell);
    }
    return bitcast<f32>(INF_BITS);
}

fn line_emit(p: EnvelopeParams, line: u32, x: u32, value: f32) {
    rows[p.cell_offset + line * p.res + x] = value;
}

// No source on this row.
fn line_empty(p: EnvelopeParams, line: u32, x: u32) {
    rows[p.cell_offset + line * p.res + x] = bitcast<f32>(INF_BITS);
}

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = params[id.y];
    if id.x < p.res {
        lower_envelope(p, id.x);
    }
}
