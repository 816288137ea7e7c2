// displace: moves a target's vertices by the attenuated dent map (paper §3.1). Every vertex at
// grid coordinates (x, y) and depth z below the collision plane gets p += a(z)·Δ(x, y), Δ the
// dent map sampled bilinearly and zero off the grid, a the falloff. GPU twin of
// src/cpu/displace.rs (`displace`, `attenuation`) and src/cpu/sample.rs (`bilinear`,
// `near_grid`); the statements below follow those functions line by line.
//
// Bindings (group 0):
//   0 params     array<DisplaceParams>, read: the dents of this dispatch (one "layer", see below)
//   1 cells      array<vec4<f32>>, read: dent maps [Δx, Δy, Δz, height] per cell, world units,
//                row-major [row][col] per dent, dent k's map at params[k].cell_offset
//   2 table      array<f32>, read: falloff tables (FALLOFF_TABLE), dent k's at
//                params[k].table_offset, params[k].table_len entries
//   3 positions  array<vec4<f32>>, read_write: the resident vertex buffer, xyz = world position,
//                w = "moved" flag: set to 1.0 when this batch changed the vertex, otherwise left as
//                it was (the host clears it with `clear_moved` before a batch). Dent k's target
//                is positions[params[k].vertex_offset ..][.. params[k].vertex_count].
//
// Dispatch geometry: `main` runs one invocation per target vertex, x = vertex index within the
// dent's target, y = dent index of the layer; dispatch = [ceil(max vertex_count / 64), dents in
// the layer, 1]. Invocations past their dent's vertex_count return at once.
// Order: all dents of one dispatch run concurrently, so a dispatch ("layer") must hold at most
// one dent per target (no two dents of a layer may touch the same vertex). The host
// (src/gpu/displace.rs, `layers`) puts the k-th dent on a target in layer k, in submission
// order, and records one dispatch per layer, each in its own compute pass; wgpu orders passes
// that write the same storage buffer, so dents on one target apply in submission order exactly
// as sequential calls of the CPU twin do.
//
// `clear_moved` runs one invocation per element of `positions` (x = vertex index in the whole
// buffer, y = 0; dispatch = [ceil(arrayLength / 64), 1, 1]) and sets every w to 0.
//
// Host constants matched: DisplaceParams and the FALLOFF_* codes of shaders/shared/layout.wgsl
// (src/cpu/layout.rs, `mod falloff`: NONE, LOGISTIC, LINEAR, TABLE, TABLE_DEPTH);
// WORKGROUP = displace::WORKGROUP in src/gpu/displace.rs.

const WORKGROUP: u32 = 64u;

@group(0) @binding(0) var<storage, read> params: array<DisplaceParams>;
@group(0) @binding(1) var<storage, read> cells: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> table: array<f32>;
@group(0) @binding(3) var<storage, read_write> positions: array<vec4<f32>>;

// One cell of dent `k`'s map, zero outside the grid (sample.rs `bilinear`, closure `at`).
fn at(k: u32, i: i32, j: i32) -> vec4<f32> {
    let n = i32(params[k].grid.res);
    if i >= 0 && i < n && j >= 0 && j < n {
        return cells[params[k].cell_offset + u32(j * n + i)];
    }
    return vec4<f32>(0.0);
}

// sample.rs `bilinear`: the map at continuous index coordinates (x = column, y = row; integers
// are cell centres); the caller has checked `near_grid`, so the indices below are in i32 range.
fn bilinear(k: u32, x: f32, y: f32) -> vec4<f32> {
    let b = bilinear_at(x, y);
    let top = at(k, b.i0, b.j0) * (1.0 - b.fx) + at(k, b.i0 + 1, b.j0) * b.fx;
    let bottom = at(k, b.i0, b.j0 + 1) * (1.0 - b.fx) + at(k, b.i0 + 1, b.j0 + 1) * b.fx;
    return top * (1.0 - b.fy) + bottom * b.fy;
}

// displace.rs `attenuation`: a(z) for depth z below the plane and dent distance d.
fn attenuation(k: u32, z: f32, d: f32) -> f32 {
    if z <= 0.0 {
        return 1.0;
    }
    let p = params[k];
    switch p.falloff {
        case FALLOFF_LOGISTIC: {
            return 2.0 / (1.0 + exp(z / d));
        }
        case FALLOFF_LINEAR: {
            return max(1.0 - z / (p.falloff_scale * d), 0.0);
        }
        case FALLOFF_TABLE: {
            let last = f32(p.table_len - 1u);
            let t = min(z / (FALLOFF_TABLE_DEPTH * d) * last, last);
            let i = min(u32(t), p.table_len - 2u);
            let f = t - f32(i);
            return table[p.table_offset + i] * (1.0 - f) + table[p.table_offset + i + 1u] * f;
        }
        default: {
            return 1.0;
        }
    }
}

@compute @workgroup_size(WORKGROUP, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.y;
    if k >= arrayLength(&params) || id.x >= params[k].vertex_count {
        return;
    }
    let grid = params[k].grid;
    let origin = grid.origin;
    let inv_h = 1.0 / grid.cell_size;
    let axis_x = grid.axis_x * inv_h;
    let axis_y = grid.axis_y * inv_h;
    let axis_z = grid.axis_z;
    let shift = 0.5 * f32(grid.res) - 0.5;
    let d = params[k].dent_distance;

    let v = params[k].vertex_offset + id.x;
    let p = positions[v].xyz;
    let r = p - origin;
    // Dot products written out in glam's order, (a.x·b.x + a.y·b.y) + a.z·b.z.
    let x = (r.x * axis_x.x + r.y * axis_x.y + r.z * axis_x.z) + shift;
    let y = (r.x * axis_y.x + r.y * axis_y.y + r.z * axis_y.z) + shift;
    if !near_grid(grid.res, x, y) {
        return;
    }
    let delta = bilinear(k, x, y).xyz;
    if all(delta == vec3<f32>(0.0)) {
        return;
    }
    let a = attenuation(k, r.x * axis_z.x + r.y * axis_z.y + r.z * axis_z.z, d);
    let moved = p + a * delta;
    if any(moved != p) {
        positions[v] = vec4<f32>(moved, 1.0);
    }
}

@compute @workgroup_size(WORKGROUP, 1, 1)
fn clear_moved(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < arrayLength(&positions) {
        positions[id.x].w = 0.0;
    }
}
