//! Many dents per frame on the GPU: `GpuDenter` keeps target meshes resident and runs each
//! kernel once per batch (paper Algorithm 1 for every impact of a time step at once).

mod arena;
mod batch;
mod chunks;
mod output;
mod resident;
mod stages;
mod targets;

use std::collections::HashMap;
use std::ops::Range;
use std::sync::{Mutex, MutexGuard};

use glam::Vec3;
use rayon::prelude::*;

use super::displace::Displace;
use super::envelope_cols::EnvelopeCols;
use super::envelope_rows::{EnvelopeBuffers, EnvelopeRows, scratch_bytes};
use super::glance::{GlanceBuffers, GlanceKernel};
use super::heat::{HeatBatch, HeatBuffers, HeatDent, HeatKernel};
use super::interleave::Interleave;
use super::moved::Moved;
use super::normals::{Normals, NormalsParams};
use super::recorder::Recorder;
use super::zbuffer::{Zbuffer, ZbufferBuffers, work_words};
use super::{GpuContext, GpuError, buffers};
use crate::cpu::{DisplaceParams, EnvelopeParams, GlanceParams, HeatParams, ZbufferParams, falloff_table};
use crate::dent::{BatchError, DentJob, DentMap, DentPlan, DentStages, plan_dent};
use crate::mesh::TriMesh;
use arena::{Arena, Slot};
use resident::{Resident, ResidentBuffers};

/// Why a GPU batch failed; no target changed.
#[derive(Debug, thiserror::Error)]
pub enum GpuBatchError {
    /// One dent's input was invalid (reported by job index, as [`crate::dent::dent_batch`] does).
    #[error(transparent)]
    Job(#[from] BatchError),
    /// A dent given to [`GpuDenter::record_batch`] (or `dent_batch_timed`, with the `kernels`
    /// feature) asks for stages that run on the host,
    /// which a recording that never waits cannot run; nothing was recorded.
    #[error(
        "dent {job} of the batch asks for {stages}, which run on the host around the kernels, and \
         a recorded batch runs the kernels alone: dent it with GpuDenter::dent_batch, or make the \
         paper's dent with DentParams::without_host_stages"
    )]
    HostStages {
        /// Index of the dent in the batch.
        job: usize,
        /// The stages it asks for, comma-separated.
        stages: String,
    },
    /// The GPU failed.
    #[error(transparent)]
    Gpu(#[from] GpuError),
}

impl GpuStages {
    kernels_fn! {
        /// The same stages in the CPU pipeline's form.
        fn into_stages(self) -> DentStages {
            let map = DentMap { grid: self.plan.map_grid, cells: self.map, dent_distance: self.plan.dent_distance };
            DentStages {
                zbuffer_grid: self.plan.zbuffer_grid,
                zbuffer: self.zbuffer,
                envelope: self.envelope,
                smoothed: self.smoothed,
                map,
                frame: self.plan.frame,
                sigma: self.plan.sigma,
            }
        }
    }
}

/// What one dent of a GPU batch was planned as (vertex counts need a read-back, so they are
/// not reported).
#[derive(Debug, Clone, PartialEq)]
pub struct GpuDentInfo {
    /// θ after clamping, degrees.
    pub theta_deg: f32,
    /// Z-buffer grid side, cells.
    pub resolution: u32,
    /// Dent-map grid side, cells.
    pub map_resolution: u32,
    /// Z-buffer cell side, world units.
    pub cell_size: f32,
}

/// Every stage of one dent map as the GPU computed it (what `dent_map_stages` returns on the
/// CPU), read back for inspection and tests.
#[derive(Debug, Clone)]
pub struct GpuStages {
    /// The host-side plan (frame, grids, parameter blocks).
    pub plan: DentPlan,
    /// Profile P, `res²`, row-major.
    pub zbuffer: Vec<f32>,
    /// Exact Gaussian envelope.
    pub envelope: Vec<f32>,
    /// After heat smoothing.
    pub smoothed: Vec<f32>,
    /// Dent-map cells `[Δx, Δy, Δz, height]`.
    pub map: Vec<[f32; 4]>,
}

/// The compiled kernels.
struct Kernels {
    zbuffer: Zbuffer,
    rows: EnvelopeRows,
    cols: EnvelopeCols,
    heat: HeatKernel,
    glance: GlanceKernel,
    displace: Displace,
    normals: Normals,
    interleave: Interleave,
    moved: Moved,
}

