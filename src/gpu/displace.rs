//! GPU twin of [`cpu::displace`](crate::cpu::displace): moves target vertices by attenuated dent
//! maps, many dents (on many targets) per batch, in the resident `vec4` vertex buffer.
//!
//! Dents on the same target must apply in submission order. A vertex's displacement depends only
//! on its own position, so each invocation applies its target's dents to its vertex one after the
//! other: [`runs`] groups a batch's dents by target (each group in submission order) and
//! [`Displace::encode`] records one dispatch for up to [`MAX_RUNS`] targets, however many dents
//! each takes.

use bytemuck::Zeroable;
use glam::{Vec3, Vec4};

use super::{Binding, GpuContext, GpuError, Kernel, buffers};
use crate::cpu::{DisplaceParams, falloff};

/// Invocations per workgroup along x. Keep in sync with `WORKGROUP` in `shaders/displace.wgsl`.
pub(crate) const WORKGROUP: u32 = 64;
/// Targets one dispatch serves (a 16 KiB uniform of 16-byte runs). Keep in sync with `MAX_RUNS`
/// in `shaders/displace.wgsl`.
pub const MAX_RUNS: usize = 1024;

/// The `displace` kernel (and its `clear_moved` companion), compiled once.
#[derive(Debug)]
pub struct Displace {
    kernel: Kernel,
    clear: Kernel,
    /// A 16-byte buffer filling the storage bindings `clear_moved` does not read.
    unused: wgpu::Buffer,
    /// A zeroed `runs` uniform for `clear_moved`, which does not read it.
    unused_runs: wgpu::Buffer,
}

/// One dent of a [`Displace::run_batch`] batch: which target it moves and the map it applies.
#[derive(Debug, Clone, Copy)]
pub struct DisplaceDent<'a> {
    /// Index of the target in the batch's `targets`.
    pub target: usize,
    /// Grid, dent distance and falloff as for [`cpu::displace`](crate::cpu::displace); the
    /// `vertex_count` and `*_offset` fields are filled in by the batch.
    pub params: DisplaceParams,
    /// The dent map, `res²` cells `[Δx, Δy, Δz, height]` (world units), row-major.
    pub cells: &'a [[f32; 4]],
    /// The falloff table when `params.falloff` is [`falloff::TABLE`] (at least two entries),
    /// ignored otherwise.
    pub table: &'a [f32],
}

/// A target after a [`Displace::run_batch`] batch.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DisplacedTarget {
    /// Vertex positions, world units.
    pub positions: Vec<Vec3>,
    /// Whether each vertex moved in this batch (the `w` flag of the GPU vertex buffer).
    pub moved: Vec<bool>,
}

/// Groups a batch's dents by target for [`Displace::encode`]: one list of dent indices (into
/// `params`, ascending, i.e. in submission order) per target, targets in the order of their first
/// dent. A target is identified by its vertex range `vertex_offset .. vertex_offset +
/// vertex_count`.
///
/// # Errors
/// [`GpuError::Validation`] if two dents' vertex ranges overlap without being equal (they are
/// not one target, and their order on the shared vertices would be lost).
pub fn runs(params: &[DisplaceParams]) -> Result<Vec<Vec<usize>>, GpuError> {
    let range = |p: &DisplaceParams| (p.vertex_offset as u64, p.vertex_offset as u64 + p.vertex_count as u64);
    // (range, its group): a linear scan, dents × targets, fine for the hundreds of targets a
    // batch holds.
    let mut targets: Vec<(u64, u64)> = Vec::new();
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (k, p) in params.iter().enumerate() {
        let (start, end) = range(p);
        let mut found = None;
        for (t, &(s, e)) in targets.iter().enumerate() {
            if (s, e) == (start, end) {
                found = Some(t);
                break;
            }
            if start < e && s < end {
                return Err(batch_error(format!(
                    "dent {k} moves vertices {start}..{end}, which overlap another dent's {s}..{e}"
                )));
            }
        }
        match found {
            Some(t) => groups[t].push(k),
            None => {
                targets.push((start, end));
                groups.push(vec![k]);
            }
        }
    }
    Ok(groups)
}

