// displace: moves a target's vertices by the attenuated dent map (paper §3.1). Every vertex at
// grid coordinates (x, y) and depth z below the collision plane gets p += a(z)·Δ(x, y), Δ the
// dent map sampled bilinearly and zero off the grid, a the falloff. GPU twin of
// src/cpu/displace.rs (`displace`, `attenuation`) and src/cpu/sample.rs (`bilinear`,
// `near_grid`); the statements below follow those functions line by line.
//
// Bindings (group 0):
//   0 params     array<DisplaceParams>, read: the dents of this dispatch, grouped by target (see
//                `runs`), each target's in submission order
//   1 cells      array<vec4<f32>>, read: dent maps [Δx, Δy, Δz, height] per cell, world units,
//                row-major [row][col] per dent, dent k's map at params[k].cell_offset
//   2 table      array<f32>, read: falloff tables (FALLOFF_TABLE), dent k's at
//                params[k].table_offset, params[k].table_len entries
//   3 positions  array<vec4<f32>>, read_write: the resident vertex buffer, xyz = world position,
//                w = "moved" flag: set to 1.0 when this batch changed the vertex, otherwise left as
//                it was (the host clears it with `clear_moved` before a batch). Dent k's target
//                is positions[params[k].vertex_offset ..][.. params[k].vertex_count].
//   4 runs       array<vec4<u32>, MAX_RUNS>, uniform: one per target of this dispatch, (first
//                dent in `params`, its number of dents, vertex_offset, vertex_count)
//
// Dispatch geometry: `main` runs one invocation per target vertex, x = vertex index within the
// target, y = run (target) index; dispatch = [ceil(max vertex_count / 64), runs, 1].
// Invocations past their target's vertex_count return at once.
// Order: each invocation applies its target's dents to its vertex one after the other, in
// submission order, holding the position in registers: a vertex's displacement depends only on
// its own position, so this is exactly what sequential calls of the CPU twin do, in one dispatch
// however many dents a target takes. The host (src/gpu/displace.rs, `runs`) groups the dents by
// target and cuts batches of more than MAX_RUNS targets into several dispatches.
//
// `clear_moved` runs one invocation per element of `positions` (x = vertex index in the whole
// buffer, y = 0; dispatch = [ceil(arrayLength / 64), 1, 1]) and sets every w to 0.
//
// Host constants matched: DisplaceParams and the FALLOFF_* codes of shaders/shared/layout.wgsl
// (src/cpu/layout.rs, `mod falloff`: NONE, LOGISTIC, LINEAR, TABLE, TABLE_DEPTH);
// WORKGROUP and MAX_RUNS = displace::{WORKGROUP, MAX_RUNS} in src/gpu/displace.rs.

const WORKGROUP: u32 = 64u;
// Targets one dispatch serves: 16 KiB of `runs`.
const MAX_RUNS: u32 = 1024u;

@group(0) @binding(0) var<storage, read> params: array<DisplaceParams>;
@group(0) @binding(1) var<storage, read> cells: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> table: array<f32>;
@group(0) @binding(3) var<storage, read_write> positions: array<vec4<f32>>;
@group(0) @binding(4) var<uniform> runs: array<vec4<u32>, MAX_RUNS>;

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

// Vertex position p after dent k (p itself when the dent does not reach it).
fn displaced(k: u32, p: vec3<f32>) -> vec3<f32> {
    let grid = params[k].grid;
    let origin = grid.origin;
    let inv_h = 1.0 / grid.cell_size;
    let axis_x = grid.axis_x * inv_h;
    let axis_y = grid.axis_y * inv_h;
    let axis_z = grid.axis_z;
    let shift = 0.5 * f32(grid.res) - 0.5;
    let d = params[k].dent_distance;

    let r = p - origin;
    // Dot products written out in glam's order, (a.x·b.x + a.y·b.y) + a.z·b.z.
    let x = (r.x * axis_x.x + r.y * axis_x.y + r.z * axis_x.z) + shift;
    let y = (r.x * axis_y.x + r.y * axis_y.y + r.z * axis_y.z) + shift;
    if !near_grid(grid.res, x, y) {
        return p;
    }
    let delta = bilinear(k, x, y).xyz;
    if all(delta == vec3<f32>(0.0)) {
        return p;
    }
    let a = attenuation(k, r.x * axis_z.x + r.y * axis_z.y + r.z * axis_z.z, d);
    return p + a * delta;
}

@compute @workgroup_size(WORKGROUP, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let run = runs[id.y];
    if id.x >= run.w {
        return;
    }
    let v = run.z + id.x;
    var p = positions[v].xyz;
    var moved = false;
    for (var k = run.x; k < run.x + run.y; k += 1u) {
        let next = displaced(k, p);
        if any(next != p) {
            p = next;
            moved = true;
        }
    }
    if moved {
        positions[v] = vec4<f32>(p, 1.0);
    }
}

@compute @workgroup_size(WORKGROUP, 1, 1)
fn clear_moved(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < arrayLength(&positions) {
        positions[id.x].w = 0.0;
    }
}
