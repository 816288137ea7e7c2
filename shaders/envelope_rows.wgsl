// envelope_rows: first pass of the exact Gaussian envelope (DESIGN.md §4 "Broadening").
//
// For every row j and column i of every dent of the batch:
//   rows[j][i] = min_k (c·(i − k)² − ln P[j][k])  over the cells k of row j with 0 < P < ∞,
//   rows[j][i] = +∞ (bits 0x7f800000) where row j has no such cell.
// It is the lower envelope of identical parabolas (a Felzenszwalb–Huttenlocher generalized
// distance transform), O(res) per row. CPU twin: src/cpu/envelope_rows.rs (`envelope_rows` and
// its line routine `lower_envelope`), followed statement by statement; the line routine is
// repeated in envelope_cols.wgsl (WGSL has no includes): keep the two in step.
// Differences from the twin, none of which changes a result:
//   - the hull floor hull[0] and the sentinel hull[m + 1] become the tests `m > 1` and `k < m`;
//   - the first parabola's b = −∞ is never read (it is never popped, and sweep 2 reads b from
//     entry 2 on), so it is stored as 0;
//   - w = u + v is not stored: the final hull's left neighbour of entry k + 1 is entry k, so
//     sweep 2 forms it as cur.v + next.v, the same exact integer sum;
//   - b multiplies by 1/(c·Δ) computed in place instead of read from a table (same operations).
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

// One parabola of a line's lower envelope, as kept on the hull (CPU: `Piece`).
struct Piece {
    // Source cell index along the line, as a float (exact).
    v: f32,
    // Its offset f_v (log domain, dimensionless).
    f: f32,
    // (f_v − f_u)/(c·(v − u)) against the previous hull entry u, which puts their breakpoint at
    // (u + v + b)/2, in cells; unused (0) for the first entry.
    b: f32,
}

// Bits of f32 +∞; an f32 whose exponent bits are all set is +∞, −∞ or NaN.
const INF_BITS: u32 = 0x7f800000u;

@group(0) @binding(0) var<storage, read> params: array<EnvelopeParams>;
@group(0) @binding(1) var<storage, read> profile: array<f32>;
@group(0) @binding(2) var<storage, read_write> rows: array<f32>;
@group(0) @binding(3) var<storage, read_write> hull: array<Piece>;

// Whether x is finite, on its bits (immune to fast-math assumptions about ∞ and NaN).
fn is_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & INF_BITS) != INF_BITS;
}

// Scratch index of hull entry k (1-based) of line `line`: entries of neighbouring lines are
// adjacent, so invocations side by side touch neighbouring words.
fn hull_slot(p: EnvelopeParams, line: u32, k: u32) -> u32 {
    return p.cell_offset + (k - 1u) * p.res + line;
}

// −ln P of a source cell (CPU: the `out_row` fill of `envelope_rows`); +∞ for zero, NaN and +∞
// cells, which are no parabola.
fn offset_of(p: f32) -> f32 {
    if p > 0.0 && is_finite(p) {
        return -log(p);
    }
    return bitcast<f32>(INF_BITS);
}

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = params[id.y];
    let n = p.res;
    let line = id.x;
    if line >= n {
        return;
    }
    let c = p.c;
    let base = p.cell_offset + line * n;

    // Sweep 1: hull entries 1..m−1 then `top` hold, left to right, the parabolas lowest
    // somewhere on [0, q]; `top` stays in registers. m = 0 until the first source is met.
    var m = 0u;
    var top = Piece(0.0, 0.0, 0.0);
    for (var q = 0u; q < n; q++) {
        let fq = offset_of(profile[base + q]);
        if !is_finite(fq) {
            continue;
        }
        let qf = f32(q);
        if m == 0u {
            top = Piece(qf, fq, 0.0);
            m = 1u;
            continue;
        }
        loop {
            let b = (fq - top.f) * (1.0 / (c * f32(q - u32(top.v))));
            // Pop `top` when the new parabola undercuts it before it undercuts its left
            // neighbour u: (top.v + q + b)/2 <= (u + top.v + top.b)/2, integers on the right.
            // The first parabola (m = 1) is never popped.
            if m > 1u && b - top.b <= hull[hull_slot(p, line, m - 1u)].v - qf {
                m -= 1u;
                top = hull[hull_slot(p, line, m)];
                continue;
            }
            hull[hull_slot(p, line, m)] = top;
            m += 1u;
            top = Piece(qf, fq, b);
            break;
        }
    }
    if m == 0u {
        // No source on this row.
        for (var x = 0u; x < n; x++) {
            rows[base + x] = bitcast<f32>(INF_BITS);
        }
        return;
    }
    hull[hull_slot(p, line, m)] = top;

    // Sweep 2: advance to the parabola whose interval holds x, i.e. while the next breakpoint
    // (v_k + v_{k+1} + b_{k+1})/2 lies left of x.
    // `cur` is entry k, `next` entry k + 1 while k < m (the CPU's sentinel: never passed).
    var k = 1u;
    var cur = hull[hull_slot(p, line, 1u)];
    var next = cur;
    if m > 1u {
        next = hull[hull_slot(p, line, 2u)];
    }
    for (var x = 0u; x < n; x++) {
        let xf = f32(x);
        while k < m && next.b < 2.0 * xf - (cur.v + next.v) {
            k += 1u;
            cur = next;
            if k < m {
                next = hull[hull_slot(p, line, k + 1u)];
            }
        }
        let d = xf - cur.v;
        rows[base + x] = c * d * d + cur.f;
    }
}
