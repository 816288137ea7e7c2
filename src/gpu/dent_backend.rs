//! Dents on the GPU for the world-free damage API: a [`DentBackend`] keyed by the caller's ids
//! whose targets stay resident on the device ([`GpuDenter`]) between steps. A target whose mesh the GPU has not seen (a new dentable
//! collider, or a mesh changed outside the backend) makes it upload every known target again;
//! otherwise a batch uploads nothing but its jobs and reads back the dented targets.
//!
//! The same [`DentParams`](crate::DentParams) give the same dent as on the CPU
//! ([`dent_batch_tracked`](crate::dent::dent_batch_tracked)): the GPU kernels build the maps and
//! displace, and the host runs every other stage with the CPU pipeline's functions, in its order.
//! - Each job is planned on the host from the target as given (the CPU batch's automatic
//!   resolution) and sent with that grid side fixed; the refine stage
//!   ([`refine_targets`](crate::dent::refine_targets)'s, from those plans) runs first, and a
//!   target it refines is uploaded again (with every other, as for a changed mesh).
//! - A falloff steep enough to fold a wall under its map (not the default logistic one) is fitted
//!   to the target's thickness before the kernels displace with it: its map is built on the GPU
//!   and read back first, so such a dent builds its map twice.
//! - After each displacement the dented target is read back, and the intersection guard, the
//!   volume rim of [`VolumeMode::Preserve`](crate::dent::VolumeMode::Preserve), the guard again
//!   and the volume measurement run on the host; positions they change are written back to the
//!   device. Several dents on one target run in rounds (each target's first dents, then its
//!   second ones…), one kernel batch and read-back per round, so each dent's stages see the
//!   target as the earlier dents left it, as on the CPU.

use std::collections::HashMap;
use std::hash::Hash;

use glam::Vec3;

use super::{GpuBatchError, GpuContext, GpuDenter};
use crate::dent::{
    BatchError, BatchOutcome, DentBackend, DentError, DentJob, DentPlan, FittedFalloff, Refine, Resolution,
    falloff_may_need_fit, finish_displaced, fit_to_target, plan_jobs, refine_planned,
};
use crate::mesh::TriMesh;

/// Batches on a GPU, targets resident there, keyed by the caller's ids.
pub struct GpuBackend<K> {
    context: GpuContext,
    denter: Option<GpuDenter>,
    slots: HashMap<K, usize>,
    meshes: Vec<TriMesh>,
}

impl<K> std::fmt::Debug for GpuBackend<K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuBackend").field("resident", &self.meshes.len()).finish()
    }
}

impl<K: Copy + Eq + Hash> GpuBackend<K> {
    /// A backend on `context` (e.g. [`shared_context`](super::shared_context), or an
    /// application's device through [`GpuContext::from_device`]); nothing resident yet.
    pub fn new(context: &GpuContext) -> Self {
        Self { context: context.clone(), denter: None, slots: HashMap::new(), meshes: Vec::new() }
    }

    /// Forgets `key` (its mesh leaves the device at the next upload).
    pub fn forget(&mut self, key: K) {
        if let Some(slot) = self.slots.remove(&key) {
            self.meshes.remove(slot);
            self.slots.values_mut().filter(|s| **s > slot).for_each(|s| *s -= 1);
            self.denter = None;
        }
    }

    /// Makes `meshes` (current meshes; `keys[i]` the id of `meshes[i]`) resident now, uploading once, so that their
    /// first batch uploads nothing but its jobs.
    ///
    /// # Errors
    /// [`DentError::Backend`] when the upload fails.
    pub fn make_resident(&mut self, keys: &[K], meshes: &[TriMesh]) -> Result<(), DentError> {
        self.resident(keys, &meshes.iter().collect::<Vec<_>>()).map(|_| ())
    }

    /// Makes every target of the batch resident with its current mesh; the slot of each.
    fn resident(&mut self, keys: &[K], meshes: &[&TriMesh]) -> Result<Vec<usize>, DentError> {
        // A mesh whose faces changed (refined) is resident again even if its positions match.
        let same = |old: &TriMesh, new: &TriMesh| old.positions() == new.positions() && old.faces() == new.faces();
        let mut stale = self.denter.is_none();
        for (key, &mesh) in keys.iter().zip(meshes) {
            match self.slots.get(key) {
                Some(&slot) if same(&self.meshes[slot], mesh) => {}
                Some(&slot) => {
                    self.meshes[slot] = mesh.clone();
                    stale = true;
                }
                None => {
                    self.slots.insert(*key, self.meshes.len());
                    self.meshes.push(mesh.clone());
                    stale = true;
                }
            }
        }
        if stale {
            self.denter = None;
            let denter = GpuDenter::new(&self.context, &self.meshes).map_err(|e| DentError::Backend(e.to_string()))?;
            self.denter = Some(denter);
        }
        Ok(keys.iter().map(|k| self.slots[k]).collect())
    }
}

