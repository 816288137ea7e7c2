// heat: explicit heat smoothing of the broadened envelope (paper §3.2), GPU twin of
// src/cpu/heat.rs. One heat step is E ← E + α·ΔE (5-point Laplacian, zero outside the grid;
// with clamping E ← max(E, E + α·ΔE)). `step` takes one step of every cell (the CPU `heat_step`)
// or copies; `fused_steps` takes FUSED_STEPS steps of one tile in workgroup memory. The host
// strings the entry points together into the whole `heat`: k₁ plain steps (fused, FUSED_STEPS a
// dispatch), `clear_peak` + `reduce_peak` + `rescale` (each dent's peak becomes its dent
// distance d; all-zero grids stay zero), k₂ clamped steps (fused), and one final copy when the
// dispatch count is odd, so the result always ends in `grid_a`. Both entry points compute every
// step with the same arithmetic (`heat_update`), so fusing changes no bit of the result.
//
// Bindings (group 0), the same for every entry point:
//   0 params:    array<HeatParams>  read        per dent: res, rate α, clamped, cell_offset
//   1 dents:     array<HeatDent>    read_write  per dent: d, k₁, k₂, peak slot (atomic f32 bits)
//   2 current:   array<f32>         read_write  the grids a pass reads (row-major, at cell_offset)
//   3 next:      array<f32>         read_write  the grids a step writes, same layout
//   The host binds the caller's grid and scratch buffers as (current, next) or (next, current)
//   per pass, following HeatPass.source, so the shader never branches on which buffer is which.
//   4 pass_info: HeatPass           uniform     what this dispatch does; the host copies one
//                                               entry of its pass table here before each dispatch
//
// Dispatch geometry: `step`: one invocation per grid cell, x = column, y = row, z = dent index
// of the batch; workgroups [ceil(max res / STEP_WORKGROUP), max res, batch] (no division per
// cell). `fused_steps`: one workgroup per output tile of HeatPass.tile² cells (tile ≤
// MAX_TILE), x = tile column, y = tile row, z = dent; workgroups [ceil(max res / tile),
// ceil(max res / tile), batch]; its WORKGROUP invocations stride over the tile and its halo.
// `reduce_peak`, `rescale`: one invocation per grid cell, x = cell index within the dent
// (row-major, row · res + col), y = dent index; workgroups [ceil(max res² / WORKGROUP), batch,
// 1]. `clear_peak`: one invocation per dent, workgroups [1, batch, 1].
//
// Host constants it must match (src/gpu/heat.rs): WORKGROUP = 256, STEP_WORKGROUP = 64,
// FUSED_STEPS = 4, MAX_TILE = 32, the PHASE_* codes, and the layouts of HeatDent (16 bytes) and
// HeatPass (32 bytes), 4-byte fields in this order.

const WORKGROUP: u32 = 256u;
const STEP_WORKGROUP: u32 = 64u;
// Steps one `fused_steps` dispatch takes (even, so its result ends in the region's first copy).
const FUSED_STEPS: u32 = 4u;
// Largest output tile side of `fused_steps`, cells.
const MAX_TILE: u32 = 32u;
// A tile and its halo (FUSED_STEPS cells each side), the region's row pitch in workgroup memory.
const REGION: u32 = MAX_TILE + 2u * FUSED_STEPS;
const REGION_CELLS: u32 = REGION * REGION;

// HeatPass.phase: which steps a dispatch takes.
// `fused_steps` pass `index` of the k₁ plain steps: steps index·FUSED_STEPS onwards, each by the
// dents whose heat_iters it is below (the others copy).
const PHASE_PLAIN: u32 = 0u;
// The same for the k₂ clamped steps and clamp_iters.
const PHASE_CLAMPED: u32 = 1u;
// `step`: one step of every dent, clamped as HeatParams.clamped says (the CPU `heat_step`).
const PHASE_SINGLE: u32 = 2u;
// `step`: every dent copies its grid to the other buffer.
const PHASE_COPY: u32 = 3u;

struct HeatDent {
    dent_distance: f32,
    heat_iters: u32,
    clamp_iters: u32,
    // Bits of the largest positive value of the grid (0 when none): non-negative f32s order like
    // their bit patterns, so an integer atomicMax is a float max.
    peak_bits: atomic<u32>,
}

