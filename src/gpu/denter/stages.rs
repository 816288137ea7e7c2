//! A batch with every stage of [`DentParams`](crate::DentParams) on resident targets
//! ([`GpuDenter::dent_batch`]), giving what the CPU batch gives:
//!
//! 1. Each job is planned on the host from the host's copy of its target, as the CPU batch plans
//!    it (the mean edge sets the automatic grid), and sent with that grid side.
//! 2. Refinement runs on the host's copy (`refine_planned`, from those plans); a refined target
//!    is written into its slice of the device buffers, or every target is laid out afresh when
//!    it outgrows it (`resident.rs`).
//! 3. The dents run in rounds (each target's first dents, then its second ones…), so each sees
//!    its target as the earlier ones left it. Per round: the falloffs that could fold a wall
//!    are fitted on the host (their maps built and read back first, so such a dent builds its
//!    map twice; the default logistic falloff never needs it); the kernels build the round's
//!    maps and displace; the `moved` kernel compacts the vertices the kernels moved and only
//!    those come back; the intersection guard and the volume rim run on the host's copy
//!    (`finish_displaced`, the CPU pipeline's own functions), and the vertices they change are
//!    written back before the next round.
//! 4. The normals around what moved are refreshed on the device; the host's copy takes the new
//!    positions and recomputes its normals around the same vertices.
//!
//! A failure anywhere puts every target back as it was, on the device and on the host.

use std::time::Instant;

use glam::Vec3;

use super::GpuDenter;
use super::batch::Sink;
use crate::dent::{
    BatchError, BatchOutcome, DentJob, DentPlan, DentReport, FittedFalloff, Refine, RefinedTargets,
    falloff_may_need_fit, finish_displaced, fit_to_target, plan_jobs, refine_planned,
};
use crate::gpu::moved::{MovedVertices, PendingMoved, wait_all};
use crate::gpu::{GpuBatchError, GpuError};
use crate::mesh::TriMesh;

/// A round's fitted falloffs (per job of the round) and the bytes read back to fit them.
struct Fitted {
    falloffs: Vec<Option<FittedFalloff>>,
    bytes: u64,
}

/// One dented target during a batch: its current positions and the vertices moved so far.
struct TargetState {
    positions: Vec<Vec3>,
    moved: Vec<bool>,
}