/// One target of a dispatch, as `shaders/displace.wgsl` reads `runs`: its dents' place in the
/// dispatch's parameters and its vertices.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Run {
    first_dent: u32,
    dents: u32,
    vertex_offset: u32,
    vertex_count: u32,
}

impl Displace {
    /// Compiles the kernel.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader does not compile on this device.
    pub fn new(context: &GpuContext) -> Result<Self, GpuError> {
        let source = super::shaders::body("displace");
        let bindings = [Binding::Read, Binding::Read, Binding::Read, Binding::ReadWrite, Binding::Uniform];
        let kernel = Kernel::new(context, "displace", source, "main", &bindings)?;
        let clear = Kernel::new(context, "displace clear_moved", source, "clear_moved", &bindings)?;
        let unused = buffers::storage_zeroed(context, "displace clear_moved unused", 16);
        let unused_runs = runs_uniform(context, "displace clear_moved runs", &[Run::zeroed(); MAX_RUNS]);
        Ok(Self { kernel, clear, unused, unused_runs })
    }

    /// Records the dispatches that apply a batch of dents, in submission order, to the vertex
    /// buffer `positions` (`vec4` per vertex: xyz world position, w moved flag, set to 1.0 for
    /// every vertex a dent moves). `params` are the dents in submission order with their offsets
    /// into `cells` (dent maps, `vec4` per cell), `table` (falloff tables, f32) and `positions`;
    /// dents on the same target share its vertex range. One dispatch per [`MAX_RUNS`] targets
    /// ([`runs`]); the small parameter buffers are created here.
    ///
    /// # Errors
    /// As [`runs`]; [`GpuError::OverLimit`] if a target has more than 4,194,240 (65,535 workgroups of 64)
    /// vertices.
    pub fn encode(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        params: &[DisplaceParams],
        cells: &wgpu::Buffer,
        table: &wgpu::Buffer,
        positions: &wgpu::Buffer,
    ) -> Result<(), GpuError> {
        let max_groups = context.limits.max_compute_workgroups_per_dimension;
        // Targets are the dispatch's y: at most MAX_RUNS, and at most the device allows.
        for targets in runs(params)?.chunks(MAX_RUNS.min(max_groups as usize).max(1)) {
            let max_vertices = targets.iter().map(|dents| params[dents[0]].vertex_count).max().unwrap_or(0);
            let groups = max_vertices.div_ceil(WORKGROUP);
            if groups > max_groups {
                let what = "displace dispatch (vertices per target / WORKGROUP)";
                return Err(GpuError::OverLimit { what: what.into(), needed: groups.into(), limit: max_groups.into() });
            }
            if groups == 0 {
                continue;
            }
            let mut ordered = Vec::new();
            let mut table_of_runs = vec![Run::zeroed(); MAX_RUNS];
            for (run, dents) in table_of_runs.iter_mut().zip(targets) {
                let target = params[dents[0]];
                *run = Run {
                    first_dent: ordered.len() as u32,
                    dents: dents.len() as u32,
                    vertex_offset: target.vertex_offset,
                    vertex_count: target.vertex_count,
                };
                ordered.extend(dents.iter().map(|&k| params[k]));
            }
            let params_buffer = buffers::storage(context, "displace params", &ordered);
            let runs_buffer = runs_uniform(context, "displace runs", &table_of_runs);
            let bind = self.kernel.bind(context, &[&params_buffer, cells, table, positions, &runs_buffer]);
            self.kernel.dispatch(encoder, &bind, [groups, targets.len() as u32, 1]);
        }
        Ok(())
    }