/// Dents target meshes that stay on the GPU, with every stage of [`DentParams`](crate::DentParams).
///
/// Targets are uploaded once ([`new`](Self::new)) and stay on the device; the host keeps a
/// mirror of each (`resident.rs`). [`dent_batch`](Self::dent_batch) gives what the CPU batch
/// ([`dent_batch_tracked`](crate::dent::dent_batch_tracked)) gives: each job is planned on the
/// host, its target refined there where the dent needs it (the new vertices and triangles are
/// written into the target's slice of the device buffers), the falloff fitted to the target's
/// thickness where it could fold a wall; the kernels build every map and displace, once per batch
/// (per memory-sized chunk of it) over every dent; then only the vertices the kernels moved come
/// back, the intersection guard and the volume rim run on the host's mirror, and what they change
/// is written back. Several dents on one target apply in submission order, each on what the
/// earlier ones left. No batch reads a whole target back.
///
/// The deformed vertices stay in [`vertex_buffer`](Self::vertex_buffer) (`vec4<f32>` per
/// vertex, `w` = moved in the last batch) for a renderer to bind; [`mesh`](Self::mesh) is the
/// host's copy and [`read_positions`](Self::read_positions) reads the device's.
///
/// [`record_batch`](Self::record_batch) records a batch into the caller's command encoder for a
/// frame loop that never waits: it runs the kernels, so it takes the dents that need no host
/// stage ([`DentParams::without_host_stages`](crate::DentParams::without_host_stages)) and
/// refuses the others.
///
/// The denter holds its own clone of the [`GpuContext`] (no borrow), so it is `Send + Sync +
/// 'static` and can live in an application's resources.
pub struct GpuDenter {
    context: GpuContext,
    kernels: Kernels,
    targets: Vec<Resident>,
    buffers: ResidentBuffers,
    /// Usage the vertex and normal buffers get beyond storage and copies.
    usage: wgpu::BufferUsages,
    /// The map-building buffers, kept between batches (see [`scratch_bytes`](Self::scratch_bytes)).
    arena: Mutex<Arena>,
    /// Vertices the last [`dent_batch`](Self::dent_batch) read back.
    vertices_read_back: usize,
    /// Bytes the last [`dent_batch`](Self::dent_batch) read back.
    bytes_read_back: u64,
    /// Seconds the last [`dent_batch`](Self::dent_batch) waited for the device.
    waited_s: f64,
}

/// How a [`GpuDenter`] creates its resident buffers.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GpuDenterOptions {
    /// Give the resident vertex and normal buffers `VERTEX` usage as well as `STORAGE`, so a
    /// render pipeline can bind them as vertex buffers (`Float32x3` at offset 0, stride 16 bytes)
    /// with no copy.
    pub vertex_usage: bool,
}

impl GpuDenter {
    /// Compiles the kernels and uploads `targets` (positions, normals, triangles, vertex→face
    /// adjacency) onto `context`'s device, keeping a clone of `context` (cheap: the handles are
    /// shared) and a copy of each target on the host.
    ///
    /// # Errors
    /// Kernel compilation errors, or [`GpuError::OverLimit`] when the targets do not fit one
    /// storage binding.
    pub fn new(context: &GpuContext, targets: &[TriMesh]) -> Result<Self, GpuError> {
        Self::with_options(context, targets, GpuDenterOptions::default())
    }

    /// [`new`](Self::new) with `options` (e.g. resident buffers an application can bind as
    /// vertex buffers).
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn with_options(
        context: &GpuContext,
        targets: &[TriMesh],
        options: GpuDenterOptions,
    ) -> Result<Self, GpuError> {
        let context = context.clone();
        let context = &context;
        let kernels = Kernels {
            zbuffer: Zbuffer::new(context)?,
            rows: EnvelopeRows::new(context)?,
            cols: EnvelopeCols::new(context)?,
            heat: HeatKernel::new(context)?,
            glance: GlanceKernel::new(context)?,
            displace: Displace::new(context)?,
            normals: Normals::new(context)?,
            interleave: Interleave::new(context)?,
            moved: Moved::new(context)?,
        };
        let mut resident: Vec<Resident> = targets.iter().cloned().map(Resident::new).collect();
        let usage = if options.vertex_usage { wgpu::BufferUsages::VERTEX } else { wgpu::BufferUsages::empty() };
        let buffers = ResidentBuffers::lay_out(context, &mut resident, usage)?;
        Ok(Self {
            context: context.clone(),
            kernels,
            targets: resident,
            buffers,
            usage,
            arena: Mutex::default(),
            vertices_read_back: 0,
            bytes_read_back: 0,
            waited_s: 0.0,
        })
    }

