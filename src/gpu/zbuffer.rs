//! GPU twin of [`cpu::zbuffer`](crate::cpu::zbuffer): `shaders/zbuffer.wgsl`, the Z-buffer profile
//! of every dent of a batch in four dispatches: `centres` (one invocation per triangle and
//! `TILE`-sided tile of the grid), `edges` (one per triangle), `resolve` (one per cell) and
//! `tip_mark` (one per triangle).
//!
//! All samples of a dent go into one atomic word per cell (the shader's header explains how a
//! flag bit makes one `atomicMax` do the CPU's centre/edge combine), plus one tip-height word per
//! dent at the end of the same buffer, so the kernel binds four storage buffers: parameters,
//! positions, faces and the work buffer whose first words are the profiles.

use glam::Vec3;

use super::{Binding, GpuContext, GpuError, Kernel, buffers, shaders};
use crate::cpu::ZbufferParams;

/// Invocations per workgroup along x of the per-triangle entry points (`centres`, `edges`,
/// `tip_mark`); matches `FACE_WORKGROUP` in `shaders/zbuffer.wgsl`.
pub(crate) const FACE_WORKGROUP: u32 = 64;

/// Invocations per workgroup along x of the per-cell entry point (`resolve`); matches
/// `CELL_WORKGROUP` in `shaders/zbuffer.wgsl`.
pub(crate) const CELL_WORKGROUP: u32 = 256;

/// Side of the square tiles, cells, over which `centres` splits each triangle's cells (dispatch z
/// = `ceil(max_res / TILE)²`), bounding one invocation's loop to `TILE²` cells: Mesa's lavapipe
/// ends an invocation's loops after 65,535 iterations in all. Matches `TILE` in
/// `shaders/zbuffer.wgsl`.
pub(crate) const TILE: u32 = 240;

/// Vertex index the host writes for a corner that is out of range within its dent: past the end
/// of any positions buffer, so the shader culls the triangle as the CPU twin does.
pub(crate) const NO_VERTEX: u32 = u32::MAX;

/// Number of 32-bit words the work buffer needs for a batch of `batch` dents with `cells` profile
/// cells in all: the profiles (each dent at its `cell_offset`), then one tip-height word per dent,
/// which the shader finds as the buffer's last `batch` words. A larger buffer works too (the
/// words between the profiles and the tip words are cleared and unused).
pub fn work_words(cells: u64, batch: u32) -> u64 {
    cells + u64::from(batch)
}

/// The caller-owned buffers of one Z-buffer batch, in binding order.
#[derive(Debug, Clone, Copy)]
pub struct ZbufferBuffers<'a> {
    /// `array<ZbufferParams>`, one per dent: `face_offset` locates the dent's triangles (in
    /// triangles) in `faces`, `cell_offset` its profile (in cells) in `work`; `face_count`
    /// triangles are read.
    pub params: &'a wgpu::Buffer,
    /// Vertex positions of every dent's projectile, f32 x, y, z per vertex (world units), packed
    /// without padding (a `&[Vec3]` as bytes).
    pub positions: &'a wgpu::Buffer,
    /// Triangles, three u32 vertex indices each, already offset into `positions`; an index past
    /// its end (such as `u32::MAX`) culls its triangle.
    pub faces: &'a wgpu::Buffer,
    /// At least [`work_words`]`(total cells, batch)` u32 words, with `COPY_DST` usage: cleared by
    /// [`Zbuffer::encode`], then holding each dent's profile (f32, world units, `res × res`
    /// row-major at its `cell_offset`) and, in its last `batch` words, each dent's tip height.
    pub work: &'a wgpu::Buffer,
}

/// One dent's input to [`Zbuffer::run_batch`], as [`cpu::zbuffer`](crate::cpu::zbuffer) takes it.
#[derive(Debug, Clone, Copy)]
pub struct ZbufferDent<'a> {
    /// The dent's grid, dent distance and triangle count (`face_offset` and `cell_offset` are
    /// ignored: `run_batch` assigns them).
    pub params: ZbufferParams,
    /// Projectile vertex positions, world units.
    pub positions: &'a [Vec3],
    /// Projectile triangles, indices into `positions`.
    pub faces: &'a [[u32; 3]],
}

/// The compiled `zbuffer` kernel: its four entry points.
#[derive(Debug)]
pub struct Zbuffer {
    centres: Kernel,
    edges: Kernel,
    resolve: Kernel,
    tip_mark: Kernel,
}

/// Binding kinds of every entry point: params, positions, faces, work.
const BINDINGS: [Binding; 4] = [Binding::Read, Binding::Read, Binding::Read, Binding::ReadWrite];

impl Zbuffer {
    /// Compiles the four entry points.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader does not validate on this device.
    pub fn new(context: &GpuContext) -> Result<Self, GpuError> {
        let source = shaders::body("zbuffer");
        Ok(Self {
            centres: Kernel::new(context, "zbuffer centres", source, "centres", &BINDINGS)?,
            edges: Kernel::new(context, "zbuffer edges", source, "edges", &BINDINGS)?,
            resolve: Kernel::new(context, "zbuffer resolve", source, "resolve", &BINDINGS)?,
            tip_mark: Kernel::new(context, "zbuffer tip_mark", source, "tip_mark", &BINDINGS)?,
        })
    }

