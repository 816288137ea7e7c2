// The line routine of the exact Gaussian envelope, shared by envelope_rows.wgsl and
// envelope_cols.wgsl (prepended to both by src/gpu/shaders.rs): the lower envelope of identical
// parabolas c·(x − v)² + f_v along one grid line, O(res), the twin of `lower_envelope` in
// src/cpu/envelope_rows.rs, followed statement by statement. Differences from the twin, none of
// which changes a result:
//   - the hull floor hull[0] and the sentinel hull[m + 1] become the tests `m > 1` and `k < m`;
//   - the first parabola's b = −∞ is never read (it is never popped, and sweep 2 reads b from
//     entry 2 on), so it is stored as 0;
//   - w = u + v is not stored: the final hull's left neighbour of entry k + 1 is entry k, so
//     sweep 2 forms it as cur.v + next.v, the same exact integer sum;
//   - b multiplies by 1/(c·Δ) computed in place instead of read from a table (same operations).
// Each including shader declares `hull: array<Piece>` (binding 3) and the hooks
// `line_offset(p, line, q) -> f32` (the offset f_q of cell q, +∞ when it is no source),
// `line_emit(p, line, x, value)` (the envelope's value c·d² + f at cell x) and
// `line_empty(p, line, x)` (cell x of a line with no source).

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

// Whether x is finite, on its bits (immune to fast-math assumptions about ∞ and NaN).
fn is_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & INF_BITS) != INF_BITS;
}

// Scratch index of hull entry k (1-based) of line `line`: entries of neighbouring lines are
// adjacent, so invocations side by side touch neighbouring words.
fn hull_slot(p: EnvelopeParams, line: u32, k: u32) -> u32 {
    return p.cell_offset + (k - 1u) * p.res + line;
}

// The lower envelope along line `line` of a dent with parameters `p`.
fn lower_envelope(p: EnvelopeParams, line: u32) {
    let n = p.res;
    let c = p.c;

    // Sweep 1: hull entries 1..m−1 then `top` hold, left to right, the parabolas lowest
    // somewhere on [0, q]; `top` stays in registers. m = 0 until the first source is met.
    var m = 0u;
    var top = Piece(0.0, 0.0, 0.0);
    for (var q = 0u; q < n; q++) {
        let fq = line_offset(p, line, q);
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
        for (var x = 0u; x < n; x++) {
            line_empty(p, line, x);
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
        line_emit(p, line, x, c * d * d + cur.f);
    }
}
