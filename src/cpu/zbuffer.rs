//! Z-buffer profile of the projectile (paper §3.2, DESIGN.md §4). CPU twin of `shaders/zbuffer.wgsl`.

use glam::Vec3;

use super::ZbufferParams;

/// Writes the projectile profile `P = max(0, d + max s)` of every cell, where
/// `s(p) = (p − grid.origin)·grid.axis_z ≤ 0` over the surface along the cell-centre ray.
/// `profile` is `res × res`, row-major.
pub fn zbuffer(params: &ZbufferParams, positions: &[Vec3], faces: &[[u32; 3]], profile: &mut [f32]) {
    let _ = (params, positions, faces, profile);
    todo!("zbuffer: being written")
}
