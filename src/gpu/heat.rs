//! GPU twin of [`cpu::heat`] and [`cpu::heat_step`]: `shaders/heat.wgsl` smooths the envelopes
//! of a whole batch of dents, [`FUSED_STEPS`] steps a dispatch over all dents: each workgroup
//! steps one tile (at most `MAX_TILE`² cells) and its halo in workgroup memory, so the grids
//! cross device memory once per four steps instead of once per step.
//!
//! The whole smoothing of one batch is recorded into one command encoder: what each dispatch does
//! (phase, pass number, steps, tile) reaches the shader through a 32-byte uniform that a buffer
//! copy refreshes from a pass table before every dispatch, so the batch needs no round trip to
//! the host between steps. Iteration counts are per dent ([`HeatDent`]); the batch runs as many
//! steps as its largest counts (in passes of up to [`FUSED_STEPS`]), and a dent whose count is
//! exhausted copies its grid through the remaining steps.
//!
//! [`cpu::heat`]: crate::cpu::heat
//! [`cpu::heat_step`]: crate::cpu::heat_step

use bytemuck::{Pod, Zeroable};

use super::{Binding, GpuContext, GpuError, Kernel, buffers, shaders};
use crate::cpu::HeatParams;

/// Invocations per workgroup along x (cells); `WORKGROUP` in `shaders/heat.wgsl`.
pub(crate) const WORKGROUP: u32 = 256;
/// Invocations per workgroup of the `step` entry point (one grid row segment each); keep in
/// sync with `STEP_WORKGROUP` in `shaders/heat.wgsl`.
pub(crate) const STEP_WORKGROUP: u32 = 64;
/// Heat steps one `fused_steps` dispatch takes; `FUSED_STEPS` in `shaders/heat.wgsl`.
pub const FUSED_STEPS: u32 = 4;
/// Largest output tile side of `fused_steps`, cells; `MAX_TILE` in `shaders/heat.wgsl`.
pub(crate) const MAX_TILE: u32 = 32;

/// `HeatPass.phase` codes of `shaders/heat.wgsl`: fused plain steps of the k₁ phase.
const PHASE_PLAIN: u32 = 0;
/// Fused clamped steps of the k₂ phase.
const PHASE_CLAMPED: u32 = 1;
/// One step of every dent, clamped per `HeatParams::clamped`.
const PHASE_SINGLE: u32 = 2;
/// Every dent copies its grid to the other buffer.
const PHASE_COPY: u32 = 3;

/// Bindings of every entry point, in `@binding` order: params, dents, grid_a, grid_b, pass_info.
const BINDINGS: [Binding; 5] =
    [Binding::Read, Binding::ReadWrite, Binding::ReadWrite, Binding::ReadWrite, Binding::Uniform];

/// Per-dent schedule of the whole smoothing, beside its [`HeatParams`]. 16 bytes.
///
/// Keep in sync with `HeatDent` in `shaders/heat.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct HeatDent {
    /// Dent distance d, world units: the dent's peak after the rescale.
    pub dent_distance: f32,
    /// k₁: plain steps before the rescale (at most the batch's [`HeatBatch::heat_iters`]).
    pub heat_iters: u32,
    /// k₂: clamped steps after it (at most the batch's [`HeatBatch::clamp_iters`]).
    pub clamp_iters: u32,
    /// Scratch of the peak reduction (f32 bits of the grid's largest positive value), written by
    /// the kernel; upload 0.
    pub peak_bits: u32,
}

/// What one dispatch does, 32 bytes. Keep in sync with `HeatPass` in `shaders/heat.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
struct HeatPass {
    /// One of the `PHASE_*` codes (read by `step` and `fused_steps`).
    phase: u32,
    /// Fused pass number within the phase.
    index: u32,
    /// Buffer holding the current grids: 0 = `grid`, 1 = `scratch`.
    source: u32,
    /// Output tile side of `fused_steps`, cells (read by `fused_steps` only).
    tile: u32,
    /// Steps a `fused_steps` pass takes at most: the batch's count less the phase's earlier
    /// passes' steps, at most [`FUSED_STEPS`].
    steps: u32,
    _pad: [u32; 3],
}

/// Caller-owned buffers of one batch, in `@binding` order.
#[derive(Debug, Clone, Copy)]
pub struct HeatBuffers<'a> {
    /// `array<HeatParams>`, one per dent (`cell_offset` places the dent in `grid` and
    /// `scratch`; [`HeatKernel::encode`] ignores `clamped`).
    pub params: &'a wgpu::Buffer,
    /// `array<HeatDent>`, one per dent (read and written).
    pub dents: &'a wgpu::Buffer,
    /// The dents' grids (f32, row-major, world units): the input, and the output of
    /// [`HeatKernel::encode`], which smooths in place.
    pub grid: &'a wgpu::Buffer,
    /// Ping-pong scratch, at least as large as the part of `grid` the dents use; its contents
    /// are overwritten.
    pub scratch: &'a wgpu::Buffer,
}

