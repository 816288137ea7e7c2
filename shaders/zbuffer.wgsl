// zbuffer: the Z-buffer profile P = max(0, d + max s) of each dent's projectile (paper §3.2,
// ARCHITECTURE.md §4). GPU twin of `cpu::zbuffer` (src/cpu/zbuffer.rs), whose module doc explains the
// three kinds of samples (exact centre samples, edge walks, the tip); the functions below mirror
// it line by line, with the same f32 operations in the same order.
//
// Bindings (group 0), as src/gpu/zbuffer.rs creates them:
//   0  params     array<ZbufferParams>, read: one per dent of the batch (shared/layout.wgsl).
//   1  positions  array<f32>, read: x, y, z of every vertex of the batch, world units.
//   2  faces      array<u32>, read: three vertex indices per triangle, already offset by the host
//                 into `positions`; an index past the end culls its triangle (the host writes
//                 0xffffffff for an index that is out of range within its dent).
//   3  work       array<atomic<u32>>, read_write, zeroed by the host before the first pass:
//                 words [cell_offset, cell_offset + res²) of each dent hold its profile (row-major,
//                 as f32 bits once `resolve` has run), and the LAST `batch` words of the buffer
//                 hold one tip height per dent (dent b at arrayLength − batch + b, f32 bits,
//                 with batch = num_workgroups.y).
//
// One atomic word per cell instead of the CPU's two buffers (centres, edges): every height is
// ≥ 0, so its f32 bits are < 2³¹ and order like the heights; centre samples are max-merged with
// bit 31 (CENTRE_FLAG) set, edge samples without it. A flagged word beats every unflagged one,
// so after all samples a cell holds its highest centre sample if it has any, and otherwise its
// highest edge sample (0 if none): exactly the CPU's combine ("cells with no centre sample take
// the edge value"), with no ordering between the two kinds of samples.
//
// Entry points, dispatched in this order (`centres` and `edges` may swap), each as
// [ceil(max_items / workgroup), batch, 1] with global_invocation_id.y = dent index of the batch
// (workgroup size y = 1), except `centres`, whose z is a tile index:
//   centres   one invocation per triangle and tile: x = face index within the dent, z = tile
//             (row-major over ceil(res / TILE)² tiles of TILE × TILE cells; dispatch z =
//             ceil(max_res / TILE)²): the centre samples (flagged) of the triangle's cells in that
//             tile. Tiling bounds each invocation's loop to TILE² cells whatever the triangle's
//             size: Mesa's llvmpipe/lavapipe silently ends an invocation's loops after 65,535
//             iterations in all, and on any GPU it spreads a large triangle over many threads.
//             Barycentrics are still stepped from the triangle's first cell, as on the CPU, so
//             tiling changes no value.
//   edges     one invocation per triangle: the edge walks of its three edges (at most
//             3·(res + 1) samples), and its corners into the dent's tip height (atomicMax).
//   resolve   one invocation per cell (x = row·res + col within the dent): clears CENTRE_FLAG,
//             leaving the combined profile as plain f32 bits.
//   tip_mark  one invocation per triangle: every corner as high as the dent's tip height marks
//             its cell (max-merged) with its height.
//
// Host constants to match: FACE_WORKGROUP, CELL_WORKGROUP and TILE (src/gpu/zbuffer.rs);
// INSIDE_EPS and DEGENERATE_EPS (src/cpu/zbuffer.rs).

const FACE_WORKGROUP: u32 = 64u;
const CELL_WORKGROUP: u32 = 256u;
/// Side of a `centres` tile, cells: TILE² + 2·TILE loop iterations stay under llvmpipe's 65,535.
const TILE: u32 = 240u;

/// Barycentric tolerance of the centre test (cpu::zbuffer INSIDE_EPS).
const INSIDE_EPS: f32 = 1e-5;
/// Relative doubled area below which a triangle is a segment (cpu::zbuffer DEGENERATE_EPS).
const DEGENERATE_EPS: f32 = 1e-6;
/// Bit 31 of a work word: the word holds a centre sample.
const CENTRE_FLAG: u32 = 0x80000000u;
/// "Not on the grid", returned by `nearest`.
const NONE: u32 = 0xffffffffu;