    /// Vertices the last [`dent_batch`](Self::dent_batch) read back from the device: those the
    /// kernels moved, once per round of the batch (16 bytes each, plus 4 per target and
    /// round for the count). No other read-back of positions happens in a batch.
    pub fn vertices_read_back(&self) -> usize {
        self.vertices_read_back
    }

    /// Bytes the last [`dent_batch`](Self::dent_batch) read back from the device: the moved
    /// vertices ([`vertices_read_back`](Self::vertices_read_back)) with their counts, and the
    /// stages of each map a fold-prone falloff was fitted to.
    pub fn bytes_read_back(&self) -> u64 {
        self.bytes_read_back
    }

    /// Seconds the last [`dent_batch`](Self::dent_batch) spent waiting for the device (its
    /// kernels and read-backs); the rest of its time is the host's: planning, refinement,
    /// recording and the host stages.
    pub fn waited_seconds(&self) -> f64 {
        self.waited_s
    }

    /// The context (device and queue) the denter runs on.
    pub fn context(&self) -> &GpuContext {
        &self.context
    }

    /// The deformed vertices of every target, `vec4<f32>` each (xyz world units, w = 1 when the
    /// vertex moved in the last batch); target `t` occupies [`vertex_range`](Self::vertex_range).
    pub fn vertex_buffer(&self) -> &wgpu::Buffer {
        &self.buffers.positions
    }

    /// Unit vertex normals, laid out like [`vertex_buffer`](Self::vertex_buffer).
    pub fn normal_buffer(&self) -> &wgpu::Buffer {
        &self.buffers.normals
    }

    /// Byte range of target `target`'s vertices in the vertex and normal buffers.
    ///
    /// # Panics
    /// If `target` is not a target index.
    pub fn vertex_range(&self, target: usize) -> Range<u64> {
        let v = self.targets[target].vertices();
        u64::from(v.start) * 16..u64::from(v.end) * 16
    }

    /// Number of resident targets.
    pub fn target_count(&self) -> usize {
        self.targets.len()
    }

    /// Bytes of GPU memory the denter keeps between batches for building dent maps, beside its
    /// resident targets: the largest chunk's grids and maps so far (about 40 bytes per grid cell
    /// of the chunk, so 1,024 dents at 100² hold ~400 MB), reused by the next batch instead of
    /// allocated afresh. [`release_scratch`](Self::release_scratch) gives it back.
    pub fn scratch_bytes(&self) -> u64 {
        self.arena().bytes()
    }

    /// Frees the map-building buffers kept between batches (after a burst of dents, say); the
    /// next batch allocates what it needs again.
    pub fn release_scratch(&mut self) {
        self.arena().release();
    }