/// Shape of one batch for [`HeatKernel::encode`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HeatBatch {
    /// Number of dents (entries of `params` and `dents` used).
    pub dents: u32,
    /// Largest `res²` of the batch, cells.
    pub max_cells: u32,
    /// Plain steps recorded: the largest `HeatDent::heat_iters` of the batch.
    pub heat_iters: u32,
    /// Clamped steps recorded: the largest `HeatDent::clamp_iters` of the batch.
    pub clamp_iters: u32,
}

/// Side of the largest grid of a batch whose largest grid has `max_cells` cells (a square's area).
fn grid_side(max_cells: u32) -> u32 {
    (max_cells as f64).sqrt().ceil() as u32
}

/// The output tile side of `fused_steps` for grids of up to `max_res` cells a side: that side cut
/// into as few tiles of at most [`MAX_TILE`] cells as cover it, evenly, so the last tile wastes
/// little (100 → four tiles of 25, 200 → seven of 29).
fn tile_side(max_res: u32) -> u32 {
    let max_res = max_res.max(1);
    max_res.div_ceil(max_res.div_ceil(MAX_TILE))
}

/// One dent of [`HeatKernel::run_batch`], the arguments of [`cpu::heat`](crate::cpu::heat).
#[derive(Debug, Clone, Copy)]
pub struct HeatJob<'a> {
    /// `res × res` heights (world units), row-major; extra values are ignored.
    pub values: &'a [f32],
    /// Cells per side.
    pub res: u32,
    /// α of the explicit step, in (0, ¼].
    pub rate: f32,
    /// k₁: plain steps.
    pub heat_iters: u32,
    /// k₂: clamped steps.
    pub clamp_iters: u32,
    /// d: the peak after the rescale, world units.
    pub dent_distance: f32,
}

/// The compiled entry points of `shaders/heat.wgsl`, built once per device.
#[derive(Debug)]
pub struct HeatKernel {
    step: Kernel,
    fused_steps: Kernel,
    clear_peak: Kernel,
    reduce_peak: Kernel,
    rescale: Kernel,
}

/// Which entry point a recorded pass runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Entry {
    Step,
    FusedSteps,
    ClearPeak,
    ReducePeak,
    Rescale,
}

impl Entry {
    /// Every entry point, in discriminant order.
    const ALL: [Self; 5] = [Self::Step, Self::FusedSteps, Self::ClearPeak, Self::ReducePeak, Self::Rescale];
}

impl HeatKernel {
    /// Compiles the five entry points (`step`, `fused_steps`, `clear_peak`, `reduce_peak`,
    /// `rescale`).
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader does not validate on this device.
    pub fn new(context: &GpuContext) -> Result<Self, GpuError> {
        let body = shaders::body("heat");
        let kernel = |label, entry| Kernel::new(context, label, body, entry, &BINDINGS);
        Ok(Self {
            step: kernel("heat step", "step")?,
            fused_steps: kernel("heat fused_steps", "fused_steps")?,
            clear_peak: kernel("heat clear_peak", "clear_peak")?,
            reduce_peak: kernel("heat reduce_peak", "reduce_peak")?,
            rescale: kernel("heat rescale", "rescale")?,
        })
    }

