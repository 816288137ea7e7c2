//! What leaves a [`GpuDenter`] besides its resident buffers: a target copied into a caller's
//! interleaved vertex buffer, and the vertices the last batch moved.

use super::GpuDenter;
use crate::cpu::MovedParams;
use crate::gpu::GpuError;
use crate::gpu::interleave::{InterleaveError, VertexLayout, plan};
use crate::gpu::moved::{MovedVertices, PendingMoved};

impl GpuDenter {
    /// Records a copy of target `target`'s current positions and unit normals into `dst` (the
    /// caller's buffer, with `STORAGE` usage, on the denter's device): vertex `v` of the target
    /// goes to byte `offset + v·stride`, its position (three f32, world units) at
    /// `layout.position` and its normal at `layout.normal` within the vertex. Only those bytes
    /// are written, so other attributes of an engine's interleaved layout (UVs, colours) stay as
    /// they were. Nothing is submitted: the copy runs when the caller submits `encoder`, after
    /// whatever was recorded before it (e.g. [`record_batch`](Self::record_batch)).
    ///
    /// # Errors
    /// [`InterleaveError`] when `offset`, `stride` or a field offset is not a multiple of 4, a
    /// field does not fit in `stride` or the fields overlap, `dst` is too small or lacks
    /// `STORAGE`, `target` is unknown, or the device refuses (limits, another device, lost);
    /// nothing is recorded then.
    pub fn copy_target_into(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: usize,
        dst: &wgpu::Buffer,
        offset: u64,
        stride: u64,
        layout: VertexLayout,
    ) -> Result<(), InterleaveError> {
        let count = self.targets.len();
        let resident = self.targets.get(target).ok_or(InterleaveError::UnknownTarget { target, count })?;
        let vertices = resident.vertices();
        let copy =
            plan(&self.context, vertices.start, vertices.end - vertices.start, dst.size(), offset, stride, layout)?;
        self.context.check_flag()?;
        self.kernels.interleave.encode(
            &self.context,
            encoder,
            &copy,
            &self.buffers.positions,
            &self.buffers.normals,
            dst,
        )
    }

    /// Reads back only the vertices of target `target` that the last batch moved (their
    /// displacement was non-zero), with their new positions, in ascending index order: what a
    /// physics engine needs to refit a collider. The moved flags are the `w` component the
    /// `displace` kernel sets in the resident vertex buffer (cleared at the start of every
    /// batch); the `moved` kernel compacts them on the GPU, so the read-back is 4 bytes plus 16
    /// per moved vertex. Waits for submitted work (including a recorded batch the caller has
    /// submitted).
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] for an unknown target; device errors.
    pub fn read_moved(&self, target: usize) -> Result<MovedVertices, GpuError> {
        let params = self.moved_params(target)?;
        self.context.check_alive()?;
        self.kernels.moved.run(&self.context, params, &self.buffers.positions)
    }

    /// [`read_moved`](Self::read_moved) without blocking, for a frame loop: records the
    /// compaction of target `target`'s moved vertices into the caller's `encoder` (after the
    /// batch recorded there); submit it, call [`PendingMoved::submitted`], then
    /// [`PendingMoved::poll`] each frame. The vertices are those the batch just before the
    /// compaction moved.
    ///
    /// # Errors
    /// As [`read_moved`](Self::read_moved): an unknown target or a lost device records
    /// nothing; a device error while recording may leave part of the compaction in `encoder`,
    /// so drop it instead of submitting it (as after [`record_batch`](Self::record_batch)).
    pub fn record_moved(&self, encoder: &mut wgpu::CommandEncoder, target: usize) -> Result<PendingMoved, GpuError> {
        let params = self.moved_params(target)?;
        self.context.check_flag()?;
        self.kernels.moved.record(&self.context, encoder, params, &self.buffers.positions)
    }

    /// The `moved` kernel's parameters for target `target`.
    fn moved_params(&self, target: usize) -> Result<MovedParams, GpuError> {
        let Some(resident) = self.targets.get(target) else {
            return Err(GpuError::OverLimit { what: "target index".into(), needed: target as u64, limit: 0 });
        };
        let vertices = resident.vertices();
        Ok(MovedParams { vertex_offset: vertices.start, vertex_count: vertices.end - vertices.start, _pad: [0; 2] })
    }
}