@group(0) @binding(0) var<storage, read> params: array<ZbufferParams>;
@group(0) @binding(1) var<storage, read> positions: array<f32>;
@group(0) @binding(2) var<storage, read> faces: array<u32>;
@group(0) @binding(3) var<storage, read_write> work: array<atomic<u32>>;

/// World → grid-index space (cpu::zbuffer Frame).
struct Frame {
    origin: vec3<f32>,
    /// axis_x / h, 1/world unit.
    axis_x: vec3<f32>,
    /// axis_y / h, 1/world unit.
    axis_y: vec3<f32>,
    axis_z: vec3<f32>,
    /// res/2 − ½: grid index of the grid centre line.
    shift: f32,
    /// Dent distance, world units.
    d: f32,
}

/// The profile being written (cpu::zbuffer Target): one dent's cells in `work`.
struct Target {
    /// First word of the dent's profile.
    base: u32,
    /// Cells per side.
    res: u32,
    /// res − 1.
    last: u32,
    /// Dent distance, world units: the cap on heights.
    d: f32,
}

/// The grid indices i with lo ≤ i ≤ hi (cpu::zbuffer Target::span); `ok` false if none.
struct Span {
    first: u32,
    end: u32,
    ok: bool,
}

/// A triangle's corners in grid-index space; `ok` false if culled.
struct Triangle {
    v: array<vec3<f32>, 3>,
    ok: bool,
}

fn is_valid(p: ZbufferParams) -> bool {
    return p.grid.res > 0u && p.grid.cell_size > 0.0 && p.dent_distance > 0.0;
}

fn frame_of(p: ZbufferParams) -> Frame {
    let g = p.grid;
    return Frame(g.origin, g.axis_x / g.cell_size, g.axis_y / g.cell_size, g.axis_z, 0.5 * f32(g.res) - 0.5,
        p.dent_distance);
}

fn target_of(p: ZbufferParams) -> Target {
    return Target(p.cell_offset, p.grid.res, p.grid.res - 1u, p.dent_distance);
}

/// glam's Vec3::dot, in its order.
fn dot3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

/// (column, row, height): cell centres at integer column and row; height d + s, world units.
fn to_grid(f: Frame, p: vec3<f32>) -> vec3<f32> {
    let r = p - f.origin;
    return vec3<f32>(dot3(r, f.axis_x) + f.shift, dot3(r, f.axis_y) + f.shift, dot3(r, f.axis_z) + f.d);
}

