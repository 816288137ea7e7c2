//! First pass of the exact Gaussian envelope. CPU twin of `shaders/envelope_rows.wgsl`.
//!
//! Along one line of n cells both passes compute the lower envelope of the identical parabolas
//! `c·(x − k)² + f_k` (a Felzenszwalb–Huttenlocher generalized distance transform) in O(n):
//! sweep the sources left to right keeping the parabolas that are lowest somewhere, then sweep
//! the cells reading off the lowest one. Coordinates are cell indices (exact in f32).
//!
//! The breakpoint between hull neighbours `v < q` is `s = (v + q)/2 + b/2` with
//! `b = (f_q − f_v)/(c·(q − v))`. Only `b` is stored: every comparison against a breakpoint
//! moves the integer part to the other side, where it is exact, so no rounding of `s` itself
//! can pick the wrong parabola at a cell. The error left is a few ulps of `f`, which is what
//! evaluating the parabolas costs anyway. Here `b` multiplies by a per-call table of `1/(c·Δ)`
//! where a shader may divide; the two agree to an ulp or two of `b`.

use super::EnvelopeParams;

/// One parabola of a line's lower envelope, as kept on the hull.
#[derive(Debug, Clone, Copy, Default)]
struct Piece {
    /// Source cell index along the line, as a float (exact).
    v: f32,
    /// Its offset `f_v` (log domain, dimensionless).
    f: f32,
    /// `(f_v − f_u)/(c·(v − u))` against the previous hull entry u, which puts their breakpoint
    /// at `(u + v + b)/2`, in cells; −∞ for the first entry.
    b: f32,
    /// `u + v`, cells (exact).
    w: f32,
    /// Source cell index along the line.
    i: u32,
}

/// Per-call scratch of [`lower_envelope`] for lines of `n` cells.
#[derive(Debug)]
pub(super) struct LineScratch {
    /// Coefficient c, 1/cell².
    c: f32,
    /// Hull of the current line between a floor and a sentinel, `n + 2` entries.
    hull: Vec<Piece>,
    /// `recip[Δ] = 1/(c·Δ)` for Δ in 1..n, cell; one division per call instead of one per test.
    recip: Vec<f32>,
}

impl LineScratch {
    /// Scratch for lines of `n` cells and coefficient `c` (1/cell²).
    pub(super) fn new(n: usize, c: f32) -> Self {
        let recip = (0..n).map(|d| 1.0 / (c * d as f32)).collect();
        Self { c, hull: vec![Piece::default(); n + 2], recip }
    }
}

/// Overwrites `line[x]` by `min_k (c·(x − k)² + line[k])` over the finite entries k, or `+∞`
/// where there are none. Entries that are `+∞` (or otherwise not finite) are not sources.
/// `line` is at most as long as `scratch` was made for.
pub(super) fn lower_envelope(line: &mut [f32], scratch: &mut LineScratch) {
    let n = line.len();
    let c = scratch.c;
    let hull = &mut scratch.hull[..n + 2];
    let recip = &scratch.recip[..n];
    let mut sources = line.iter().enumerate().filter(|(_, f)| f.is_finite());
    let Some((first, &f_first)) = sources.next() else {
        line.fill(f32::INFINITY);
        return;
    };
    // Sweep 1: `hull[1..m]` then `top` hold, left to right, the parabolas lowest somewhere on
    // [0, q]; `top` stays in registers. `hull[0]` is a floor, read only by tests against the
    // first parabola, whose b = −∞ makes them fail: that one is never popped.
    let mut top = Piece { v: first as f32, f: f_first, b: f32::NEG_INFINITY, w: 0.0, i: first as u32 };
    let mut m = 1;
    for (q, &fq) in sources {
        let qf = q as f32;
        loop {
            let b = (fq - top.f) * recip[q - top.i as usize];
            // Pop `top` when the new parabola undercuts it before it undercuts its left
            // neighbour u: (top.v + q + b)/2 <= (u + top.v + top.b)/2, integers on the right.
            if b - top.b <= hull[m - 1].v - qf {
                m -= 1;
                top = hull[m];
                continue;
            }
            hull[m] = top;
            m += 1;
            top = Piece { v: qf, f: fq, b, w: top.v + qf, i: q as u32 };
            break;
        }
    }
    hull[m] = top;
    // Sentinel: its breakpoint is never passed.
    hull[m + 1] = Piece { v: 0.0, f: f32::INFINITY, b: f32::INFINITY, w: 0.0, i: 0 };

    // Sweep 2: advance to the parabola whose interval holds x, i.e. while the next breakpoint
    // (v_k + v_{k+1} + b_{k+1})/2 lies left of x.
    let mut k = 1;
    for (x, out) in line.iter_mut().enumerate() {
        let x = x as f32;
        while hull[k + 1].b < 2.0 * x - hull[k + 1].w {
            k += 1;
        }
        let d = x - hull[k].v;
        *out = c * d * d + hull[k].f;
    }
}

/// For each row j and column i: `out[j][i] = min_k (c·(i − k)² − ln P[j][k])` over cells with
/// `P > 0`, `+∞` when the row has none.
///
/// `profile` and `out` are `res × res`, row-major; `c = 1/(2σ²)` with σ in cells. One shader
/// invocation per row; here a plain loop over rows.
///
/// # Panics
///
/// If either slice is shorter than `res²`.
pub fn envelope_rows(params: &EnvelopeParams, profile: &[f32], out: &mut [f32]) {
    let n = params.res as usize;
    if n == 0 {
        return;
    }
    let (profile, out) = (&profile[..n * n], &mut out[..n * n]);
    let mut scratch = LineScratch::new(n, params.c);
    for (p_row, out_row) in profile.chunks_exact(n).zip(out.chunks_exact_mut(n)) {
        // One ln per source cell; zero, NaN and +∞ cells are no parabola.
        for (o, &p) in out_row.iter_mut().zip(p_row) {
            *o = if p > 0.0 { -p.ln() } else { f32::INFINITY };
        }
        lower_envelope(out_row, &mut scratch);
    }
}
