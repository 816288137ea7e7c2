//! Copies a target's positions and normals into an interleaved vertex buffer. CPU twin of
//! `shaders/interleave.wgsl`.

use bytemuck::{Pod, Zeroable};

/// `normal_word` when only positions are copied. Keep in sync with `NO_NORMAL` in
/// `shaders/interleave.wgsl`.
pub const NO_NORMAL: u32 = u32::MAX;

/// Where one target's vertices go in an interleaved buffer, every byte quantity in 4-byte words.
/// 32 bytes; keep in sync with `InterleaveParams` in `shaders/interleave.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Pod, Zeroable)]
pub struct InterleaveParams {
    /// First vertex of the target in the source positions and normals (vertices).
    pub vertex_offset: u32,
    /// Vertices to copy.
    pub vertex_count: u32,
    /// Word of the destination where vertex 0 starts (words from the start of the bound range).
    pub dst_word: u32,
    /// Words from one vertex to the next in the destination.
    pub stride_words: u32,
    /// Word of the position (three f32) within a vertex.
    pub position_word: u32,
    /// Word of the normal (three f32) within a vertex, or `NO_NORMAL`.
    pub normal_word: u32,
    /// Padding, zero.
    pub _pad: [u32; 2],
}

/// For each of the `vertex_count` vertices from `vertex_offset`, writes the bits of the
/// position's xyz (world units) and, unless `normal_word` is `NO_NORMAL`, of the unit normal's
/// xyz into `dst` at the words `params` names; every other word of `dst` is left as it was.
///
/// # Panics
/// If the vertex range is outside `positions` or `normals`, or a written word is outside `dst`
/// (the GPU path validates its input first; see `gpu::interleave`).
pub fn interleave(params: &InterleaveParams, positions: &[[f32; 4]], normals: &[[f32; 4]], dst: &mut [u32]) {
    let write_vec3 = |dst: &mut [u32], word: u32, value: &[f32; 4]| {
        let word = word as usize;
        dst[word] = value[0].to_bits();
        dst[word + 1] = value[1].to_bits();
        dst[word + 2] = value[2].to_bits();
    };
    for v in 0..params.vertex_count {
        let source = (params.vertex_offset + v) as usize;
        let base = params.dst_word + v * params.stride_words;
        write_vec3(dst, base + params.position_word, &positions[source]);
        if params.normal_word != NO_NORMAL {
            write_vec3(dst, base + params.normal_word, &normals[source]);
        }
    }
}