fn is_finite(x: f32) -> bool {
    // By the bits: the compiler may assume floats are finite and fold `x == x`-style tests.
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

/// Face `face` (index into the batch) in grid-index space, culled as cpu::zbuffer's
/// `triangles()` culls: a face or corner index out of range, no corner above z = 0, or a corner
/// not finite.
fn load_triangle(f: Frame, face: u32) -> Triangle {
    var t: Triangle;
    t.ok = true;
    if face >= arrayLength(&faces) / 3u {
        t.ok = false;
        return t;
    }
    let vertices = arrayLength(&positions) / 3u;
    for (var k = 0u; k < 3u; k++) {
        let index = faces[3u * face + k];
        if index >= vertices {
            t.ok = false;
            return t;
        }
        let p = vec3<f32>(positions[3u * index], positions[3u * index + 1u], positions[3u * index + 2u]);
        t.v[k] = to_grid(f, p);
    }
    let reaches = max(max(t.v[0].z, t.v[1].z), t.v[2].z) > 0.0;
    var finite = true;
    for (var k = 0u; k < 3u; k++) {
        finite = finite && is_finite(t.v[k].x) && is_finite(t.v[k].y) && is_finite(t.v[k].z);
    }
    t.ok = reaches && finite;
    return t;
}

/// Triangle `face` (index within its dent) of the dent with parameters `p`, not `ok` when it is
/// past the dent's triangles, the dent's grid is unusable, or `load_triangle` culls it.
fn dent_triangle(p: ZbufferParams, face: u32) -> Triangle {
    if face >= p.face_count || !is_valid(p) {
        var none: Triangle;
        none.ok = false;
        return none;
    }
    return load_triangle(frame_of(p), p.face_offset + face);
}

/// Max-merges height z (world units) into cell (row, col), both in 0..=last, with `flag` (0 or
/// CENTRE_FLAG) on its bits; heights not above 0 (or NaN) are ignored, heights are capped at d.
fn write(t: Target, row: u32, col: u32, z: f32, flag: u32) {
    if z > 0.0 {
        atomicMax(&work[t.base + row * t.res + col], bitcast<u32>(min(z, t.d)) | flag);
    }
}

/// Index of the cell whose span [i − ½, i + ½) holds grid coordinate x, or NONE.
fn nearest(t: Target, x: f32) -> u32 {
    // x + ½ > 0, so truncation is floor; `min` guards the rounding of x + ½ up to res.
    if x >= -0.5 && x < f32(t.last) + 0.5 {
        return min(u32(x + 0.5), t.last);
    }
    return NONE;
}

/// The grid indices i with lo ≤ i ≤ hi, if any.
fn span(t: Target, lo_in: f32, hi_in: f32) -> Span {
    let lo = max(lo_in, 0.0);
    let hi = min(hi_in, f32(t.last));
    if lo > hi {
        return Span(0u, 0u, false);
    }
    // ceil and floor of non-negative values, by truncation.
    let first = u32(lo) + select(0u, 1u, f32(u32(lo)) < lo);
    let end = u32(hi);
    return Span(first, end, first <= end);
}

/// Centre samples of one triangle (grid-index space): every centre inside the closed triangle
/// gets the height interpolated there (cpu::zbuffer rasterize_centres), among the cells of the
/// TILE × TILE tile whose first cell is (tile_row, tile_col).
fn rasterize_centres(t: Target, corners: array<vec3<f32>, 3>, tile_row: u32, tile_col: u32) {
    var v = corners;
    // Barycentric coordinate of vertex k: w_k = e_k(p) / area2, with the edge function
    // e_k(p) = (b − a) × (p − a) of the opposite edge a = v[k+1] → b = v[k+2], stepped from the
    // first cell of the clipped bounding box.
    let area2 = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[1].y - v[0].y) * (v[2].x - v[0].x);
    var longest2 = 0.0;
    for (var k = 0u; k < 3u; k++) {
        let e = v[(k + 1u) % 3u] - v[k];
        longest2 = max(longest2, e.x * e.x + e.y * e.y);
    }
    let solid = abs(area2) > DEGENERATE_EPS * longest2;
    if !solid {
        return;
    }
    let lo = min(min(v[0], v[1]), v[2]);
    let hi = max(max(v[0], v[1]), v[2]);
    let cols = span(t, lo.x, hi.x);
    let rows = span(t, lo.y, hi.y);
    if !cols.ok || !rows.ok {
        return;
    }
    // The part of the bounding box in this tile (the GPU's addition).
    let row_first = max(rows.first, tile_row);
    let row_end = min(rows.end, tile_row + TILE - 1u);
    let col_first = max(cols.first, tile_col);
    let col_end = min(cols.end, tile_col + TILE - 1u);
    if row_first > row_end || col_first > col_end {
        return;
    }
    let inv_area2 = 1.0 / area2;
    let x0 = f32(cols.first);
    let y0 = f32(rows.first);
    var w0: vec3<f32>;
    var dw_dx: vec3<f32>;
    var dw_dy: vec3<f32>;
    for (var k = 0u; k < 3u; k++) {
        let a = v[(k + 1u) % 3u];
        let b = v[(k + 2u) % 3u];
        w0[k] = ((b.x - a.x) * (y0 - a.y) - (b.y - a.y) * (x0 - a.x)) * inv_area2;
        dw_dx[k] = -(b.y - a.y) * inv_area2;
        dw_dy[k] = (b.x - a.x) * inv_area2;
    }
    for (var row = row_first; row <= row_end; row++) {
        let dy = f32(row - rows.first);
        let w_row = w0 + dy * dw_dy;
        var entered = false;
        for (var col = col_first; col <= col_end; col++) {
            let dx = f32(col - cols.first);
            let w = w_row + dx * dw_dx;
            if w[0] >= -INSIDE_EPS && w[1] >= -INSIDE_EPS && w[2] >= -INSIDE_EPS {
                let z = clamp(w[0] * v[0].z + w[1] * v[1].z + w[2] * v[2].z, lo.z, hi.z);
                write(t, row, col, z, CENTRE_FLAG);
                entered = true;
            } else if entered {
                break; // the covered columns of a row are contiguous (each w_k is monotone in dx)
            }
        }
    }
}

