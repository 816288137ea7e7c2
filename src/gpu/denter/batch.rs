//! Running a batch: recording it into the caller's encoder ([`GpuDenter::record_batch`]), or
//! recording and submitting it ([`GpuDenter::dent_batch`], and stage by stage with timings).

use std::borrow::Borrow;

use super::chunks::chunks;
use super::{GpuDentInfo, GpuDenter};
use crate::dent::{DentJob, DentPlan, falloff_may_need_fit};
use crate::gpu::normals::NormalsParams;
use crate::gpu::recorder::{KernelTimes, Recorder};
use crate::gpu::{GpuBatchError, GpuContext, GpuError};

impl GpuDenter {
    /// Records the kernels of a batch of the paper's dents into the caller's `encoder`, without
    /// submitting or waiting, for a frame loop: every job is planned on the CPU (all cores), then
    /// every kernel runs once per chunk of the batch (cut to the device's limits) and the normals
    /// around what moved are refreshed. Dents on the same target apply in submission order; the
    /// targets change when the caller submits the encoder's commands (the batch's small buffers
    /// go through `queue.write_buffer` and land before that submission). Record several batches
    /// before one submission and they apply in recording order.
    ///
    /// A recording cannot wait for the GPU, so it takes only dents that need no host stage
    /// ([`DentParams::without_host_stages`](crate::DentParams::without_host_stages), with a
    /// falloff that cannot fold a wall); [`dent_batch`](Self::dent_batch) runs every stage. The
    /// host's copy of a target dented here is read back once, the next time the host needs it:
    /// submit the encoder before the next call on this denter that reads the host copies
    /// ([`mesh`](Self::mesh), [`dent_batch`](Self::dent_batch), adding, replacing or removing a
    /// target), or that read finds the targets as they were and the recorded dents are lost.
    /// A dent whose profile vanishes on its grid (σ or d far outside the projectile's scale)
    /// leaves its target unchanged, where the CPU pipeline reports
    /// [`DentError::EmptyProfile`](crate::DentError::EmptyProfile): telling would need a
    /// read-back.
    ///
    /// # Errors
    /// [`GpuBatchError::Job`] naming the first invalid dent, [`GpuBatchError::HostStages`] the
    /// first that needs a host stage (nothing is recorded then); [`GpuBatchError::Gpu`] for
    /// device errors. A device limit met while recording leaves part of the batch in `encoder`,
    /// so after an error drop the encoder instead of submitting it (the targets then stay as
    /// they were). Resource creation is checked here inside error scopes; what wgpu only
    /// validates when the caller finishes the encoder is checked beforehand against the
    /// device's limits (grid sizes, dispatch sizes, binding sizes), so it should not reach the
    /// application's handler.
    pub fn record_batch(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        jobs: &[DentJob<'_>],
    ) -> Result<Vec<GpuDentInfo>, GpuBatchError> {
        let plans = self.kernel_plans(jobs)?;
        let mut sink = Sink::Caller(encoder);
        self.context.scoped("dent batch", || self.encode_batch(&plans, jobs, &mut sink))??;
        self.fall_behind(jobs);
        Ok(infos(&plans))
    }

    kernels_fn! {
        /// [`record_batch`](Self::record_batch) on the denter's own command buffers, submitting and
        /// waiting after every kernel stage to time it: GPU time from timestamp queries when
        /// [`GpuContext::timestamps`] is set, else wall time.
        ///
        /// # Errors
        /// As [`record_batch`](Self::record_batch).
        fn dent_batch_timed(&mut self, jobs: &[DentJob<'_>]) -> Result<KernelTimes, GpuBatchError> {
            let mut times = KernelTimes::new();
            let plans = self.kernel_plans(jobs)?;
            self.context.check_alive()?;
            let mut sink = Sink::Own { timings: Some(&mut times), pending: Vec::new() };
            self.context.scoped("dent batch", || self.encode_batch(&plans, jobs, &mut sink))??;
            if let Sink::Own { pending, .. } = sink {
                self.context.queue.submit(pending);
            }
            self.fall_behind(jobs);
            self.context.check_alive()?;
            Ok(times)
        }
    }

    /// Plans every job (all cores) and checks that none needs a host stage.
    fn kernel_plans(&self, jobs: &[DentJob<'_>]) -> Result<Vec<DentPlan>, GpuBatchError> {
        let plans = self.plan(jobs)?;
        for (job, (j, plan)) in jobs.iter().zip(&plans).enumerate() {
            let mut stages = j.params.host_stages();
            if falloff_may_need_fit(plan, &j.params) {
                stages.push("a falloff fitted to the wall's thickness");
            }
            if !stages.is_empty() {
                return Err(GpuBatchError::HostStages { job, stages: stages.join(", ") });
            }
        }
        Ok(plans)
    }

    /// Marks the targets `jobs` dent as moved behind the host's copy.
    fn fall_behind(&mut self, jobs: &[DentJob<'_>]) {
        jobs.iter().for_each(|j| self.targets[j.target].behind = true);
    }

    /// Records the whole batch into `sink`: clear the moved flags, then per chunk (cut to the
    /// device's limits) the map kernels and the displacement, then the normals of every target
    /// a job names. A timing sink submits what came before each chunk and the normals.
    fn encode_batch(&self, plans: &[DentPlan], jobs: &[DentJob<'_>], sink: &mut Sink<'_>) -> Result<(), GpuError> {
        self.encode_dents(plans, jobs, sink, true)?;
        self.encode_normals(jobs, sink)
    }

    /// Records, into `sink`, the clearing of the moved flags (when `clear_moved`), then per chunk
    /// (cut to the device's limits) the map kernels and the displacement of `jobs` planned as
    /// `plans`.
    pub(super) fn encode_dents<P: Borrow<DentPlan>>(
        &self,
        plans: &[P],
        jobs: &[DentJob<'_>],
        sink: &mut Sink<'_>,
        clear_moved: bool,
    ) -> Result<(), GpuError> {
        let context = &self.context;
        if clear_moved {
            let mut clear = sink.recorder(context);
            self.kernels.displace.encode_clear_moved(context, clear.encoder(), &self.buffers.positions)?;
            let done = clear.finish();
            sink.push(done);
        }
        let mut arena = self.arena();
        for chunk in chunks(plans, jobs, context) {
            sink.flush(context);
            let chunk_jobs: Vec<&DentJob> = chunk.clone().map(|k| &jobs[k]).collect();
            let chunk_plans: Vec<&DentPlan> = chunk.clone().map(|k| plans[k].borrow()).collect();
            let mut rec = sink.recorder(context);
            let maps = self.encode_maps(&mut rec, &mut arena, &chunk_jobs, &chunk_plans, false)?;
            self.encode_displace(&mut rec, &chunk_jobs, &chunk_plans, &maps)?;
            let done = rec.finish();
            sink.push(done);
        }
        Ok(())
    }

    /// Records, into `sink`, the normals' refresh around the moved vertices of every target a
    /// job of `jobs` names.
    pub(super) fn encode_normals(&self, jobs: &[DentJob<'_>], sink: &mut Sink<'_>) -> Result<(), GpuError> {
        let context = &self.context;
        let dented = self.dented_targets(jobs);
        let normals: Vec<NormalsParams> =
            (0..self.targets.len()).filter(|&t| dented[t]).map(|t| self.normals_params(t)).collect();
        sink.flush(context);
        let mut rec = sink.recorder(context);
        let b = &self.buffers;
        self.kernels.normals.encode(
            context,
            rec.encoder(),
            &normals,
            &b.positions,
            &b.faces,
            &b.adjacency,
            &b.normals,
        )?;
        rec.stage("normals")?;
        let done = rec.finish();
        sink.push(done);
        Ok(())
    }

    /// Per target, whether a job of `jobs` dents it.
    pub(super) fn dented_targets(&self, jobs: &[DentJob<'_>]) -> Vec<bool> {
        let mut dented = vec![false; self.targets.len()];
        jobs.iter().for_each(|j| dented[j.target] = true);
        dented
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
pub(super) enum Sink<'s> {
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