impl<K: Copy + Eq + Hash> DentBackend<K> for GpuBackend<K> {
    fn dent_batch(
        &mut self,
        keys: &[K],
        targets: &mut [TriMesh],
        jobs: &[DentJob<'_>],
    ) -> Result<BatchOutcome, BatchError> {
        // Stage 1 on the host: plan every job, then refine copies of the targets where their
        // dents need it.
        let (edges, plans) = plan_jobs(targets, jobs)?;
        let refining: Vec<Option<&DentPlan>> =
            plans.iter().zip(jobs).map(|(plan, job)| (job.params.refine != Refine::Off).then_some(plan)).collect();
        let refined = refine_planned(targets, &edges, jobs, &refining)?;
        let current: Vec<&TriMesh> =
            targets.iter().zip(&refined.meshes).map(|(old, new)| new.as_ref().unwrap_or(old)).collect();
        let slots = self.resident(keys, &current).map_err(|error| BatchError { job: 0, error })?;
        let first_new: Vec<usize> = targets.iter().map(TriMesh::vertex_count).collect();
        let dented = self.dent_resident(&current, &first_new, &slots, jobs, &plans);
        let (states, mut reports) = match dented {
            Ok(done) => done,
            Err(e) => {
                // The device may hold a half-applied batch: upload again next time.
                self.denter = None;
                return Err(e);
            }
        };
        // Each target's mesh, built before any is written so that a failure changes none.
        let mut built = Vec::with_capacity(targets.len());
        for (t, state) in states.into_iter().enumerate() {
            let Some(TargetState { positions, moved }) = state else {
                built.push(None);
                continue;
            };
            // Normals change only around what moved, as on the CPU.
            let (faces, normals) = (current[t].faces().to_vec(), current[t].normals().to_vec());
            let mut mesh = TriMesh::with_normals(positions, faces, normals).map_err(|e| {
                self.denter = None;
                let job = jobs.iter().position(|j| j.target == t).unwrap_or(0);
                BatchError { job, error: DentError::Backend(format!("read back mesh: {e}")) }
            })?;
            mesh.recompute_normals_near(&moved);
            built.push(Some((mesh, moved)));
        }
        let mut moved = vec![Vec::new(); targets.len()];
        for (t, done) in built.into_iter().enumerate() {
            let Some((mesh, flags)) = done else { continue };
            moved[t] = flags.iter().enumerate().filter(|(_, m)| **m).map(|(v, _)| v as u32).collect();
            self.meshes[slots[t]] = mesh.clone();
            targets[t] = mesh;
        }
        // As on the CPU: the dent's own warnings, then its refinement's.
        for (report, refine) in reports.iter_mut().zip(refined.reports) {
            report.refined_vertices = refine.refined_vertices;
            report.refined_triangles = refine.refined_triangles;
            report.warnings.extend(refine.warnings);
        }
        Ok(BatchOutcome { reports, moved, refined: refined.refinements })
    }
}

/// One dented target during a batch: its current positions and the vertices moved so far.
struct TargetState {
    positions: Vec<Vec3>,
    moved: Vec<bool>,
}

/// Per target, its state after the batch (`None`: no job dents it); per job, its report.
type Dented = (Vec<Option<TargetState>>, Vec<crate::DentReport>);

impl<K: Copy + Eq + Hash> GpuBackend<K> {
    /// Dents the resident targets (`current[t]` is target `t` as uploaded at `slots[t]`, its
    /// vertices from `first_new[t]` on added by refinement) by `jobs` planned as `plans`, round
    /// by round, with the host stages after each round.
    fn dent_resident(
        &mut self,
        current: &[&TriMesh],
        first_new: &[usize],
        slots: &[usize],
        jobs: &[DentJob<'_>],
        plans: &[DentPlan],
    ) -> Result<Dented, BatchError> {
        let failed = |error: String| BatchError { job: 0, error: DentError::Backend(error) };
        let Some(denter) = self.denter.as_mut() else { return Err(failed("no resident targets".into())) };
        let gpu_failed = |job: usize, e: super::GpuError| BatchError { job, error: DentError::Backend(e.to_string()) };
        // New vertices count as moved, as on the CPU: a caller's collider does not have them yet.
        let mut states: Vec<Option<TargetState>> = (0..current.len())
            .map(|t| {
                jobs.iter().any(|j| j.target == t).then(|| TargetState {
                    positions: current[t].positions().to_vec(),
                    moved: (0..current[t].vertex_count()).map(|v| v >= first_new[t]).collect(),
                })
            })
            .collect();
        let mut reports = vec![crate::DentReport::default(); jobs.len()];
        for round in rounds(jobs, current.len()) {
            // The falloffs, fitted on the host where they could fold a wall.
            let mut fitted: Vec<Option<FittedFalloff>> = vec![None; round.len()];
            let to_fit: Vec<usize> =
                (0..round.len()).filter(|&k| falloff_may_need_fit(&plans[round[k]], &jobs[round[k]].params)).collect();
            if !to_fit.is_empty() {
                let fit_jobs: Vec<DentJob<'_>> = to_fit.iter().map(|&k| jobs[round[k]].clone()).collect();
                let fit_plans: Vec<DentPlan> = to_fit.iter().map(|&k| plans[round[k]].clone()).collect();
                let maps =
                    denter.stages_from_plans(&fit_jobs, &fit_plans).map_err(|e| gpu_failed(round[to_fit[0]], e))?;
                for (&k, stages) in to_fit.iter().zip(maps) {
                    let job = &jobs[round[k]];
                    let positions = &states[job.target].as_ref().expect("a dented target").positions;
                    let map = stages.into_stages().map;
                    fitted[k] =
                        Some(fit_to_target(&map, positions, current[job.target].faces(), &job.params.attenuation));
                }
            }
            // The kernels: each job on its slot, with its plan's grid side and its fitted falloff.
            let gpu_jobs: Vec<DentJob<'_>> = round
                .iter()
                .zip(&fitted)
                .map(|(&j, fit)| {
                    let mut job = jobs[j].clone();
                    job.target = slots[job.target];
                    job.params.resolution = Resolution::Fixed(plans[j].zbuffer_grid.res);
                    if let Some(fit) = fit {
                        job.params.attenuation = fit.attenuation.clone();
                    }
                    job
                })
                .collect();
            denter.dent_batch(&gpu_jobs).map_err(|e| match e {
                GpuBatchError::Job(BatchError { job, error }) => BatchError { job: round[job], error },
                GpuBatchError::Gpu(e) => gpu_failed(round[0], e),
            })?;
            // The host stages of each dent of the round, on what the kernels left.
            for (&j, fit) in round.iter().zip(fitted) {
                let t = jobs[j].target;
                let after = denter.read_positions(slots[t]).map_err(|e| gpu_failed(j, e))?;
                let state = states[t].as_mut().expect("a dented target");
                let (faces, normals) = (current[t].faces(), current[t].normals());
                let done =
                    finish_displaced(&state.positions, after.clone(), faces, normals, &plans[j], &jobs[j].params, fit)
                        .map_err(|error| BatchError { job: j, error })?;
                if done.positions != after {
                    write_positions(denter, slots[t], &done.positions, &done.moved);
                }
                state.moved.iter_mut().zip(&done.moved).for_each(|(m, &d)| *m |= d);
                state.positions = done.positions;
                reports[j] = done.report;
            }
        }
        Ok((states, reports))
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

/// Writes the host stages' `positions` of the target at `slot` back to the device (`w` = moved by
/// the dent, as the kernels leave it), before the next submission. The resident normals are not
/// refreshed: this backend never reads them (meshes come back with normals from the host).
fn write_positions(denter: &GpuDenter, slot: usize, positions: &[Vec3], moved: &[bool]) {
    let data: Vec<[f32; 4]> =
        positions.iter().zip(moved).map(|(p, &m)| [p.x, p.y, p.z, f32::from(u8::from(m))]).collect();
    let offset = denter.vertex_range(slot).start;
    denter.context().queue.write_buffer(denter.vertex_buffer(), offset, bytemuck::cast_slice(&data));
}
