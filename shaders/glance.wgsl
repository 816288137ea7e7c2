// glance: maps each dent's smoothed heights (on the Z-buffer grid, perpendicular to the relative
// velocity) onto the collision plane and shears them along the velocity (paper §3.3, ARCHITECTURE.md
// §4). GPU twin of src/cpu/glance.rs, with the bilinear sampling of src/cpu/sample.rs.
//
// For the dent-map cell at in-plane coordinates (u, v) (world units from the impact point along
// t̂ and n̂ × t̂) it samples D₂ = heights(u·cos θ, v) (the 1/cos θ stretch of the oblique
// projection) and writes Δ = D₂·cos θ·n̂ + 2·sin θ·D₂ / (1 + e^{−t·u})·t̂ as vec4(Δ, D₂), world
// units. The CPU hoists each column's source coordinate and shear factor out of the row loop;
// here every cell computes them with the same expressions.
//
// Bindings (group 0):
//   0 params:   array<GlanceParams>  read        per dent: grids, θ, widening t, n̂, t̂, offsets
//   1 heights:  array<f32>           read        src_res² heights per dent at src_offset
//   2 dent_map: array<vec4<f32>>     read_write  dst_res² cells per dent at dst_offset
//
// Dispatch geometry: one invocation per dent-map cell, x = cell index within the dent
// (row-major, row · dst_res + col), y = dent index of the batch; workgroups
// [ceil(max dst_res² / WORKGROUP), batch, 1].
//
// Host constants it must match: WORKGROUP = 256 in src/gpu/glance.rs.

const WORKGROUP: u32 = 256u;

@group(0) @binding(0) var<storage, read> params: array<GlanceParams>;
@group(0) @binding(1) var<storage, read> heights: array<f32>;
@group(0) @binding(2) var<storage, read_write> dent_map: array<vec4<f32>>;

// Cell (column i, row j) of the dent's heights; zero outside the grid.
fn height_at(p: GlanceParams, i: i32, j: i32) -> f32 {
    let n = i32(p.src_res);
    if i >= 0 && i < n && j >= 0 && j < n {
        return heights[p.src_offset + u32(j * n + i)];
    }
    return 0.0;
}

// Bilinear interpolation of the dent's heights at continuous index coordinates (x = column,
// y = row; integers are cell centres), cells outside the grid reading as zero.
fn bilinear(p: GlanceParams, x: f32, y: f32) -> f32 {
    if !near_grid(p.src_res, x, y) {
        return 0.0;
    }
    let b = bilinear_at(x, y);
    let top = height_at(p, b.i0, b.j0) * (1.0 - b.fx) + height_at(p, b.i0 + 1, b.j0) * b.fx;
    let bottom = height_at(p, b.i0, b.j0 + 1) * (1.0 - b.fx) + height_at(p, b.i0 + 1, b.j0 + 1) * b.fx;
    return top * (1.0 - b.fy) + bottom * b.fy;
}

@compute @workgroup_size(WORKGROUP, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = params[id.y];
    if id.x >= p.dst_res * p.dst_res {
        return;
    }
    let row = id.x / p.dst_res;
    let col = id.x % p.dst_res;
    let dst_shift = 0.5 * f32(p.dst_res) - 0.5;
    let src_shift = 0.5 * f32(p.src_res) - 0.5;
    // The column's source coordinate and shear factor 2·sin θ/(1 + e^{−t·u}).
    let u = (f32(col) - dst_shift) * p.dst_cell_size;
    let x = u * p.cos_theta / p.src_cell_size + src_shift;
    let shear = 2.0 * p.sin_theta / (1.0 + exp(-p.widen * u));
    // The row's source coordinate.
    let v = (f32(row) - dst_shift) * p.dst_cell_size;
    let y = v / p.src_cell_size + src_shift;
    let height = bilinear(p, x, y);
    let delta = height * p.cos_theta * p.normal + (shear * height) * p.tangent;
    dent_map[p.dst_offset + id.x] = vec4<f32>(delta, height);
}