    /// Records, for the `batch` dents described in `buffers.params`, a clear of `buffers.work`
    /// and the four dispatches that leave each dent's profile there, as
    /// [`cpu::zbuffer`](crate::cpu::zbuffer) computes it. `max_faces` is the largest
    /// `face_count` of the batch, `max_res` the largest grid `res` (cells).
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] if `batch`, `max_faces`, `max_res²` or the tiles of `max_res` need
    /// more workgroups than the device allows in one dimension, or a buffer exceeds the binding
    /// size limit.
    pub fn encode(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        buffers: &ZbufferBuffers,
        batch: u32,
        max_faces: u32,
        max_res: u32,
    ) -> Result<(), GpuError> {
        let face_groups = u64::from(max_faces.div_ceil(FACE_WORKGROUP));
        let cell_groups = (u64::from(max_res) * u64::from(max_res)).div_ceil(CELL_WORKGROUP.into());
        let tiles = u64::from(max_res.div_ceil(TILE)).pow(2);
        let limit = context.limits.max_compute_workgroups_per_dimension;
        for (what, needed) in [
            ("zbuffer dispatch: triangle workgroups", face_groups),
            ("zbuffer dispatch: cell workgroups", cell_groups),
            ("zbuffer dispatch: tiles", tiles),
            ("zbuffer dispatch: dents", batch.into()),
        ] {
            if needed > limit.into() {
                return Err(GpuError::OverLimit { what: what.into(), needed, limit: limit.into() });
            }
        }
        for (what, buffer) in [
            ("zbuffer params", buffers.params),
            ("zbuffer positions", buffers.positions),
            ("zbuffer faces", buffers.faces),
            ("zbuffer work", buffers.work),
        ] {
            buffers::check_binding_size(context, what, buffer.size())?;
        }
        encoder.clear_buffer(buffers.work, 0, None);
        if batch == 0 {
            return Ok(());
        }
        let bound = [buffers.params, buffers.positions, buffers.faces, buffers.work];
        let (face_groups, cell_groups, tiles) = (face_groups as u32, cell_groups as u32, tiles as u32);
        for (kernel, groups) in [
            (&self.centres, [face_groups, batch, tiles]),
            (&self.edges, [face_groups, batch, 1]),
            (&self.resolve, [cell_groups, batch, 1]),
            (&self.tip_mark, [face_groups, batch, 1]),
        ] {
            if groups[0] > 0 && groups[2] > 0 {
                kernel.dispatch(encoder, &kernel.bind(context, &bound), groups);
            }
        }
        Ok(())
    }

    /// Runs a batch: packs every dent's positions and triangles into flat buffers (offsetting
    /// vertex indices, `face_count` capped at the triangles given, as the CPU twin caps it),
    /// encodes, submits, and returns each dent's `res × res` profile (world units, row-major), as
    /// [`cpu::zbuffer`](crate::cpu::zbuffer).
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] if the batch exceeds a binding or dispatch limit; validation,
    /// out-of-memory and device-lost errors from wgpu.
    pub fn run_batch(&self, context: &GpuContext, dents: &[ZbufferDent]) -> Result<Vec<Vec<f32>>, GpuError> {
        let over = |what: &str, needed: usize| GpuError::OverLimit {
            what: format!("zbuffer batch {what}"),
            needed: needed as u64,
            limit: u32::MAX.into(),
        };
        let mut params = Vec::with_capacity(dents.len());
        let (mut positions, mut faces) = (Vec::<Vec3>::new(), Vec::<[u32; 3]>::new());
        let mut cells = 0usize;
        for dent in dents {
            let (base, vertices) = (positions.len(), dent.positions.len());
            u32::try_from(base + vertices).map_err(|_| over("vertices", base + vertices))?;
            let base = base as u32;
            let count = (dent.params.face_count as usize).min(dent.faces.len());
            let face_offset = u32::try_from(faces.len()).map_err(|_| over("triangles", faces.len()))?;
            let cell_offset = u32::try_from(cells).map_err(|_| over("cells", cells))?;
            faces.extend(
                dent.faces[..count]
                    .iter()
                    .map(|face| face.map(|v| if (v as usize) < vertices { base + v } else { NO_VERTEX })),
            );
            positions.extend_from_slice(dent.positions);
            cells = cells.saturating_add((dent.params.grid.res as usize).saturating_pow(2));
            params.push(ZbufferParams { face_count: count as u32, face_offset, cell_offset, ..dent.params });
        }
        let batch = u32::try_from(dents.len()).map_err(|_| over("dents", dents.len()))?;
        let words = work_words(cells as u64, batch);
        // Before allocating: a batch too large for one binding is an error, not an abort.
        buffers::check_binding_size(context, "zbuffer work", words.saturating_mul(4))?;
        let max_faces = params.iter().map(|p| p.face_count).max().unwrap_or(0);
        let max_res = params.iter().map(|p| p.grid.res).max().unwrap_or(0);
        let work = context.scoped("zbuffer", || -> Result<wgpu::Buffer, GpuError> {
            let params = buffers::storage(context, "zbuffer params", &params);
            let positions = buffers::storage(context, "zbuffer positions", &positions);
            let faces = buffers::storage(context, "zbuffer faces", &faces);
            let work = buffers::storage_zeroed(context, "zbuffer work", words * 4);
            let mut encoder =
                context.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("zbuffer") });
            let bound = ZbufferBuffers { params: &params, positions: &positions, faces: &faces, work: &work };
            self.encode(context, &mut encoder, &bound, batch, max_faces, max_res)?;
            context.queue.submit([encoder.finish()]);
            Ok(work)
        })??;
        let flat: Vec<f32> = buffers::read_back(context, &work, cells)?;
        Ok(params.iter().map(|p| flat[p.cell_offset as usize..][..(p.grid.res as usize).pow(2)].to_vec()).collect())
    }
}
