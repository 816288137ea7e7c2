// envelope_cols: second pass of the exact Gaussian envelope (ARCHITECTURE.md §4 "Broadening").
//
// For every column i and row j of every dent of the batch:
//   envelope[j][i] = exp(−min_k (c·(j − k)² + rows[k][i]))  over the finite rows[k][i],
//   envelope[j][i] = 0 where column i has none (every term is +∞).
// `rows` is the output of envelope_rows, `envelope` the exact upper envelope
// max_k P_k·exp(−c·|x − x_k|²) in the profile's units. CPU twin: src/cpu/envelope_cols.rs, which
// runs the line routine `lower_envelope` of src/cpu/envelope_rows.rs down each column (gathered
// in blocks of 16 for the cache; every column is independent, so here one invocation sweeps one
// column). The line routine is shaders/shared/envelope_line.wgsl, prepended to this file; its
// differences from the CPU routine are listed there and change no result.
//
// Bindings (group 0):
//   0 params:   array<EnvelopeParams>, read  one per dent: res (cells per side), c = 1/(2σ²)
//                                            (1/cell², σ in cells), cell_offset
//   1 rows:     array<f32>, read             output of envelope_rows, each dent res×res
//                                            row-major from its cell_offset; +∞ = no source
//   2 envelope: array<f32>, read_write       the result, same layout
//   3 hull:     array<Piece>, read_write     scratch, at least as many entries as cells; entry k
//                                            (1-based) of column i's hull is at
//                                            cell_offset + (k − 1)·res + i (see hull_slot)
// Dispatch: one invocation per grid column, x = column index i within the dent, y = dent index
// of the batch; workgroups [ceil(max res / 64), batch, 1].
// Host constants it must match (src/gpu/envelope_rows.rs): WORKGROUP = 64 (@workgroup_size),
// PIECE_BYTES = 12 (size of Piece), and the +∞ of envelope_rows (f32::INFINITY, INF_BITS).

@group(0) @binding(0) var<storage, read> params: array<EnvelopeParams>;
@group(0) @binding(1) var<storage, read> rows: array<f32>;
@group(0) @binding(2) var<storage, read_write> envelope: array<f32>;
@group(0) @binding(3) var<storage, read_write> hull: array<Piece>;

// Cell q of column `line`: the rows pass's value; +∞ (or otherwise not finite) is no source.
fn line_offset(p: EnvelopeParams, line: u32, q: u32) -> f32 {
    return rows[p.cell_offset + line + q * p.res];
}

// One exp per output cell.
fn line_emit(p: EnvelopeParams, line: u32, x: u32, value: f32) {
    envelope[p.cell_offset + line + x * p.res] = exp(-value);
}

// No source in this column: exp(−∞) = 0.
fn line_empty(p: EnvelopeParams, line: u32, x: u32) {
    envelope[p.cell_offset + line + x * p.res] = 0.0;
}

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = params[id.y];
    if id.x < p.res {
        lower_envelope(p, id.x);
    }
}
