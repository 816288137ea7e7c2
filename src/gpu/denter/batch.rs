//! Running a batch: recording it into the caller's encoder ([`GpuDenter::record_batch`]), or
//! recording and submitting it ([`GpuDenter::dent_batch`], and stage by stage with timings).

use super::chunks::chunks;
use super::{GpuDentInfo, GpuDenter};
use crate::dent::{DentJob, DentPlan};
use crate::gpu::normals::NormalsParams;
use crate::gpu::recorder::{KernelTimes, Recorder};
use crate::gpu::{GpuBatchError, GpuContext, GpuError};

impl GpuDenter {
    /// Dents the resident targets by every job (`job.target` indexes the targets given to
    /// [`new`](Self::new)): plans on the CPU (all cores), then every kernel once per chunk of the
    /// batch, chunks sized to the device's binding limit. Dents on the same target apply in
    /// submission order. A dent whose profile vanishes on its grid (σ or d far outside the
    /// projectile's scale) leaves its target unchanged, where the CPU pipeline reports
    /// [`DentError::EmptyProfile`](crate::DentError::EmptyProfile): telling would need a read-back.
    ///
    /// Submits without waiting for the GPU to finish; the read-backs wait.
    ///
    /// # Errors
    /// [`GpuBatchError::Job`] naming the first invalid dent (nothing is submitted then);
    /// [`GpuBatchError::Gpu`] for device errors: [`GpuError::DeviceLost`] for a device lost
    /// before or while the batch is recorded and submitted (the caller's meshes are never
    /// touched by the GPU path).
    pub fn dent_batch(&mut self, jobs: &[DentJob<'_>]) -> Result<Vec<GpuDentInfo>, GpuBatchError> {
        self.context.check_alive()?;
        let mut encoder = self.context.device.create_command_encoder(&Default::default());
        // A device lost while recording shows up as a validation error of some command; name
        // the real cause.
        let info = self.record_batch(&mut encoder, jobs).map_err(|error| match error {
            GpuBatchError::Gpu(gpu) => GpuBatchError::Gpu(self.context.lost_or(gpu)),
            job => job,
        })?;
        let context = &self.context;
        context
            .scoped("dent batch submit", || context.queue.submit([encoder.finish()]))
            .map_err(|e| context.lost_or(e))?;
        context.check_alive()?;
        Ok(info)
    }

    /// Records the batch [`dent_batch`](Self::dent_batch) runs into the caller's `encoder`,
    /// without submitting or polling: the targets change when the caller submits the encoder's
    /// commands (uploads of the batch's small buffers go through `queue.write_buffer` and land
    /// before that submission). Record several batches before one submission and they apply in
    /// recording order.
    ///
    /// # Errors
    /// As [`dent_batch`](Self::dent_batch). An invalid job is found before anything is recorded;
    /// a device limit met while recording leaves part of the batch in `encoder`, so after an
    /// error drop the encoder instead of submitting it (the targets then stay as they were).
    /// Resource creation is checked here inside error scopes; what wgpu only validates when the
    /// caller finishes the encoder is checked beforehand against the device's limits (grid
    /// sizes, dispatch sizes, binding sizes), so it should not reach the application's handler.
    pub fn record_batch(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        jobs: &[DentJob<'_>],
    ) -> Result<Vec<GpuDentInfo>, GpuBatchError> {
        let plans = self.plan(jobs)?;
        let mut sink = Sink::Caller(encoder);
        self.context.scoped("dent batch", || self.encode_batch(&plans, jobs, &mut sink))??;
        Ok(infos(&plans))
    }

    /// [`dent_batch`](Self::dent_batch), submitting and waiting after every kernel stage to time
    /// it (slower than `dent_batch`, which records a chunk's stages into one submission): GPU
    /// time from timestamp queries when [`GpuContext::timestamps`] is set, else wall time.
    ///
    /// # Errors
    /// As [`dent_batch`](Self::dent_batch).
    pub fn dent_batch_timed(&mut self, jobs: &[DentJob<'_>]) -> Result<KernelTimes, GpuBatchError> {
        let mut times = KernelTimes::new();
        let plans = self.plan(jobs)?;
        self.context.check_alive()?;
        let mut sink = Sink::Own { timings: Some(&mut times), pending: Vec::new() };
        self.context.scoped("dent batch", || self.encode_batch(&plans, jobs, &mut sink))??;
        if let Sink::Own { pending, .. } = sink {
            self.context.queue.submit(pending);
        }
        self.context.check_alive()?;
        Ok(times)
    }

    /// Records the whole batch into `sink`: clear the moved flags, then per chunk (cut to the
    /// device's limits) the map kernels and the displacement, then the normals of every target
    /// a job names. A timing sink submits what came before each chunk and the normals.
    fn encode_batch(&self, plans: &[DentPlan], jobs: &[DentJob<'_>], sink: &mut Sink<'_>) -> Result<(), GpuError> {
        let context = &self.context;
        let mut clear = sink.recorder(context);
        self.kernels.displace.encode_clear_moved(context, clear.encoder(), &self.positions)?;
        let done = clear.finish();
        sink.push(done);
        let mut arena = self.arena();
        for chunk in chunks(plans, jobs, context) {
            sink.flush(context);
            let chunk_jobs: Vec<&DentJob> = chunk.clone().map(|k| &jobs[k]).collect();
            let chunk_plans: Vec<&DentPlan> = chunk.clone().map(|k| &plans[k]).collect();
            let mut rec = sink.recorder(context);
            let maps = self.encode_maps(&mut rec, &mut arena, &chunk_jobs, &chunk_plans, false)?;
            self.encode_displace(&mut rec, &chunk_jobs, &chunk_plans, &maps)?;
            let done = rec.finish();
            sink.push(done);
        }
        let mut touched = vec![false; self.targets.len()];
        jobs.iter().for_each(|j| touched[j.target] = true);
        let normals: Vec<NormalsParams> =
            (0..self.targets.len()).filter(|&t| touched[t]).map(|t| self.normals_params(t)).collect();
        sink.flush(context);
        let mut rec = sink.recorder(context);
        let (positions, faces, adjacency) = (&self.positions, &self.faces, &self.adjacency);
        self.kernels.normals.encode(context, rec.encoder(), &normals, positions, faces, adjacency, &self.normals)?;
        rec.stage("normals")?;
        let done = rec.finish();
        sink.push(done);
        Ok(())
    }
}

/// What each planned dent of a batch was planned as.
fn infos(plans: &[DentPlan]) -> Vec<GpuDentInfo> {
    plans
        .iter()
        .map(|p| GpuDentInfo {
            theta_deg: p.frame.theta_deg(),
            resolution: p.zbuffer_grid.res,
            map_resolution: p.map_grid.res,
            cell_size: p.zbuffer_grid.cell_size,
        })
        .collect()
}

/// Where [`GpuDenter::encode_batch`] records: the caller's encoder, or command buffers of its own
/// (submitted stage by stage when timing, else by the caller of `encode_batch`).
enum Sink<'s> {
    Caller(&'s mut wgpu::CommandEncoder),
    Own { timings: Option<&'s mut KernelTimes>, pending: Vec<wgpu::CommandBuffer> },
}

impl Sink<'_> {
    fn recorder<'r>(&'r mut self, context: &'r GpuContext) -> Recorder<'r> {
        match self {
            Sink::Caller(encoder) => Recorder::caller(context, encoder),
            Sink::Own { timings, .. } => Recorder::new(context, timings.as_deref_mut()),
        }
    }

    fn push(&mut self, buffer: Option<wgpu::CommandBuffer>) {
        if let (Sink::Own { pending, .. }, Some(buffer)) = (self, buffer) {
            pending.push(buffer);
        }
    }

    /// When timing, submits what is pending (so the next stage's time is its own).
    fn flush(&mut self, context: &GpuContext) {
        if let Sink::Own { timings: Some(_), pending } = self {
            context.queue.submit(pending.drain(..));
        }
    }
}