struct HeatPass {
    phase: u32,
    // Fused pass number within the phase.
    index: u32,
    // Which buffer holds the current grids: 0 = grid_a (steps write grid_b), 1 = grid_b.
    source: u32,
    // `fused_steps`: output tile side, cells (1 ..= MAX_TILE); unused by the other entries.
    tile: u32,
    // `fused_steps`: steps this pass takes at most (≤ FUSED_STEPS: the batch's count less the
    // steps of the phase's earlier passes), so no dent steps past the batch's count.
    steps: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<storage, read> params: array<HeatParams>;
@group(0) @binding(1) var<storage, read_write> dents: array<HeatDent>;
@group(0) @binding(2) var<storage, read_write> current: array<f32>;
@group(0) @binding(3) var<storage, read_write> next: array<f32>;
@group(0) @binding(4) var<uniform> pass_info: HeatPass;

var<workgroup> partial_max: array<u32, WORKGROUP>;
// `fused_steps`: two copies of a tile and its halo (ping-pong between steps), cell (r, c) of a
// copy at r · REGION + c; the second copy starts at REGION_CELLS.
var<workgroup> region: array<f32, 2u * REGION_CELLS>;

// Cell `k` of the current grids.
fn load(k: u32) -> f32 {
    return current[k];
}

// Writes cell `k` of the other buffer (the next current grids).
fn store_next(k: u32, value: f32) {
    next[k] = value;
}

// Writes cell `k` of the current grids in place.
fn store_current(k: u32, value: f32) {
    current[k] = value;
}

// One step of `heat_step` for the cell (row, col) of an n × n grid, value s, from its four
// neighbours (values outside the grid are not read: each sum adds only the neighbours inside,
// in the order the CPU twin adds them).
fn heat_update(s: f32, up: f32, down: f32, left: f32, right: f32, row: u32, col: u32, n: u32, alpha: f32,
               clamped: bool) -> f32 {
    // up + down (rows outside the grid read as zero).
    var vertical = 0.0;
    if row > 0u && row + 1u < n {
        vertical = up + down;
    } else if row > 0u {
        vertical = up;
    } else if row + 1u < n {
        vertical = down;
    }
    // left + right (columns outside the grid read as zero).
    var horizontal = 0.0;
    if n == 1u {
        horizontal = 0.0;
    } else if col == 0u {
        horizontal = right;
    } else if col == n - 1u {
        horizontal = left;
    } else {
        horizontal = left + right;
    }
    // centre + α·((up + down) + (left + right) − 4·centre).
    let next = s + alpha * ((vertical + horizontal) - 4.0 * s);
    if clamped {
        return max(next, s);
    }
    return next;
}

// One step of `heat_step` for the cell (row, col) at flat index k of the current grids.
fn step_cell(k: u32, row: u32, col: u32, n: u32, alpha: f32, clamped: bool) -> f32 {
    var up = 0.0;
    var down = 0.0;
    var left = 0.0;
    var right = 0.0;
    if row > 0u {
        up = load(k - n);
    }
    if row + 1u < n {
        down = load(k + n);
    }
    if col > 0u {
        left = load(k - 1u);
    }
    if col + 1u < n {
        right = load(k + 1u);
    }
    return heat_update(load(k), up, down, left, right, row, col, n, alpha, clamped);
}

// Whether (row, col) lies on an n × n grid.
fn on_grid(row: i32, col: i32, n: u32) -> bool {
    return row >= 0 && col >= 0 && row < i32(n) && col < i32(n);
}

// One step (PHASE_SINGLE) or copy (PHASE_COPY) of every cell, current grids → other buffer.
// Indexed by (col, row, dent) so no invocation divides: x = column, y = row, z = dent.
@compute @workgroup_size(STEP_WORKGROUP, 1, 1)
fn step(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = params[id.z];
    let n = p.res;
    if id.x >= n || id.y >= n {
        return;
    }
    let k = p.cell_offset + id.y * n + id.x;
    if pass_info.phase == PHASE_SINGLE {
        store_next(k, step_cell(k, id.y, id.x, n, p.rate, p.clamped == 1u));
    } else {
        store_next(k, load(k));
    }
}

// FUSED_STEPS steps (PHASE_PLAIN or PHASE_CLAMPED pass `index`) of one tile, current grids →
// other buffer. The workgroup loads its tile and a halo of FUSED_STEPS cells into `region`
// (zero off the grid), then each step updates the cells at least one cell further in than the
// last (their neighbours are then still exact), so after the last step the tile is exact; off
// the grid cells stay zero, as the CPU twin reads them. A dent past its step count copies.
// Every barrier is reached in uniform control flow: the loops around them run FUSED_STEPS times.
@compute @workgroup_size(WORKGROUP, 1, 1)
fn fused_steps(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let p = params[group.z];
    let n = p.res;
    let tile = pass_info.tile;
    let side = tile + 2u * FUSED_STEPS;
    // Region cell (r, c) is grid cell (top + r, first + c); the halo may start off the grid.
    let top = i32(group.y * tile) - i32(FUSED_STEPS);
    let first = i32(group.x * tile) - i32(FUSED_STEPS);
    var limit = dents[group.z].clamp_iters;
    if pass_info.phase == PHASE_PLAIN {
        limit = dents[group.z].heat_iters;
    }
    let taken = pass_info.index * FUSED_STEPS;
    let steps = min(limit - min(limit, taken), pass_info.steps);
    let clamped = pass_info.phase == PHASE_CLAMPED;
    for (var i = lane; i < side * side; i += WORKGROUP) {
        let r = i / side;
        let c = i % side;
        var value = 0.0;
        if on_grid(top + i32(r), first + i32(c), n) {
            value = load(p.cell_offset + u32(top + i32(r)) * n + u32(first + i32(c)));
        }
        region[r * REGION + c] = value;
    }
    workgroupBarrier();
    for (var s = 0u; s < FUSED_STEPS; s += 1u) {
        let src = (s % 2u) * REGION_CELLS;
        let dst = REGION_CELLS - src;
        let inner = side - 2u * (s + 1u);
        for (var i = lane; i < inner * inner; i += WORKGROUP) {
            let r = s + 1u + i / inner;
            let c = s + 1u + i % inner;
            let row = top + i32(r);
            let col = first + i32(c);
            let at = src + r * REGION + c;
            var value = 0.0;
            if on_grid(row, col, n) {
                value = region[at];
                if s < steps {
                    let up = region[at - REGION];
                    let down = region[at + REGION];
                    let left = region[at - 1u];
                    let right = region[at + 1u];
                    value = heat_update(value, up, down, left, right, u32(row), u32(col), n, p.rate, clamped);
                }
            }
            region[dst + r * REGION + c] = value;
        }
        workgroupBarrier();
    }
    // FUSED_STEPS is even: the last step wrote the first copy.
    for (var i = lane; i < tile * tile; i += WORKGROUP) {
        let r = FUSED_STEPS + i / tile;
        let c = FUSED_STEPS + i % tile;
        let row = top + i32(r);
        let col = first + i32(c);
        if on_grid(row, col, n) {
            store_next(p.cell_offset + u32(row) * n + u32(col), region[r * REGION + c]);
        }
    }
}

// Resets each dent's peak slot before `reduce_peak`.
@compute @workgroup_size(1, 1, 1)
fn clear_peak(@builtin(global_invocation_id) id: vec3<u32>) {
    atomicStore(&dents[id.y].peak_bits, 0u);
}

// peak = max(0, max of the current grid): a max over each workgroup in shared memory, then one
// atomicMax per workgroup into the dent's slot. NaN and values ≤ 0 count as 0, as in the CPU
// fold `max(0, v₀, v₁, …)`.
@compute @workgroup_size(WORKGROUP, 1, 1)
fn reduce_peak(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let p = params[id.y];
    var bits = 0u;
    if id.x < p.res * p.res {
        let v = load(p.cell_offset + id.x);
        if v > 0.0 {
            bits = bitcast<u32>(v);
        }
    }
    partial_max[lane] = bits;
    workgroupBarrier();
    for (var width = WORKGROUP / 2u; width > 0u; width = width / 2u) {
        if lane < width {
            partial_max[lane] = max(partial_max[lane], partial_max[lane + width]);
        }
        workgroupBarrier();
    }
    if lane == 0u && partial_max[0] > 0u {
        atomicMax(&dents[id.y].peak_bits, partial_max[0]);
    }
}

// Current grid ← current grid · (d / peak), in place; untouched when the peak is 0.
@compute @workgroup_size(WORKGROUP, 1, 1)
fn rescale(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = params[id.y];
    if id.x >= p.res * p.res {
        return;
    }
    let peak_bits = atomicLoad(&dents[id.y].peak_bits);
    if peak_bits == 0u {
        return;
    }
    let scale = dents[id.y].dent_distance / bitcast<f32>(peak_bits);
    let k = p.cell_offset + id.x;
    store_current(k, load(k) * scale);
}