/// Edge samples of segment a → b (grid-index space): the cell of a, then one sample per column
/// line (or row line, whichever axis the segment spans more of) it crosses, in the cell nearest
/// that crossing, with the segment's height there (cpu::zbuffer rasterize_edge).
fn rasterize_edge(t: Target, a: vec3<f32>, b: vec3<f32>) {
    let a_row = nearest(t, a.y);
    let a_col = nearest(t, a.x);
    if a_row != NONE && a_col != NONE {
        write(t, a_row, a_col, a.z, 0u);
    }
    // Walk along the dominant axis u; w is the other grid coordinate.
    let along_x = abs(b.x - a.x) >= abs(b.y - a.y);
    let ua = select(a.y, a.x, along_x);
    let wa = select(a.x, a.y, along_x);
    let ub = select(b.y, b.x, along_x);
    let wb = select(b.x, b.y, along_x);
    let du = ub - ua;
    if du == 0.0 {
        return; // a point, or parallel to axis_z: the vertex samples cover it
    }
    let s = span(t, min(ua, ub), max(ua, ub));
    if !s.ok {
        return;
    }
    let inv_du = 1.0 / du;
    for (var u = s.first; u <= s.end; u++) {
        let along = clamp((f32(u) - ua) * inv_du, 0.0, 1.0);
        let w = nearest(t, wa + along * (wb - wa));
        if w != NONE {
            let row = select(u, w, along_x);
            let col = select(w, u, along_x);
            write(t, row, col, a.z + along * (b.z - a.z), 0u);
        }
    }
}

/// Word of dent `dent`'s tip height: the last `batch` words of `work` hold one per dent.
fn tip_slot(dent: u32, batch: u32) -> u32 {
    return arrayLength(&work) - batch + dent;
}

@compute @workgroup_size(FACE_WORKGROUP, 1, 1)
fn centres(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = params[id.y];
    let tiles = (p.grid.res + TILE - 1u) / TILE;
    if id.z >= tiles * tiles {
        return;
    }
    let tri = dent_triangle(p, id.x);
    if !tri.ok {
        return;
    }
    rasterize_centres(target_of(p), tri.v, (id.z / tiles) * TILE, (id.z % tiles) * TILE);
}

@compute @workgroup_size(FACE_WORKGROUP, 1, 1)
fn edges(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let p = params[id.y];
    let tri = dent_triangle(p, id.x);
    if !tri.ok {
        return;
    }
    let t = target_of(p);
    var v = tri.v;
    for (var k = 0u; k < 3u; k++) {
        rasterize_edge(t, v[k], v[(k + 1u) % 3u]);
    }
    // The tip height: max over corners of min(z, d), from 0 (a surviving triangle has z > 0).
    for (var k = 0u; k < 3u; k++) {
        let height = min(v[k].z, t.d);
        if height > 0.0 {
            atomicMax(&work[tip_slot(id.y, groups.y)], bitcast<u32>(height));
        }
    }
}

@compute @workgroup_size(CELL_WORKGROUP, 1, 1)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = params[id.y];
    if id.x >= p.grid.res * p.grid.res {
        return;
    }
    atomicAnd(&work[p.cell_offset + id.x], ~CENTRE_FLAG);
}

@compute @workgroup_size(FACE_WORKGROUP, 1, 1)
fn tip_mark(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let p = params[id.y];
    let tri = dent_triangle(p, id.x);
    if !tri.ok {
        return;
    }
    let t = target_of(p);
    // The tip: the highest corner height, compared exactly as computed in `edges`.
    let tip = bitcast<f32>(atomicLoad(&work[tip_slot(id.y, groups.y)]));
    var v = tri.v;
    for (var k = 0u; k < 3u; k++) {
        let corner = v[k];
        if min(corner.z, t.d) >= tip {
            let row = nearest(t, corner.y);
            let col = nearest(t, corner.x);
            if row != NONE && col != NONE {
                write(t, row, col, corner.z, 0u);
            }
        }
    }
}
