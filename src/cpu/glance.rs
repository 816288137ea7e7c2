//! Maps the smoothed profile onto the collision plane and shears it along the relative velocity
//! (paper §3.3, ARCHITECTURE.md §4). CPU twin of `shaders/glance.wgsl`.

use std::ops::Range;

use glam::Vec4;

use super::GlanceParams;
use super::sample::{bilinear, near_grid};

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
    let band = glance_band(params, heights, dent_map);
    let width = params.dst_res as usize;
    dent_map[..band.start * width].fill([0.0; 4]);
    dent_map[band.end * width..].fill([0.0; 4]);
}

/// As [`glance`], but writes only the rows that can read a height (the band of rows whose
/// source row lies within a cell of the heights grid) and returns that band; every other row
/// would be all zeros, and the caller has them zero already (a fresh zeroed buffer).
///
/// A glancing dent's map is `1/cos θ` cells wide along t̂ but only as tall as the heights
/// grid across it: writing the band alone costs `res²/cos θ` cells instead of `res²/cos² θ`,
/// with the same values.
///
/// # Panics
/// As [`glance`].
pub(crate) fn glance_band(params: &GlanceParams, heights: &[f32], dent_map: &mut [[f32; 4]]) -> Range<usize> {
    let p = params;
    assert_eq!(heights.len(), (p.src_res as usize).pow(2), "glance: heights must hold src_res² values");
    assert_eq!(dent_map.len(), (p.dst_res as usize).pow(2), "glance: dent_map must hold dst_res² cells");
    let normal = glam::Vec3::from_array(p.normal);
    let tangent = glam::Vec3::from_array(p.tangent);
    let dst_shift = 0.5 * p.dst_res as f32 - 0.5;
    let src_shift = 0.5 * p.src_res as f32 - 0.5;
    let source_row = |row: usize| {
        let v = (row as f32 - dst_shift) * p.dst_cell_size;
        v / p.src_cell_size + src_shift
    };
    // Rows whose source row is outside (−1, src_res) read only zeros (`bilinear`'s `near_grid`);
    // the source row grows with the row, so they lie before and after one band.
    let reads = |row: usize| near_grid(p.src_res, 0.0, source_row(row));
    let rows = p.dst_res as usize;
    let start = (0..rows).find(|&r| reads(r)).unwrap_or(rows);
    let end = (start..rows).rev().find(|&r| reads(r)).map_or(start, |r| r + 1);
    // Everything that depends on the column alone: the source column and the shear factor
    // 2·sin θ/(1 + e^{−t·u}). The shader computes both per cell; hoisting them is exact.
    let columns: Vec<(f32, f32)> = (0..p.dst_res)
        .map(|col| {
            let u = (col as f32 - dst_shift) * p.dst_cell_size;
            (u * p.cos_theta / p.src_cell_size + src_shift, 2.0 * p.sin_theta / (1.0 + (-p.widen * u).exp()))
        })
        .collect();
    let width = p.dst_res as usize;
    for (row, cells) in dent_map[start * width..end * width].chunks_exact_mut(width).enumerate() {
        let y = source_row(start + row);
        for (cell, &(x, shear)) in cells.iter_mut().zip(&columns) {
            let height = bilinear(heights, p.src_res, x, y);
            let delta = height * p.cos_theta * normal + (shear * height) * tangent;
            *cell = Vec4::from((delta, height)).to_array();
        }
    }
    start..end
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The band is exact: every cell of a steep glance's map (θ ≈ 84°, 7.7× wider than its
    /// heights) equals the per-cell formula the shader evaluates everywhere, and the band is
    /// no taller than the heights grid plus the two rows that straddle its border.
    #[test]
    fn band_matches_every_cell() {
        let (src_res, cos_theta) = (40u32, 0.13f32);
        let heights: Vec<f32> = (0..src_res * src_res).map(|k| ((k * 37 % 101) as f32) / 100.0).collect();
        let dst_res = (src_res as f32 / cos_theta).ceil() as u32;
        let src_cell_size = 0.01;
        let params = GlanceParams {
            src_res,
            src_cell_size,
            dst_res,
            dst_cell_size: src_cell_size * src_res as f32 / cos_theta / dst_res as f32,
            cos_theta,
            sin_theta: (1.0 - cos_theta * cos_theta).sqrt(),
            widen: 3.0,
            src_offset: 0,
            normal: [0.0, -1.0, 0.0],
            dst_offset: 0,
            tangent: [1.0, 0.0, 0.0],
            _pad: 0,
        };
        let mut cells = vec![[7.0; 4]; (dst_res * dst_res) as usize];
        glance(&params, &heights, &mut cells);
        let mut band_only = vec![[0.0; 4]; cells.len()];
        let band = glance_band(&params, &heights, &mut band_only);
        assert!(band.len() <= src_res as usize + 2, "band {band:?} of {dst_res} rows");
        assert_eq!(cells, band_only);
        let (dst_shift, src_shift) = (0.5 * dst_res as f32 - 0.5, 0.5 * src_res as f32 - 0.5);
        for (k, cell) in cells.iter().enumerate() {
            let (row, col) = (k / dst_res as usize, k % dst_res as usize);
            let u = (col as f32 - dst_shift) * params.dst_cell_size;
            let v = (row as f32 - dst_shift) * params.dst_cell_size;
            let x = u * cos_theta / src_cell_size + src_shift;
            let height = bilinear(&heights, src_res, x, v / src_cell_size + src_shift);
            let shear = 2.0 * params.sin_theta / (1.0 + (-params.widen * u).exp());
            let delta = height * cos_theta * glam::Vec3::NEG_Y + (shear * height) * glam::Vec3::X;
            assert_eq!(*cell, Vec4::from((delta, height)).to_array(), "cell ({row}, {col})");
        }
    }
}
