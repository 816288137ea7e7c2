//! Heat smoothing of the envelope (paper §3.2). CPU twin of `shaders/heat.wgsl`.

use super::HeatParams;

/// One explicit step `dst = src + α·Δsrc` (5-point Laplacian, zero outside the grid); with
/// `clamped = 1`, `dst = max(src, src + α·Δsrc)`.
pub fn heat_step(params: &HeatParams, src: &[f32], dst: &mut [f32]) {
    let _ = (params, src, dst);
    todo!("heat_step: being written")
}

/// `heat_iters` plain steps, rescale so the peak equals `dent_distance`, then `clamp_iters`
/// clamped steps, in place. An all-zero grid stays zero.
pub fn heat(values: &mut [f32], res: u32, rate: f32, heat_iters: u32, clamp_iters: u32, dent_distance: f32) {
    let _ = (values, res, rate, heat_iters, clamp_iters, dent_distance);
    todo!("heat: being written")
}
