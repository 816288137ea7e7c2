//! `#[repr(C)]` parameter blocks of the kernels, laid out exactly as the WGSL uniform structs.
//!
//! Keep in sync with `shaders/shared/layout.wgsl`: every `vec3<f32>` is followed by a 4-byte
//! scalar so that each struct packs with no implicit padding on either side.
//!
//! The `*_offset` fields place one dent's data inside the flat buffers of a GPU batch (in
//! elements of that buffer); the CPU twins take slices already cut to one dent and ignore them.

use bytemuck::{Pod, Zeroable};

/// A [`Grid`](crate::dent::Grid) in GPU layout. 64 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GridUniform {
    /// Grid centre, world units.
    pub origin: [f32; 3],
    /// Cell side, world units.
    pub cell_size: f32,
    /// Unit column direction.
    pub axis_x: [f32; 3],
    /// Cells per side.
    pub res: u32,
    /// Unit row direction.
    pub axis_y: [f32; 3],
    /// Padding, zero.
    pub _pad0: u32,
    /// Unit depth direction.
    pub axis_z: [f32; 3],
    /// Padding, zero.
    pub _pad1: u32,
}

/// Inputs of the `zbuffer` kernel. 80 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct ZbufferParams {
    /// Z-buffer grid: `origin` on the projectile's most advanced point along `axis_z`.
    pub grid: GridUniform,
    /// Dent distance d, world units: the profile keeps the part of the projectile within d of
    /// its tip.
    pub dent_distance: f32,
    /// Number of triangles.
    pub face_count: u32,
    /// First triangle of this dent's projectile in a batched face buffer.
    pub face_offset: u32,
    /// First cell of this dent's profile in a batched grid buffer.
    pub cell_offset: u32,
}

/// Inputs of the `envelope_rows` and `envelope_cols` kernels.
/// 16 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct EnvelopeParams {
    /// Cells per side.
    pub res: u32,
    /// Gaussian coefficient `c = 1/(2σ²)` with σ in cells (1/cell²).
    pub c: f32,
    /// First cell of this dent's grid in a batched grid buffer.
    pub cell_offset: u32,
    /// Padding, zero.
    pub _pad: u32,
}

impl EnvelopeParams {
    /// Parameters for Gaussians of width `sigma_cells` (σ in cells) on a `res × res` grid; `c` is
    /// clamped to 10⁴, past which `e^{−c}` is already 0 in f32, so σ ≪ 1 cell stays finite.
    pub fn new(res: u32, sigma_cells: f32) -> Self {
        Self { res, c: (0.5 / (sigma_cells * sigma_cells)).min(1e4), cell_offset: 0, _pad: 0 }
    }
}

/// Inputs of one `heat_step` of the heat kernel. 16 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct HeatParams {
    /// Cells per side.
    pub res: u32,
    /// α of `E ← E + α·ΔE`, in (0, ¼].
    pub rate: f32,
    /// 1 for the increase-only step `E ← max(E, E + α·ΔE)`, 0 for the plain one.
    pub clamped: u32,
    /// First cell of this dent's grid in a batched grid buffer.
    pub cell_offset: u32,
}

/// Inputs of the `glance` kernel. 64 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GlanceParams {
    /// Side of the smoothed height grid (the Z-buffer grid), cells.
    pub src_res: u32,
    /// Its cell side, world units.
    pub src_cell_size: f32,
    /// Side of the dent-map grid on the collision plane, cells.
    pub dst_res: u32,
    /// Its cell side, world units.
    pub dst_cell_size: f32,
    /// cos θ, clamped to at least `min_cos`.
    pub cos_theta: f32,
    /// sin θ.
    pub sin_theta: f32,
    /// Widening t, 1/world unit.
    pub widen: f32,
    /// First cell of this dent's heights in a batched grid buffer.
    pub src_offset: u32,
    /// Unit denting normal n̂, world.
    pub normal: [f32; 3],
    /// First cell of this dent's map in a batched map buffer.
    pub dst_offset: u32,
    /// Unit in-plane velocity direction t̂, world.
    pub tangent: [f32; 3],
    /// Padding, zero.
    pub _pad: u32,
}

/// Falloff codes of [`DisplaceParams::falloff`].
pub mod falloff {
    /// `a = 1`.
    pub const NONE: u32 = 0;
    /// `a = 2/(1 + e^{z/d})`.
    pub const LOGISTIC: u32 = 1;
    /// `a = max(0, 1 − z/(scale·d))`.
    pub const LINEAR: u32 = 2;
    /// Linear interpolation in a table of `a` sampled uniformly over `z ∈ [0, TABLE_DEPTH·d]`.
    pub const TABLE: u32 = 3;
    /// Depth covered by a falloff table, in dent distances; past it the last entry holds.
    pub const TABLE_DEPTH: f32 = 8.0;
    /// Entries of a falloff table.
    pub const TABLE_LEN: usize = 257;
}

/// Inputs of the `displace` kernel. 96 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct DisplaceParams {
    /// Dent-map grid on the collision plane; `axis_z` is the denting normal.
    pub grid: GridUniform,
    /// Dent distance d, world units.
    pub dent_distance: f32,
    /// One of the [`falloff`] codes.
    pub falloff: u32,
    /// `scale` of the linear falloff (dent distances); unused otherwise.
    pub falloff_scale: f32,
    /// Number of vertices.
    pub vertex_count: u32,
    /// First vertex of this dent's target in a batched vertex buffer.
    pub vertex_offset: u32,
    /// First cell of this dent's map in a batched map buffer.
    pub cell_offset: u32,
    /// First entry of this dent's falloff table in a batched table buffer.
    pub table_offset: u32,
    /// Entries in the falloff table (0 unless `falloff` is [`falloff::TABLE`]).
    pub table_len: u32,
}