    /// Records the whole smoothing of a batch, the twin of [`cpu::heat`](crate::cpu::heat) per
    /// dent: `batch.heat_iters` plain steps ([`FUSED_STEPS`] a dispatch), the peak reduction and
    /// rescale, `batch.clamp_iters` clamped steps (fused too), and a final copy when the step
    /// dispatches are odd in number. The result is in `buffers.grid`; `buffers.scratch` is
    /// clobbered.
    ///
    /// Dent k takes `dents[k].heat_iters` plain and `dents[k].clamp_iters` clamped steps (counts
    /// above the batch's are cut to them) and copies its grid through the other passes; its
    /// peak after the plain steps becomes `dents[k].dent_distance` unless the grid has no
    /// positive value.
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] if the dispatch is too large for the device;
    /// [`GpuError::Validation`] if the buffers do not fit the bindings.
    pub fn encode(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        buffers: &HeatBuffers<'_>,
        batch: HeatBatch,
    ) -> Result<(), GpuError> {
        let tile = tile_side(grid_side(batch.max_cells));
        let at = |phase, index, source, steps| HeatPass { phase, index, source, tile, steps, _pad: [0; 3] };
        let mut passes = vec![(Entry::ClearPeak, at(PHASE_COPY, 0, 0, 0))];
        // Appends a phase's fused passes from `source`; returns where its result is.
        let fused = |passes: &mut Vec<_>, phase, count: u32, mut source: u32| {
            for index in 0..count.div_ceil(FUSED_STEPS) {
                let steps = (count - index * FUSED_STEPS).min(FUSED_STEPS);
                passes.push((Entry::FusedSteps, at(phase, index, source, steps)));
                source ^= 1;
            }
            source
        };
        let source = fused(&mut passes, PHASE_PLAIN, batch.heat_iters, 0);
        passes.push((Entry::ReducePeak, at(PHASE_COPY, 0, source, 0)));
        passes.push((Entry::Rescale, at(PHASE_COPY, 0, source, 0)));
        let source = fused(&mut passes, PHASE_CLAMPED, batch.clamp_iters, source);
        if source == 1 {
            passes.push((Entry::Step, at(PHASE_COPY, 0, 1, 0)));
        }
        self.record(context, encoder, buffers, batch.dents, batch.max_cells, &passes)
    }

    /// Records one step of every dent, the twin of [`cpu::heat_step`](crate::cpu::heat_step):
    /// `buffers.grid` → `buffers.scratch`, plain or clamped per `HeatParams::clamped`.
    /// `buffers.dents` is bound but not read (any storage buffer of 16 bytes or more).
    ///
    /// # Errors
    /// As [`encode`](Self::encode).
    pub fn encode_step(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        buffers: &HeatBuffers<'_>,
        dents: u32,
        max_cells: u32,
    ) -> Result<(), GpuError> {
        let single = HeatPass { phase: PHASE_SINGLE, index: 0, source: 0, tile: 0, steps: 0, _pad: [0; 3] };
        self.record(context, encoder, buffers, dents, max_cells, &[(Entry::Step, single)])
    }

    /// Smooths a batch of grids with [`encode`](Self::encode) and returns each dent's result
    /// (`res²` heights, world units), as [`cpu::heat`](crate::cpu::heat) leaves them in `values`.
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] for a batch too large for one binding or dispatch; device errors.
    ///
    /// # Panics
    /// If a job's `values` holds fewer than `res²` values.
    pub fn run_batch(&self, context: &GpuContext, jobs: &[HeatJob<'_>]) -> Result<Vec<Vec<f32>>, GpuError> {
        let grids: Vec<(HeatParams, &[f32])> = jobs
            .iter()
            .map(|job| (HeatParams { res: job.res, rate: job.rate, clamped: 0, cell_offset: 0 }, job.values))
            .collect();
        let dents: Vec<HeatDent> = jobs
            .iter()
            .map(|job| HeatDent {
                dent_distance: job.dent_distance,
                heat_iters: job.heat_iters,
                clamp_iters: job.clamp_iters,
                peak_bits: 0,
            })
            .collect();
        let batch = HeatBatch {
            dents: jobs.len() as u32,
            max_cells: 0,
            heat_iters: jobs.iter().map(|job| job.heat_iters).max().unwrap_or(0),
            clamp_iters: jobs.iter().map(|job| job.clamp_iters).max().unwrap_or(0),
        };
        self.run(context, &grids, &dents, false, |encoder, buffers, max_cells| {
            self.encode(context, encoder, buffers, HeatBatch { max_cells, ..batch })
        })
    }

    /// One [`encode_step`](Self::encode_step) over a batch of `(params, src)` grids: returns each
    /// dent's `dst` of [`cpu::heat_step`](crate::cpu::heat_step) (`cell_offset` is ignored).
    ///
    /// # Errors
    /// As [`run_batch`](Self::run_batch).
    ///
    /// # Panics
    /// If a grid holds fewer than `res²` values.
    pub fn run_step_batch(
        &self,
        context: &GpuContext,
        steps: &[(HeatParams, &[f32])],
    ) -> Result<Vec<Vec<f32>>, GpuError> {
        let dents = [HeatDent::zeroed()];
        self.run(context, steps, &dents, true, |encoder, buffers, max_cells| {
            self.encode_step(context, encoder, buffers, steps.len() as u32, max_cells)
        })
    }

    /// The pipeline of `entry`.
    fn kernel(&self, entry: Entry) -> &Kernel {
        match entry {
            Entry::Step => &self.step,
            Entry::FusedSteps => &self.fused_steps,
            Entry::ClearPeak => &self.clear_peak,
            Entry::ReducePeak => &self.reduce_peak,
            Entry::Rescale => &self.rescale,
        }
    }

    /// Packs `grids` into flat buffers (setting each `cell_offset`), records with `encode`,
    /// submits, reads back the result (from `scratch` when `in_scratch`, else `grid`) and splits
    /// it per dent.
    fn run(
        &self,
        context: &GpuContext,
        grids: &[(HeatParams, &[f32])],
        dents: &[HeatDent],
        in_scratch: bool,
        encode: impl FnOnce(&mut wgpu::CommandEncoder, &HeatBuffers<'_>, u32) -> Result<(), GpuError>,
    ) -> Result<Vec<Vec<f32>>, GpuError> {
        if grids.is_empty() {
            return Ok(Vec::new());
        }
        let mut params = Vec::with_capacity(grids.len());
        let mut cells = Vec::new();
        for &(p, values) in grids {
            let count = (p.res as usize).pow(2);
            assert!(values.len() >= count, "heat: a {0}×{0} grid needs {count} values, got {1}", p.res, values.len());
            params.push(HeatParams { cell_offset: cells.len() as u32, ..p });
            cells.extend_from_slice(&values[..count]);
        }
        let bytes = (cells.len() * size_of::<f32>()) as u64;
        buffers::check_binding_size(context, "heat grids", bytes)?;
        let max_cells = params.iter().map(|p| p.res * p.res).max().unwrap_or(0);
        let params_buffer = buffers::storage(context, "heat params", &params);
        let dents_buffer = buffers::storage(context, "heat dents", dents);
        let grid = buffers::storage(context, "heat grid", &cells);
        let scratch = buffers::storage_zeroed(context, "heat scratch", bytes);
        let buffers = HeatBuffers { params: &params_buffer, dents: &dents_buffer, grid: &grid, scratch: &scratch };
        let mut encoder = context.device.create_command_encoder(&Default::default());
        encode(&mut encoder, &buffers, max_cells)?;
        context.queue.submit([encoder.finish()]);
        let flat: Vec<f32> = buffers::read_back(context, if in_scratch { &scratch } else { &grid }, cells.len())?;
        Ok(params.iter().map(|p| flat[p.cell_offset as usize..][..(p.res as usize).pow(2)].to_vec()).collect())
    }

    /// Records `passes` over `dents` dents of up to `max_cells` cells: before each dispatch a
    /// buffer copy puts its [`HeatPass`] into the uniform the shader reads.
    fn record(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        buffers: &HeatBuffers<'_>,
        dents: u32,
        max_cells: u32,
        passes: &[(Entry, HeatPass)],
    ) -> Result<(), GpuError> {
        if dents == 0 || max_cells == 0 {
            return Ok(());
        }
        let groups = max_cells.div_ceil(WORKGROUP);
        let max_res = grid_side(max_cells);
        let tiles = max_res.div_ceil(tile_side(max_res));
        let limit = context.limits.max_compute_workgroups_per_dimension;
        for (what, needed) in
            [("heat workgroups per dent", groups), ("heat batch (dents)", dents), ("heat tiles", tiles)]
        {
            if needed > limit {
                return Err(GpuError::OverLimit { what: what.into(), needed: needed.into(), limit: limit.into() });
            }
        }
        let table: Vec<HeatPass> = passes.iter().map(|(_, pass)| *pass).collect();
        let pass_size = size_of::<HeatPass>() as u64;
        context.scoped("heat encode", || {
            let device = &context.device;
            let table = context.buffer_with_contents("heat pass table",
                bytemuck::cast_slice(&table),
                wgpu::BufferUsages::COPY_SRC,
            );
            let pass_info = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("heat pass"),
                size: pass_size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            // Per entry point (each has its own layout, indexed by `Entry`), one bind group with
            // the grid as `current` and one with the scratch as `current`, picked by `source`.
            let a = [buffers.params, buffers.dents, buffers.grid, buffers.scratch, &pass_info];
            let b = [buffers.params, buffers.dents, buffers.scratch, buffers.grid, &pass_info];
            let bind_groups = Entry::ALL.map(|entry| [a, b].map(|bound| self.kernel(entry).bind(context, &bound)));
            for (k, &(entry, pass)) in passes.iter().enumerate() {
                encoder.copy_buffer_to_buffer(&table, k as u64 * pass_size, &pass_info, 0, pass_size);
                let workgroups = match entry {
                    Entry::ClearPeak => [1, dents, 1],
                    Entry::Step => [max_res.div_ceil(STEP_WORKGROUP), max_res, dents],
                    Entry::FusedSteps => [tiles, tiles, dents],
                    _ => [groups, dents, 1],
                };
                let bind_group = &bind_groups[entry as usize][(pass.source & 1) as usize];
                self.kernel(entry).dispatch(encoder, bind_group, workgroups);
            }
        })
    }
}