    /// The arena, whatever a panicking thread left in it (its buffers hold no invariant: every
    /// kernel writes what it later reads).
    fn arena(&self) -> MutexGuard<'_, Arena> {
        self.arena.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Reads target `target`'s current vertex positions back (world units).
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] for an unknown target; GPU errors.
    pub fn read_positions(&self, target: usize) -> Result<Vec<Vec3>, GpuError> {
        let Some(resident) = self.targets.get(target) else {
            return Err(GpuError::OverLimit { what: "target index".into(), needed: target as u64, limit: 0 });
        };
        let (first, count) = (resident.first_vertex as usize, resident.mesh.vertex_count());
        let values: Vec<[f32; 4]> = buffers::read_back_range(&self.context, &self.buffers.positions, first, count)?;
        Ok(values.iter().map(|v| Vec3::new(v[0], v[1], v[2])).collect())
    }

    /// Reads target `target`'s current unit vertex normals back (refreshed on the GPU after each
    /// batch around the vertices it moved).
    ///
    /// # Errors
    /// As [`read_positions`](Self::read_positions).
    pub fn read_normals(&self, target: usize) -> Result<Vec<Vec3>, GpuError> {
        let Some(resident) = self.targets.get(target) else {
            return Err(GpuError::OverLimit { what: "target index".into(), needed: target as u64, limit: 0 });
        };
        let (first, count) = (resident.first_vertex as usize, resident.mesh.vertex_count());
        let values: Vec<[f32; 4]> = buffers::read_back_range(&self.context, &self.buffers.normals, first, count)?;
        Ok(values.iter().map(|v| Vec3::new(v[0], v[1], v[2])).collect())
    }

    /// Target `target` as the device holds it now, read back whole (normals recomputed on the
    /// CPU); [`mesh`](Self::mesh) is the host's copy, with no read-back.
    ///
    /// # Errors
    /// As [`read_positions`](Self::read_positions).
    pub fn read_mesh(&self, target: usize) -> Result<TriMesh, GpuError> {
        let positions = self.read_positions(target)?;
        TriMesh::new(positions, self.targets[target].mesh.faces().to_vec())
            .map_err(|e| GpuError::Validation { label: "read back mesh".into(), message: e.to_string() })
    }

    kernels_fn! {
        /// Builds every job's dent map on the GPU and reads all stages back, without touching the
        /// targets (the GPU twin of `dent_map_stages`, batched).
        ///
        /// # Errors
        /// As [`dent_batch`](Self::dent_batch).
        fn dent_map_stages(&self, jobs: &[DentJob<'_>]) -> Result<Vec<GpuStages>, GpuBatchError> {
            let plans = self.plan(jobs)?;
            Ok(self.stages_from_plans(jobs, &plans)?)
        }
    }

    kernels_fn! {
        /// Builds the dent maps of already planned jobs (see [`plan_dent`]) and reads every stage
        /// back; `jobs[k].target` is not used, so this also serves maps with no resident target.
        ///
        /// # Errors
        /// GPU errors.
        ///
        /// # Panics
        /// If `jobs` and `plans` differ in length.
        fn stages_from_plans(&self, jobs: &[DentJob<'_>], plans: &[DentPlan]) -> Result<Vec<GpuStages>, GpuError> {
            assert_eq!(jobs.len(), plans.len(), "one plan per job");
            if let Some(plan) = plans.iter().find(|p| p.zbuffer_grid.res.max(p.map_grid.res) > crate::dent::MAX_RESOLUTION)
            {
                let res = plan.zbuffer_grid.res.max(plan.map_grid.res);
                let limit = crate::dent::MAX_RESOLUTION.into();
                return Err(GpuError::OverLimit { what: "dent grid side".into(), needed: res.into(), limit });
            }
            let mut out = Vec::with_capacity(jobs.len());
            // Held until every read-back is done, so no other call of this denter reuses the buffers
            // meanwhile; the maps and their read-back go in one submission, so no batch a caller
            // recorded earlier and submits now can come between them either.
            let mut arena = self.arena();
            for chunk in chunks::chunks(plans, jobs, &self.context) {
                let chunk_jobs: Vec<&DentJob> = chunk.clone().map(|k| &jobs[k]).collect();
                let chunk_plans: Vec<&DentPlan> = chunk.clone().map(|k| &plans[k]).collect();
                let mut rec = Recorder::new(&self.context, None);
                let maps = self.encode_maps(&mut rec, &mut arena, &chunk_jobs, &chunk_plans, true)?;
                let cells = maps.cell_offsets.last().copied().unwrap_or(0) as usize;
                let map_cells = maps.map_offsets.last().copied().unwrap_or(0) as usize;
                let sources =
                    [(&maps.work, cells), (&maps.envelope, cells), (&maps.smoothed, cells), (&maps.map, 4 * map_cells)];
                let [profile, envelope, smoothed, map] =
                    buffers::read_back_all_after::<f32>(&self.context, rec.finish(), &sources)?
                        .try_into()
                        .expect("one read-back per source");
                let map: &[[f32; 4]] = bytemuck::cast_slice(&map);
                for (k, plan) in chunk_plans.iter().enumerate() {
                    let cells = maps.cell_offsets[k] as usize..maps.cell_offsets[k + 1] as usize;
                    let map_range = maps.map_offsets[k] as usize..maps.map_offsets[k + 1] as usize;
                    out.push(GpuStages {
                        plan: (*plan).clone(),
                        zbuffer: profile[cells.clone()].to_vec(),
                        envelope: envelope[cells.clone()].to_vec(),
                        smoothed: smoothed[cells].to_vec(),
                        map: map[map_range].to_vec(),
                    });
                }
            }
            Ok(out)
        }
    }

    /// Validates and plans every job on the CPU (in parallel).
    fn plan(&self, jobs: &[DentJob<'_>]) -> Result<Vec<DentPlan>, BatchError> {
        if let Some((job, bad)) = jobs.iter().enumerate().find(|(_, j)| j.target >= self.targets.len()) {
            let error = crate::dent::invalid("target", bad.target, "must index the denter's targets");
            return Err(BatchError { job, error });
        }
        jobs.par_iter()
            .enumerate()
            .map(|(job, j)| {
                let edge = self.targets[j.target].mean_edge;
                plan_dent(j.projectile, &j.impact, &j.params, Some(edge)).map_err(|error| BatchError { job, error })
            })
            .collect()
    }

    /// Records zbuffer → envelope → heat → glance for one chunk into `arena`'s buffers; returns
    /// them. With `keep_envelope` the heat steps smooth a copy, so the envelope can be read back;
    /// without, they smooth it in place (`MapBuffers::envelope` then holds the smoothed heights).
    fn encode_maps(
        &self,
        rec: &mut Recorder<'_>,
        arena: &mut Arena,
        jobs: &[&DentJob<'_>],
        plans: &[&DentPlan],
        keep_envelope: bool,
    ) -> Result<MapBuffers, GpuError> {
        let context = &self.context;
        let batch = plans.len() as u32;
        // Projectiles, each uploaded once however many dents share it.
        let (mut positions, mut faces) = (Vec::<Vec3>::new(), Vec::<[u32; 3]>::new());
        let mut placed: HashMap<*const TriMesh, u32> = HashMap::new();
        let face_offsets: Vec<u32> = jobs
            .iter()
            .map(|job| {
                *placed.entry(std::ptr::from_ref(job.projectile)).or_insert_with(|| {
                    let (base, first) = (positions.len() as u32, faces.len() as u32);
                    positions.extend_from_slice(job.projectile.positions());
                    faces.extend(job.projectile.faces().iter().map(|f| f.map(|v| v + base)));
                    first
                })
            })
            .collect();
        let mut cell_offsets = vec![0u32];
        let mut map_offsets = vec![0u32];
        for plan in plans {
            cell_offsets.push(cell_offsets.last().unwrap() + plan.zbuffer_grid.res.pow(2));
            map_offsets.push(map_offsets.last().unwrap() + plan.map_grid.res.pow(2));
        }
        let cells = u64::from(*cell_offsets.last().unwrap());
        let max_res = plans.iter().map(|p| p.zbuffer_grid.res).max().unwrap_or(0);
        let max_faces = jobs.iter().map(|j| j.projectile.face_count() as u32).max().unwrap_or(0);

        let zparams: Vec<ZbufferParams> = plans
            .iter()
            .enumerate()
            .map(|(k, p)| ZbufferParams {
                face_count: p.zbuffer.face_count.min(jobs[k].projectile.face_count() as u32),
                face_offset: face_offsets[k],
                cell_offset: cell_offsets[k],
                ..p.zbuffer
            })
            .collect();
        let eparams: Vec<EnvelopeParams> = plans
            .iter()
            .enumerate()
            .map(|(k, p)| EnvelopeParams { cell_offset: cell_offsets[k], ..p.envelope })
            .collect();
        let hparams: Vec<HeatParams> = plans
            .iter()
            .enumerate()
            .map(|(k, p)| HeatParams {
                res: p.zbuffer_grid.res,
                rate: p.heat_rate,
                clamped: 0,
                cell_offset: cell_offsets[k],
            })
            .collect();
        let hdents: Vec<HeatDent> = plans
            .iter()
            .map(|p| HeatDent {
                dent_distance: p.dent_distance,
                heat_iters: p.heat_iters,
                clamp_iters: p.clamp_iters,
                peak_bits: 0,
            })
            .collect();
        let gparams: Vec<GlanceParams> = plans
            .iter()
            .enumerate()
            .map(|(k, p)| GlanceParams { src_offset: cell_offsets[k], dst_offset: map_offsets[k], ..p.glance })
            .collect();

        let map_bytes = u64::from(*map_offsets.last().unwrap()) * 16;
        let work = arena.take(context, Slot::Work, work_words(cells, batch) * 4);
        let rows = arena.take(context, Slot::Rows, cells * 4);
        let envelope = arena.take(context, Slot::Envelope, cells * 4);
        let scratch = arena.take(context, Slot::Scratch, scratch_bytes(cells));
        let map = arena.take(context, Slot::Map, map_bytes);

        self.kernels.zbuffer.encode(
            context,
            rec.encoder(),
            &ZbufferBuffers {
                params: &buffers::storage(context, "zbuffer params", &zparams),
                positions: &buffers::storage(context, "projectile positions", &positions),
                faces: &buffers::storage(context, "projectile faces", &faces),
                work: &work,
            },
            batch,
            max_faces,
            max_res,
        )?;
        rec.stage("zbuffer")?;
        let eparams = buffers::storage(context, "envelope params", &eparams);
        let rows_buffers = EnvelopeBuffers { params: &eparams, input: &work, output: &rows, scratch: &scratch };
        self.kernels.rows.encode(context, rec.encoder(), &rows_buffers, batch, max_res)?;
        rec.stage("envelope_rows")?;
        let cols_buffers = EnvelopeBuffers { params: &eparams, input: &rows, output: &envelope, scratch: &scratch };
        self.kernels.cols.encode(context, rec.encoder(), &cols_buffers, batch, max_res)?;
        rec.stage("envelope_cols")?;
        // Heat smooths in place; the rows pass's output is free by now and serves as its scratch.
        let smoothed = if keep_envelope {
            let copy = arena.take(context, Slot::Smoothed, cells * 4);
            rec.encoder().copy_buffer_to_buffer(&envelope, 0, &copy, 0, cells * 4);
            copy
        } else {
            envelope.clone()
        };
        let heat_batch = HeatBatch {
            dents: batch,
            max_cells: max_res * max_res,
            heat_iters: plans.iter().map(|p| p.heat_iters).max().unwrap_or(0),
            clamp_iters: plans.iter().map(|p| p.clamp_iters).max().unwrap_or(0),
        };
        let heat_buffers = HeatBuffers {
            params: &buffers::storage(context, "heat params", &hparams),
            dents: &buffers::storage(context, "heat dents", &hdents),
            grid: &smoothed,
            scratch: &rows,
        };
        self.kernels.heat.encode(context, rec.encoder(), &heat_buffers, heat_batch)?;
        rec.stage("heat")?;
        let max_map_cells = plans.iter().map(|p| p.map_grid.res.pow(2)).max().unwrap_or(0);
        let glance_buffers = GlanceBuffers {
            params: &buffers::storage(context, "glance params", &gparams),
            heights: &smoothed,
            dent_map: &map,
        };
        self.kernels.glance.encode(context, rec.encoder(), &glance_buffers, batch, max_map_cells)?;
        rec.stage("glance")?;
        Ok(MapBuffers { work, envelope, smoothed, map, cell_offsets, map_offsets })
    }

    /// Records the displacement of every job's target by its map, in submission order.
    fn encode_displace(
        &self,
        rec: &mut Recorder<'_>,
        jobs: &[&DentJob<'_>],
        plans: &[&DentPlan],
        maps: &MapBuffers,
    ) -> Result<(), GpuError> {
        let mut tables = Vec::<f32>::new();
        let params: Vec<DisplaceParams> = jobs
            .iter()
            .zip(plans)
            .enumerate()
            .map(|(k, (job, plan))| {
                let (falloff, falloff_scale, table) = falloff_table(&job.params.attenuation, plan.dent_distance);
                let table_offset = tables.len() as u32;
                tables.extend_from_slice(&table);
                let vertices = self.targets[job.target].vertices();
                DisplaceParams {
                    grid: plan.map_grid.uniform(),
                    dent_distance: plan.dent_distance,
                    falloff,
                    falloff_scale,
                    vertex_count: vertices.end - vertices.start,
                    vertex_offset: vertices.start,
                    cell_offset: maps.map_offsets[k],
                    table_offset,
                    table_len: table.len() as u32,
                }
            })
            .collect();
        let tables = buffers::storage(&self.context, "falloff tables", &tables);
        self.kernels.displace.encode(
            &self.context,
            rec.encoder(),
            &params,
            &maps.map,
            &tables,
            &self.buffers.positions,
        )?;
        rec.stage("displace")
    }

    fn normals_params(&self, target: usize) -> NormalsParams {
        let t = &self.targets[target];
        NormalsParams {
            vertex_count: t.mesh.vertex_count() as u32,
            vertex_offset: t.first_vertex,
            face_offset: t.face_offset,
            adjacency_offset: t.adjacency_offset,
            moved_only: 1,
            _pad: [0; 3],
        }
    }
}

/// The buffers of one chunk's maps and where each dent sits in them (prefix sums, one entry
/// more than dents).
struct MapBuffers {
    work: wgpu::Buffer,
    envelope: wgpu::Buffer,
    smoothed: wgpu::Buffer,
    map: wgpu::Buffer,
    cell_offsets: Vec<u32>,
    map_offsets: Vec<u32>,
}
