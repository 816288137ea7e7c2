// heat: explicit heat smoothing of the broadened envelope (paper §3.2), GPU twin of
// src/cpu/heat.rs. `step` is one `heat_step` (E ← E + α·ΔE, 5-point Laplacian, zero outside the
// grid; with clamping E ← max(E, E + α·ΔE)); the host strings the entry points together into the
// whole `heat`: k₁ plain steps, `clear_peak` + `reduce_peak` + `rescale` (each dent's peak
// becomes its dent distance d; all-zero grids stay zero), k₂ clamped steps, and one final copy
// when the step count is odd, so the result always ends in `grid_a`.
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
// cell). `reduce_peak`, `rescale`: one invocation per grid cell, x = cell index within the dent
// (row-major, row · res + col), y = dent index; workgroups [ceil(max res² / WORKGROUP), batch,
// 1]. `clear_peak`: one invocation per dent, workgroups [1, batch, 1].
//
// Host constants it must match (src/gpu/heat.rs): WORKGROUP = 256, STEP_WORKGROUP = 64, the PHASE_* codes, and the
// layouts of HeatDent and HeatPass (16 bytes each, four 4-byte fields in this order).

const WORKGROUP: u32 = 256u;
const STEP_WORKGROUP: u32 = 64u;

// HeatPass.phase: which steps a `step` dispatch takes.
// Step `index` of the k₁ plain ones: dents with index < heat_iters step, the others copy.
const PHASE_PLAIN: u32 = 0u;
// Step `index` of the k₂ clamped ones: dents with index < clamp_iters step, the others copy.
const PHASE_CLAMPED: u32 = 1u;
// One step of every dent, clamped as HeatParams.clamped says (the CPU `heat_step`).
const PHASE_SINGLE: u32 = 2u;
// Every dent copies its grid to the other buffer.
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
    // Step number within the phase.
    index: u32,
    // Which buffer holds the current grids: 0 = grid_a (steps write grid_b), 1 = grid_b.
    source: u32,
    _pad: u32,
}

@group(0) @binding(0) var<storage, read> params: array<HeatParams>;
@group(0) @binding(1) var<storage, read_write> dents: array<HeatDent>;
@group(0) @binding(2) var<storage, read_write> current: array<f32>;
@group(0) @binding(3) var<storage, read_write> next: array<f32>;
@group(0) @binding(4) var<uniform> pass_info: HeatPass;

var<workgroup> partial_max: array<u32, WORKGROUP>;

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

// One step of `heat_step` for the cell (row, col) at flat index k of a res × res grid.
fn step_cell(k: u32, row: u32, col: u32, n: u32, alpha: f32, clamped: bool) -> f32 {
    let s = load(k);
    // up + down (rows outside the grid read as zero).
    var vertical = 0.0;
    if row > 0u && row + 1u < n {
        vertical = load(k - n) + load(k + n);
    } else if row > 0u {
        vertical = load(k - n);
    } else if row + 1u < n {
        vertical = load(k + n);
    }
    // left + right (columns outside the grid read as zero).
    var horizontal = 0.0;
    if n == 1u {
        horizontal = 0.0;
    } else if col == 0u {
        horizontal = load(k + 1u);
    } else if col == n - 1u {
        horizontal = load(k - 1u);
    } else {
        horizontal = load(k - 1u) + load(k + 1u);
    }
    // centre + α·((up + down) + (left + right) − 4·centre).
    let next = s + alpha * ((vertical + horizontal) - 4.0 * s);
    if clamped {
        return max(next, s);
    }
    return next;
}

// One step (or copy) of every cell, current grids → other buffer. Indexed by (col, row, dent)
// so no invocation divides: x = column, y = row, z = dent.
@compute @workgroup_size(STEP_WORKGROUP, 1, 1)
fn step(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = params[id.z];
    let n = p.res;
    if id.x >= n || id.y >= n {
        return;
    }
    let k = p.cell_offset + id.y * n + id.x;
    var stepping = false;
    var clamped = false;
    switch pass_info.phase {
        case PHASE_PLAIN: {
            stepping = pass_info.index < dents[id.z].heat_iters;
        }
        case PHASE_CLAMPED: {
            stepping = pass_info.index < dents[id.z].clamp_iters;
            clamped = true;
        }
        case PHASE_SINGLE: {
            stepping = true;
            clamped = p.clamped == 1u;
        }
        default: {}
    }
    if stepping {
        store_next(k, step_cell(k, id.y, id.x, n, p.rate, clamped));
    } else {
        store_next(k, load(k));
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
