//! Maps the smoothed profile onto the collision plane and shears it along the relative velocity
//! (paper §3.3, ARCHITECTURE.md §4). CPU twin of `shaders/glance.wgsl`.

use glam::Vec4;

use super::GlanceParams;
use super::sample::bilinear;

/// For every dent-map cell at in-plane coordinates `(u, v)` (world units from the impact point
/// along t̂ and n̂ × t̂), samples the height `D₂ = heights(u·cos θ, v)` (the 1/cos θ stretch of
/// the oblique projection) and writes the displacement
/// `Δ = D₂·cos θ·n̂ + 2·sin θ·D₂ / (1 + e^{−t·u})·t̂` as `[Δx, Δy, Δz, D₂]`, world units.
///
/// Head-on (`sin θ = 0`, `cos θ = 1`, equal grids) this is `Δ = D₂·n̂`; with `t = 0` the
/// displacement has length `D₂` along the velocity and depth `D₂·cos θ`.
///
/// # Panics
/// If `heights` does not hold `src_res²` values or `dent_map` `dst_res²` cells.
pub fn glance(params: &GlanceParams, heights: &[f32], dent_map: &mut [[f32; 4]]) {
    let p = params;
    assert_eq!(heights.len(), (p.src_res as usize).pow(2), "glance: heights must hold src_res² values");
    assert_eq!(dent_map.len(), (p.dst_res as usize).pow(2), "glance: dent_map must hold dst_res² cells");
    let normal = glam::Vec3::from_array(p.normal);
    let tangent = glam::Vec3::from_array(p.tangent);
    let dst_shift = 0.5 * p.dst_res as f32 - 0.5;
    let src_shift = 0.5 * p.src_res as f32 - 0.5;
    // Everything that depends on the column alone: the source column and the shear factor
    // 2·sin θ/(1 + e^{−t·u}). The shader computes both per cell; hoisting them is exact.
    let columns: Vec<(f32, f32)> = (0..p.dst_res)
        .map(|col| {
            let u = (col as f32 - dst_shift) * p.dst_cell_size;
            (u * p.cos_theta / p.src_cell_size + src_shift, 2.0 * p.sin_theta / (1.0 + (-p.widen * u).exp()))
        })
        .collect();
    for (row, cells) in dent_map.chunks_exact_mut(p.dst_res as usize).enumerate() {
        let v = (row as f32 - dst_shift) * p.dst_cell_size;
        let y = v / p.src_cell_size + src_shift;
        for (cell, &(x, shear)) in cells.iter_mut().zip(&columns) {
            let height = bilinear(heights, p.src_res, x, y);
            let delta = height * p.cos_theta * normal + (shear * height) * tangent;
            *cell = Vec4::from((delta, height)).to_array();
        }
    }
}
