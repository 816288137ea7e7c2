//! Lists the vertices of one target that the last batch moved. CPU twin of `shaders/moved.wgsl`.

use bytemuck::{Pod, Zeroable};

/// Which vertices of the resident buffer form the target. 16 bytes; keep in sync with
/// `MovedParams` in `shaders/moved.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Pod, Zeroable)]
pub struct MovedParams {
    /// First vertex of the target in the vertex buffer (vertices).
    pub vertex_offset: u32,
    /// Vertices of the target.
    pub vertex_count: u32,
    /// Padding, zero.
    pub _pad: [u32; 2],
}

/// Appends `[v, x bits, y bits, z bits]` to `out` for every target vertex `v` (index within the
/// target) whose moved flag (`w`, world-unit xyz) is set, in ascending `v`: the list the GPU
/// kernel builds in some order.
///
/// # Panics
/// If the target's vertex range is outside `positions`.
pub fn moved(params: &MovedParams, positions: &[[f32; 4]], out: &mut Vec<[u32; 4]>) {
    let first = params.vertex_offset as usize;
    let target = &positions[first..first + params.vertex_count as usize];
    for (v, p) in target.iter().enumerate() {
        if p[3] > 0.0 {
            out.push([v as u32, p[0].to_bits(), p[1].to_bits(), p[2].to_bits()]);
        }
    }
}
