// Parameter blocks shared by every kernel, prepended to each shader by src/gpu/kernel.rs.
// Keep in sync with src/cpu/layout.rs (same field order; each vec3<f32> is followed by a 4-byte
// scalar, so the WGSL and #[repr(C)] layouts agree byte for byte). Units as documented there.

struct GridUniform {
    origin: vec3<f32>,
    cell_size: f32,
    axis_x: vec3<f32>,
    res: u32,
    axis_y: vec3<f32>,
    _pad0: u32,
    axis_z: vec3<f32>,
    _pad1: u32,
}

struct ZbufferParams {
    grid: GridUniform,
    dent_distance: f32,
    face_count: u32,
    face_offset: u32,
    cell_offset: u32,
}

struct EnvelopeParams {
    res: u32,
    c: f32,
    cell_offset: u32,
    _pad: u32,
}

struct HeatParams {
    res: u32,
    rate: f32,
    clamped: u32,
    cell_offset: u32,
}

struct GlanceParams {
    src_res: u32,
    src_cell_size: f32,
    dst_res: u32,
    dst_cell_size: f32,
    cos_theta: f32,
    sin_theta: f32,
    widen: f32,
    src_offset: u32,
    normal: vec3<f32>,
    dst_offset: u32,
    tangent: vec3<f32>,
    _pad: u32,
}

// Falloff codes of DisplaceParams.falloff (src/cpu/layout.rs, mod falloff).
const FALLOFF_NONE: u32 = 0u;
const FALLOFF_LOGISTIC: u32 = 1u;
const FALLOFF_LINEAR: u32 = 2u;
const FALLOFF_TABLE: u32 = 3u;
const FALLOFF_TABLE_DEPTH: f32 = 8.0;

struct DisplaceParams {
    grid: GridUniform,
    dent_distance: f32,
    falloff: u32,
    falloff_scale: f32,
    vertex_count: u32,
    vertex_offset: u32,
    cell_offset: u32,
    table_offset: u32,
    table_len: u32,
}
