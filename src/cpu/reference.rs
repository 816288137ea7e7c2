//! f64 brute-force references, for tests and the benchmark's comparison column only.

/// The upper envelope `E(x) = max_k P_k·exp(−c·|x − x_k|²)` over every cell pair, O(N²) in the
/// number of cells, in f64. `c = 1/(2σ²)` with σ in cells; cell coordinates are indices.
///
/// Every source with `P > 0` is evaluated at every cell, directly in the linear domain (no
/// logarithms, so it shares no trick with the fast kernels). The Gaussian factors as
/// `exp(−c·dx²)·exp(−c·dy²)`, so one table of `exp(−c·t²)` replaces the per-pair `exp`; a row
/// where a source's factor has underflowed to exactly 0 contributes exactly 0 and is skipped.
///
/// # Panics
///
/// If `profile` is shorter than `res²`.
pub fn envelope_brute(res: u32, c: f64, profile: &[f32]) -> Vec<f64> {
    let n = res as usize;
    let mut out = vec![0.0f64; n * n];
    if n == 0 {
        return out;
    }
    // g[n − 1 + t] = exp(−c·t²) for t in −(n − 1)..=n − 1.
    let g: Vec<f64> = (0..2 * n - 1)
        .map(|k| {
            let t = k as f64 - (n - 1) as f64;
            (-c * t * t).exp()
        })
        .collect();
    // Sources: cells with P > 0 (NaN is none).
    for (k, &p) in profile[..n * n].iter().enumerate().filter(|(_, p)| **p > 0.0) {
        let (yk, xk) = (k / n, k % n);
        // Along a row, cell i sees the source at column distance i − xk.
        let gx = &g[n - 1 - xk..2 * n - 1 - xk];
        let gy = &g[n - 1 - yk..2 * n - 1 - yk];
        for (row, &fy) in out.chunks_exact_mut(n).zip(gy) {
            let py = f64::from(p) * fy;
            if py == 0.0 {
                continue;
            }
            for (e, &fx) in row.iter_mut().zip(gx) {
                let v = py * fx;
                if v > *e {
                    *e = v;
                }
            }
        }
    }
    out
}
