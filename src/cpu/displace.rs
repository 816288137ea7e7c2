//! Moves the target's vertices by the attenuated dent map (paper §3.1). CPU twin of
//! `shaders/displace.wgsl`.

use glam::{Vec3, Vec4};

use super::Attenuation;
use super::DisplaceParams;
use super::layout::falloff;
use super::sample::{bilinear, near_grid};

/// For every vertex at grid coordinates `(x, y)` and depth `z` below the collision plane, adds
/// `a(z)·Δ(x, y)` where `Δ` is the dent map (`[Δx, Δy, Δz, height]` per cell, world units)
/// sampled bilinearly and zero off the grid. Sets `moved[k]` for each vertex whose position
/// changed (leaves the others as they were).
///
/// `table` holds the falloff samples when `params.falloff` is [`falloff::TABLE`] (see
/// [`falloff_table`]), and is ignored otherwise.
///
/// # Panics
/// If `dent_map` does not hold `res²` cells, `moved` is shorter than `positions`, or the falloff
/// is [`falloff::TABLE`] with fewer than two table entries.
pub fn displace(
    params: &DisplaceParams,
    dent_map: &[[f32; 4]],
    table: &[f32],
    positions: &mut [Vec3],
    moved: &mut [bool],
) {
    let grid = &params.grid;
    assert_eq!(dent_map.len(), (grid.res as usize).pow(2), "displace: dent_map must hold res² cells");
    assert!(moved.len() >= positions.len(), "displace: one moved flag per vertex");
    assert!(params.falloff != falloff::TABLE || table.len() >= 2, "displace: a falloff table needs two entries");
    let origin = Vec3::from_array(grid.origin);
    let inv_h = 1.0 / grid.cell_size;
    let axis_x = Vec3::from_array(grid.axis_x) * inv_h;
    let axis_y = Vec3::from_array(grid.axis_y) * inv_h;
    let axis_z = Vec3::from_array(grid.axis_z);
    let shift = 0.5 * grid.res as f32 - 0.5;
    let d = params.dent_distance;
    for (p, moved) in positions.iter_mut().zip(moved.iter_mut()) {
        let r = *p - origin;
        let (x, y) = (r.dot(axis_x) + shift, r.dot(axis_y) + shift);
        if !near_grid(grid.res, x, y) {
            continue;
        }
        let delta = bilinear(cast_cells(dent_map), grid.res, x, y).truncate();
        if delta == Vec3::ZERO {
            continue;
        }
        let a = attenuation(params, table, r.dot(axis_z), d);
        let new = *p + a * delta;
        if new != *p {
            *p = new;
            *moved = true;
        }
    }
}

/// `a(z)` as the shader computes it.
#[inline]
fn attenuation(params: &DisplaceParams, table: &[f32], z: f32, d: f32) -> f32 {
    if z <= 0.0 {
        return 1.0;
    }
    match params.falloff {
        falloff::LOGISTIC => 2.0 / (1.0 + (z / d).exp()),
        falloff::LINEAR => (1.0 - z / (params.falloff_scale * d)).max(0.0),
        falloff::TABLE => {
            let last = (table.len() - 1) as f32;
            let t = (z / (falloff::TABLE_DEPTH * d) * last).min(last);
            let k = (t as usize).min(table.len() - 2);
            let f = t - k as f32;
            table[k] * (1.0 - f) + table[k + 1] * f
        }
        _ => 1.0,
    }
}

/// The falloff code, linear scale and sample table that [`displace`] uses for `attenuation`:
/// built-in falloffs are evaluated exactly; a custom one is sampled at
/// `falloff::TABLE_LEN` points over `z ∈ [0, 8d]` and interpolated linearly.
pub fn falloff_table(attenuation: &Attenuation, dent_distance: f32) -> (u32, f32, Vec<f32>) {
    match attenuation {
        Attenuation::Logistic => (falloff::LOGISTIC, 0.0, Vec::new()),
        Attenuation::Linear { scale } => (falloff::LINEAR, *scale, Vec::new()),
        Attenuation::None => (falloff::NONE, 0.0, Vec::new()),
        Attenuation::Custom(_) => {
            let last = (falloff::TABLE_LEN - 1) as f32;
            let table = (0..falloff::TABLE_LEN)
                .map(|k| attenuation.eval(k as f32 / last * falloff::TABLE_DEPTH * dent_distance, dent_distance))
                .collect();
            (falloff::TABLE, 0.0, table)
        }
    }
}

fn cast_cells(cells: &[[f32; 4]]) -> &[Vec4] {
    bytemuck::cast_slice(cells)
}