    /// Records a dispatch that clears the moved flag (`w`) of every vertex in `positions` (the
    /// whole buffer, `vec4` per vertex), before a batch whose moved vertices the caller wants to
    /// tell apart.
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] if `positions` holds more than 4,194,240 (65,535 workgroups of 64) vertices.
    pub fn encode_clear_moved(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        positions: &wgpu::Buffer,
    ) -> Result<(), GpuError> {
        let vertices = positions.size() / size_of::<Vec4>() as u64;
        let groups = vertices.div_ceil(WORKGROUP as u64);
        let limit = context.limits.max_compute_workgroups_per_dimension as u64;
        if groups > limit {
            return Err(GpuError::OverLimit { what: "displace clear_moved workgroups".into(), needed: groups, limit });
        }
        let unused = &self.unused;
        let bind = self.clear.bind(context, &[unused, unused, unused, positions, &self.unused_runs]);
        self.clear.dispatch(encoder, &bind, [groups as u32, 1, 1]);
        Ok(())
    }

    /// Applies `dents`, in order, to copies of `targets` (positions, world units) on the GPU and
    /// returns every target's new positions and moved flags: the same as calling
    /// [`cpu::displace`](crate::cpu::displace) for each dent in turn.
    ///
    /// # Errors
    /// [`GpuError::Validation`] for a dent whose target index, map size or falloff table is
    /// invalid; as [`encode`](Self::encode); [`GpuError::OverLimit`] for a buffer over the
    /// binding limit; any device error.
    pub fn run_batch(
        &self,
        context: &GpuContext,
        targets: &[&[Vec3]],
        dents: &[DisplaceDent<'_>],
    ) -> Result<Vec<DisplacedTarget>, GpuError> {
        let mut vertex_offsets = Vec::with_capacity(targets.len());
        let mut vertices: Vec<Vec4> = Vec::new();
        for target in targets {
            vertex_offsets.push(vertices.len() as u32);
            vertices.extend(target.iter().map(|p| p.extend(0.0)));
        }
        let mut params = Vec::with_capacity(dents.len());
        let mut cells: Vec<[f32; 4]> = Vec::new();
        let mut table: Vec<f32> = Vec::new();
        for (k, dent) in dents.iter().enumerate() {
            let Some(target) = targets.get(dent.target) else {
                return Err(batch_error(format!("dent {k} names target {} of {}", dent.target, targets.len())));
            };
            if dent.cells.len() != (dent.params.grid.res as usize).pow(2) {
                return Err(batch_error(format!("dent {k}: the map must hold res² cells")));
            }
            let uses_table = dent.params.falloff == falloff::TABLE;
            if uses_table && dent.table.len() < 2 {
                return Err(batch_error(format!("dent {k}: a falloff table needs two entries")));
            }
            let dent_table = if uses_table { dent.table } else { &[] };
            params.push(DisplaceParams {
                vertex_count: target.len() as u32,
                vertex_offset: vertex_offsets[dent.target],
                cell_offset: cells.len() as u32,
                table_offset: table.len() as u32,
                table_len: dent_table.len() as u32,
                ..dent.params
            });
            cells.extend_from_slice(dent.cells);
            table.extend_from_slice(dent_table);
        }
        buffers::check_binding_size(context, "displace cells", size_of_val(cells.as_slice()) as u64)?;
        buffers::check_binding_size(context, "displace table", size_of_val(table.as_slice()) as u64)?;
        buffers::check_binding_size(context, "displace positions", size_of_val(vertices.as_slice()) as u64)?;

        let cells_buffer = buffers::storage(context, "displace cells", &cells);
        let table_buffer = buffers::storage(context, "displace table", &table);
        let positions_buffer = buffers::storage(context, "displace positions", &vertices);
        let mut encoder = context.device.create_command_encoder(&Default::default());
        context.scoped("displace", || {
            self.encode(context, &mut encoder, &params, &cells_buffer, &table_buffer, &positions_buffer)
        })??;
        context.queue.submit([encoder.finish()]);
        let out: Vec<Vec4> = buffers::read_back(context, &positions_buffer, vertices.len())?;

        Ok(targets
            .iter()
            .zip(&vertex_offsets)
            .map(|(target, &offset)| {
                let slice = &out[offset as usize..offset as usize + target.len()];
                DisplacedTarget {
                    positions: slice.iter().map(|v| v.truncate()).collect(),
                    moved: slice.iter().map(|v| v.w > 0.0).collect(),
                }
            })
            .collect())
    }
}

/// The `runs` uniform: [`MAX_RUNS`] runs, 16 KiB.
fn runs_uniform(context: &GpuContext, label: &str, runs: &[Run]) -> wgpu::Buffer {
    debug_assert_eq!(runs.len(), MAX_RUNS);
    context.buffer_with_contents(label, bytemuck::cast_slice(runs), wgpu::BufferUsages::UNIFORM)
}

fn batch_error(message: String) -> GpuError {
    GpuError::Validation { label: "displace batch".into(), message }
}