impl GpuDenter {
    /// Dents the resident targets by every job (`job.target` indexes the targets given to
    /// [`new`](Self::new)) with every stage its [`DentParams`](crate::DentParams) asks for
    /// (refinement, the fitted falloff, the intersection guard, the volume rim), as the CPU batch
    /// ([`dent_batch_tracked`](crate::dent::dent_batch_tracked)) does: the same refinement,
    /// positions within the kernels' tolerance, the same `limited_to` within the guard's
    /// bisection step. Reports come back in job order; per target, the vertices that moved and
    /// what refinement appended. Waits for the GPU.
    ///
    /// Reads back only the vertices the kernels moved (16 bytes each); a target that refinement
    /// grew past its slice makes every target be laid out again, which moves
    /// [`vertex_buffer`](Self::vertex_buffer) to a new buffer (fetch it again after a batch
    /// whose outcome [`topology_changed`](BatchOutcome::topology_changed)).
    ///
    /// # Errors
    /// [`GpuBatchError::Job`] naming the first bad dent (in job order);
    /// [`GpuBatchError::Gpu`] for device errors, including [`GpuError::OverLimit`] for a refined
    /// target past the device's buffer limits and [`GpuError::DeviceLost`] for a device lost
    /// between stages. Every target is as it was then, on the host and (unless lost) on the
    /// device.
    pub fn dent_batch(&mut self, jobs: &[DentJob<'_>]) -> Result<BatchOutcome, GpuBatchError> {
        self.context.check_alive()?;
        self.catch_up()?;
        (self.vertices_read_back, self.bytes_read_back, self.waited_s) = (0, 0, 0.0);
        let meshes: Vec<&TriMesh> = self.targets.iter().map(|r| &r.mesh).collect();
        let (edges, plans) = plan_jobs(&meshes, jobs)?;
        let refining: Vec<Option<&DentPlan>> =
            plans.iter().zip(jobs).map(|(plan, job)| (job.params.refine != Refine::Off).then_some(plan)).collect();
        let RefinedTargets { meshes: refined, refinements, reports: refine_reports } =
            refine_planned(&meshes, &edges, jobs, &refining)?;
        let first_new: Vec<usize> = self.targets.iter().map(|r| r.mesh.vertex_count()).collect();
        let mut undo = Vec::new();
        for (t, mesh) in refined.into_iter().enumerate() {
            if let Some(mesh) = mesh {
                undo.push((t, std::mem::replace(&mut self.targets[t].mesh, mesh)));
            }
        }
        let grown: Vec<usize> = undo.iter().map(|(t, _)| *t).collect();
        let dented = self.grow(&grown).map_err(GpuBatchError::Gpu).and_then(|()| self.rounds(jobs, &plans, &first_new));
        let (states, mut reports) = match dented {
            Ok(done) => done,
            Err(error) => {
                self.put_back(undo, jobs);
                return Err(match error {
                    GpuBatchError::Gpu(gpu) => GpuBatchError::Gpu(self.context.lost_or(gpu)),
                    other => other,
                });
            }
        };
        let moved = self.commit(states);
        // As on the CPU: the dent's own warnings, then its refinement's.
        for (report, refine) in reports.iter_mut().zip(refine_reports) {
            report.refined_vertices = refine.refined_vertices;
            report.refined_triangles = refine.refined_triangles;
            report.warnings.extend(refine.warnings);
        }
        Ok(BatchOutcome { reports, moved, refined: refinements })
    }

    /// Reads back every target that kernels recorded into a caller's encoder moved, so the
    /// host's copies are current before anything is planned or laid out from them.
    pub(super) fn catch_up(&mut self) -> Result<(), GpuError> {
        for t in 0..self.targets.len() {
            if !self.targets[t].behind {
                continue;
            }
            let (positions, normals) = (self.read_positions(t)?, self.read_normals(t)?);
            let faces = self.targets[t].mesh.faces().to_vec();
            let mesh = TriMesh::with_normals(positions, faces, normals).map_err(|e| GpuError::Validation {
                label: "read back resident target".into(),
                message: e.to_string(),
            })?;
            let target = &mut self.targets[t];
            target.mean_edge = mesh.mean_edge_length();
            (target.mesh, target.behind) = (mesh, false);
        }
        Ok(())
    }

    /// Writes the refined targets `grown` (their host copies already refined) to the device:
    /// into their slices where they fit, else by laying every target out afresh.
    fn grow(&mut self, grown: &[usize]) -> Result<(), GpuError> {
        let mut fits = true;
        for &t in grown {
            let target = &mut self.targets[t];
            target.grows = true;
            target.mean_edge = target.mesh.mean_edge_length();
            fits &= target.fits(&target.mesh);
        }
        if fits {
            for &t in grown {
                self.buffers.upload(&self.context, &self.targets[t])?;
            }
        } else {
            self.lay_out()?;
        }
        Ok(())
    }

    /// After a failed batch: the host's copies of the refined targets back to `undo`'s meshes,
    /// and every target `jobs` dent written back to the device from its copy (which the batch
    /// only changes once it has succeeded).
    fn put_back(&mut self, undo: Vec<(usize, TriMesh)>, jobs: &[DentJob<'_>]) {
        for (t, mesh) in undo {
            self.targets[t].mean_edge = mesh.mean_edge_length();
            self.targets[t].mesh = mesh;
        }
        if self.context.check_alive().is_err() {
            return;
        }
        let dented = self.dented_targets(jobs);
        for (t, target) in self.targets.iter().enumerate() {
            // A target the failed layout never placed has no room yet: nothing on the device to
            // mend. A device failing now is reported by the next batch.
            if dented[t] && target.fits(&target.mesh) && self.buffers.upload(&self.context, target).is_err() {
                return;
            }
        }
    }

    /// Runs the dents round by round (`first_new[t]`: target `t`'s first vertex added by
    /// refinement); per target, its state after the batch (`None`: no job dents it); per job, its
    /// report.
    fn rounds(
        &mut self,
        jobs: &[DentJob<'_>],
        plans: &[DentPlan],
        first_new: &[usize],
    ) -> Result<(Vec<Option<TargetState>>, Vec<DentReport>), GpuBatchError> {
        // New vertices count as moved, as on the CPU: a caller's collider does not have them yet.
        let mut states: Vec<Option<TargetState>> = (0..self.targets.len())
            .map(|t| {
                let mesh = &self.targets[t].mesh;
                jobs.iter().any(|j| j.target == t).then(|| TargetState {
                    positions: mesh.positions().to_vec(),
                    moved: (0..mesh.vertex_count()).map(|v| v >= first_new[t]).collect(),
                })
            })
            .collect();
        let mut reports = vec![DentReport::default(); jobs.len()];
        for (r, round) in rounds(jobs, self.targets.len()).into_iter().enumerate() {
            let waiting = Instant::now();
            let fitted = self.fit_falloffs(&round, jobs, plans, &states)?;
            if fitted.bytes > 0 {
                self.waited_s += waiting.elapsed().as_secs_f64();
            }
            self.bytes_read_back += fitted.bytes;
            let fitted = fitted.falloffs;
            let round_jobs: Vec<DentJob<'_>> = round
                .iter()
                .zip(&fitted)
                .map(|(&j, fit)| {
                    let mut job = jobs[j].clone();
                    if let Some(fit) = fit {
                        job.params.attenuation = fit.attenuation.clone();
                    }
                    job
                })
                .collect();
            let round_plans: Vec<&DentPlan> = round.iter().map(|&j| &plans[j]).collect();
            let (moved, bytes, waited) = self.displace_round(&round_jobs, &round_plans, r == 0)?;
            self.waited_s += waited;
            self.vertices_read_back += moved.iter().map(|m| m.indices.len()).sum::<usize>();
            self.bytes_read_back += bytes;
            for ((&j, fit), moved) in round.iter().zip(fitted).zip(moved) {
                let t = jobs[j].target;
                let state = states[t].as_mut().expect("a dented target");
                let mut after = state.positions.clone();
                for (&v, &p) in moved.indices.iter().zip(&moved.positions) {
                    after[v as usize] = p;
                }
                let mesh = &self.targets[t].mesh;
                let done = finish_displaced(
                    &state.positions,
                    after,
                    mesh.faces(),
                    mesh.normals(),
                    &plans[j],
                    &jobs[j].params,
                    fit,
                )
                .map_err(|error| BatchError { job: j, error })?;
                state.moved.iter_mut().zip(&done.moved).for_each(|(m, &d)| *m |= d);
                // Refinement's new vertices are flagged moved from the first round on, so the
                // device refreshes their normals as the host does.
                let new = if r == 0 { first_new[t]..state.moved.len() } else { 0..0 };
                self.write_back(t, (&moved.indices, new), &state.positions, &done.positions, &state.moved)?;
                state.positions = done.positions;
                reports[j] = done.report;
            }
        }
        self.refresh_normals(jobs)?;
        Ok((states, reports))
    }

    /// The round's falloffs fitted on the host where they could fold a wall (`None`: the job's
    /// own, which cannot), and the bytes of the maps read back for them.
    fn fit_falloffs(
        &self,
        round: &[usize],
        jobs: &[DentJob<'_>],
        plans: &[DentPlan],
        states: &[Option<TargetState>],
    ) -> Result<Fitted, GpuBatchError> {
        let mut fitted = Fitted { falloffs: vec![None; round.len()], bytes: 0 };
        let to_fit: Vec<usize> =
            (0..round.len()).filter(|&k| falloff_may_need_fit(&plans[round[k]], &jobs[round[k]].params)).collect();
        if to_fit.is_empty() {
            return Ok(fitted);
        }
        let fit_jobs: Vec<DentJob<'_>> = to_fit.iter().map(|&k| jobs[round[k]].clone()).collect();
        let fit_plans: Vec<DentPlan> = to_fit.iter().map(|&k| plans[round[k]].clone()).collect();
        let maps = self.stages_from_plans(&fit_jobs, &fit_plans)?;
        for (&k, stages) in to_fit.iter().zip(maps) {
            let job = &jobs[round[k]];
            let positions = &states[job.target].as_ref().expect("a dented target").positions;
            let faces = self.targets[job.target].mesh.faces();
            let words = stages.zbuffer.len() + stages.envelope.len() + stages.smoothed.len() + 4 * stages.map.len();
            fitted.bytes += 4 * words as u64;
            let map = stages.into_stages().map;
            fitted.falloffs[k] = Some(fit_to_target(&map, positions, faces, &job.params.attenuation));
        }
        Ok(fitted)
    }

    /// Builds the round's maps and displaces its targets (the moved flags cleared first in the
    /// batch's first round), then reads back, per job, the vertices its target's flags mark;
    /// with the bytes read and the seconds spent waiting for them.
    fn displace_round(
        &self,
        jobs: &[DentJob<'_>],
        plans: &[&DentPlan],
        first: bool,
    ) -> Result<(Vec<MovedVertices>, u64, f64), GpuBatchError> {
        let context = &self.context;
        let recorded = context.scoped("dent batch", || -> Result<_, GpuError> {
            let mut encoder = context.device.create_command_encoder(&Default::default());
            self.encode_dents(plans, jobs, &mut Sink::Caller(&mut encoder), first)?;
            let pending: Vec<PendingMoved> =
                jobs.iter().map(|j| self.record_moved(&mut encoder, j.target)).collect::<Result<_, _>>()?;
            context.queue.submit([encoder.finish()]);
            Ok(pending)
        });
        let mut pending = recorded.and_then(|inner| inner)?;
        let waiting = Instant::now();
        let moved = wait_all(context, &mut pending)?;
        let waited = waiting.elapsed().as_secs_f64();
        Ok((moved, pending.iter().map(PendingMoved::bytes_read).sum(), waited))
    }

    /// Writes back what the round left of target `t` in `finished`: every vertex the kernels
    /// moved (`read.0`), the vertices `read.1` (new ones, to flag), and those the host stages
    /// moved (`finished` differs from `before`, the positions before the round; elsewhere the
    /// kernels' positions are `before`'s), each with its moved flag from `moved`, in runs of
    /// consecutive vertices.
    fn write_back(
        &self,
        t: usize,
        read: (&[u32], std::ops::Range<usize>),
        before: &[Vec3],
        finished: &[Vec3],
        moved: &[bool],
    ) -> Result<(), GpuError> {
        let mut changed: Vec<usize> = read.0.iter().map(|&v| v as usize).chain(read.1).collect();
        changed.extend((0..finished.len()).filter(|&v| finished[v] != before[v]));
        changed.sort_unstable();
        changed.dedup();
        let target = &self.targets[t];
        self.context.scoped("dent batch write-back", || {
            let mut start = 0;
            while start < changed.len() {
                let mut end = start + 1;
                while end < changed.len() && changed[end] == changed[end - 1] + 1 {
                    end += 1;
                }
                let (first, last) = (changed[start], changed[end - 1] + 1);
                let (positions, flags) = (&finished[first..last], &moved[first..last]);
                self.buffers.write_positions(&self.context, target, first, positions, flags);
                start = end;
            }
        })
    }

    /// Refreshes, on the device, the normals around every vertex the batch moved on the targets
    /// `jobs` dent.
    fn refresh_normals(&self, jobs: &[DentJob<'_>]) -> Result<(), GpuError> {
        let context = &self.context;
        context.scoped("dent batch normals", || -> Result<(), GpuError> {
            let mut encoder = context.device.create_command_encoder(&Default::default());
            self.encode_normals(jobs, &mut Sink::Caller(&mut encoder))?;
            context.queue.submit([encoder.finish()]);
            Ok(())
        })?
    }

    /// The host's copies take the batch's positions and recompute their normals around what
    /// moved; per target, the moved vertices' indices (ascending).
    fn commit(&mut self, states: Vec<Option<TargetState>>) -> Vec<Vec<u32>> {
        let mut moved_lists = vec![Vec::new(); self.targets.len()];
        for (t, state) in states.into_iter().enumerate() {
            let Some(TargetState { positions, moved }) = state else { continue };
            let target = &mut self.targets[t];
            target.mesh.positions_mut().copy_from_slice(&positions);
            target.mesh.recompute_normals_near(&moved);
            target.mean_edge = target.mesh.mean_edge_length();
            moved_lists[t] = moved.iter().enumerate().filter(|(_, m)| **m).map(|(v, _)| v as u32).collect();
        }
        moved_lists
    }
}

/// The jobs in rounds: round `r` holds the `r`-th job of every target, in job order, so no
/// round dents a target twice and each target's dents keep their order.
fn rounds(jobs: &[DentJob<'_>], targets: usize) -> Vec<Vec<usize>> {
    let mut seen = vec![0usize; targets];
    let mut rounds: Vec<Vec<usize>> = Vec::new();
    for (j, job) in jobs.iter().enumerate() {
        let r = seen[job.target];
        seen[job.target] += 1;
        if r == rounds.len() {
            rounds.push(Vec::new());
        }
        rounds[r].push(j);
    }
    rounds
}
