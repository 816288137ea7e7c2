//! f64 brute-force references, for tests and the benchmark's comparison column only.

/// The upper envelope `E(x) = max_k P_k·exp(−c·|x − x_k|²)` over every cell pair, O(N²) in the
/// number of cells, in f64. `c = 1/(2σ²)` with σ in cells; cell coordinates are indices.
pub fn envelope_brute(res: u32, c: f64, profile: &[f32]) -> Vec<f64> {
    let _ = (res, c, profile);
    todo!("envelope_brute: being written")
}
