//! Many dents at once on the CPU (all cores): maps in parallel, then each target refined for
//! all its dents (stage 1, `refine_target`) and dented in submission order. The GPU batch (`gpu::GpuDenter`) follows the same rules.

use rayon::prelude::*;

use glam::Vec3;

use super::apply::guard_and_keep_volume;
use super::refine_target::{RefinedTarget, refine_for_dents};
use super::{DentError, DentParams, DentReport, Impact, dent_map_stages};
use crate::mesh::{EdgeLengths, Refinement, TriMesh};

/// One dent of a batch: `projectile` hits `targets[target]` at `impact`.
#[derive(Debug, Clone)]
pub struct DentJob<'a> {
    /// Index of the target mesh in the batch's target list.
    pub target: usize,
    /// The projectile, in world coordinates as at the moment of impact.
    pub projectile: &'a TriMesh,
    /// The contact.
    pub impact: Impact,
    /// How the dent is shaped.
    pub params: DentParams,
}

/// A batch failed because of one of its dents; no target changed.
#[derive(Debug, thiserror::Error)]
#[error("dent {job} of the batch: {error}")]
pub struct BatchError {
    /// Index of the offending dent in the batch.
    pub job: usize,
    /// What was wrong with it.
    #[source]
    pub error: DentError,
}

/// One target after its jobs: refined faces (if any), new positions, moved flags, and the report of
/// each of its jobs (job index, report).
type AppliedTarget = (usize, RefinedTarget, Vec<Vec3>, Vec<bool>, Vec<(usize, super::DentReport)>);

/// Dents `targets` by every job: dent maps are built in parallel from the undented meshes, then
/// each target's dents are applied in submission order (a later dent moves the vertices an
/// earlier one moved). Reports come back in job order.
///
/// # Errors
/// [`BatchError`] naming the first bad job (in job order); every target is unchanged then.
pub fn dent_batch(targets: &mut [TriMesh], jobs: &[DentJob<'_>]) -> Result<Vec<DentReport>, BatchError> {
    dent_batch_tracked(targets, jobs).map(|outcome| outcome.reports)
}

/// What a batch did: each job's report and, per target, the vertices that moved and the
/// triangles refinement added.
#[derive(Debug, Clone, Default)]
pub struct BatchOutcome {
    /// One report per job, in job order.
    pub reports: Vec<DentReport>,
    /// Per target (batch order), the indices of the vertices the batch moved, ascending; empty
    /// for a target no job dented. A caller refits its own collider over these — unless the
    /// target was refined ([`topology_changed`](Self::topology_changed)): then they include
    /// every new vertex, and the collider must be rebuilt.
    pub moved: Vec<Vec<u32>>,
    /// Per target (batch order), what refinement appended to it (vertices with their parents,
    /// to interpolate per-vertex data; faces with their parent face); empty when its faces
    /// are unchanged, and for a target no job dented. May be shorter than the target list
    /// (missing entries are empty).
    pub refined: Vec<Refinement>,
}

impl BatchOutcome {
    /// Whether target `t`'s faces changed (it was refined): rebuild its collider instead of
    /// refitting it.
    pub fn topology_changed(&self, t: usize) -> bool {
        self.refined.get(t).is_some_and(|r| !r.is_empty())
    }
}

/// As [`dent_batch`], also telling which vertices of each target moved.
///
/// # Errors
/// As [`dent_batch`]; every target is unchanged then.
pub fn dent_batch_tracked(targets: &mut [TriMesh], jobs: &[DentJob<'_>]) -> Result<BatchOutcome, BatchError> {
    if let Some((job, bad)) = jobs.iter().enumerate().find(|(_, j)| j.target >= targets.len()) {
        let error = super::error::invalid("target", bad.target, "must index the batch's target list");
        return Err(BatchError { job, error });
    }
    if let Some((job, error)) = jobs
        .iter()
        .enumerate()
        .find_map(|(job, j)| super::plan::check_target(&targets[j.target]).err().map(|error| (job, error)))
    {
        return Err(BatchError { job, error });
    }
    // Each target's edge lengths once: the mean sets automatic grids, the longest tells the
    // refine stage whether any edge could be too coarse.
    let edges: Vec<EdgeLengths> = targets.par_iter().map(TriMesh::edge_lengths).collect();
    let stages: Vec<_> = jobs
        .par_iter()
        .enumerate()
        .map(|(job, j)| {
            let edge = edges[j.target].mean;
            dent_map_stages(j.projectile, &j.impact, &j.params, Some(edge)).map_err(|error| BatchError { job, error })
        })
        .collect::<Result<_, _>>()?;

    // Each target's jobs in submission order, targets in parallel: refined for all of them
    // first (from the undented surface, as the maps are), then displaced in order.
    let applied: Vec<AppliedTarget> = (0..targets.len())
        .into_par_iter()
        .filter_map(|t| {
            let mine: Vec<usize> = (0..jobs.len()).filter(|&j| jobs[j].target == t).collect();
            (!mine.is_empty()).then_some((t, mine))
        })
        .map(|(t, mine)| {
            let target = &targets[t];
            let dents: Vec<_> = mine.iter().map(|&j| super::apply::footprint(&stages[j], &jobs[j].params)).collect();
            let refined = refine_for_dents(target, &dents, Some(edges[t].longest))
                .map_err(|(k, error)| BatchError { job: mine[k], error })?;
            let mut positions = refined.positions(target).to_vec();
            // New vertices count as moved: a caller's collider does not have them yet.
            let mut moved: Vec<bool> = (0..positions.len()).map(|v| v >= target.vertex_count()).collect();
            let mut reports = Vec::with_capacity(mine.len());
            // The rim pushes along the normals from before the batch (its size is solved, so the
            // volume is exact; only the direction lags behind earlier dents of the batch).
            let (faces, normals) = refined.surface(target);
            for (k, &job) in mine.iter().enumerate() {
                let (map, params) = (&stages[job].map, &jobs[job].params);
                let pending = map
                    .displaced_positions(&positions, faces, &params.attenuation)
                    .and_then(|mut p| {
                        guard_and_keep_volume(&mut p, faces, &normals, &positions, map, params).map(|()| p)
                    })
                    .map_err(|error| BatchError { job, error })?;
                moved.iter_mut().zip(&pending.moved).for_each(|(m, &p)| *m |= p);
                positions = pending.positions;
                let mut report = super::apply::report(&stages[job], pending.report);
                super::apply::note_refinement(&mut report, &refined, k);
                reports.push((job, report));
            }
            Ok((t, refined, positions, moved, reports))
        })
        .collect::<Result<_, BatchError>>()?;

    let mut out: Vec<Option<DentReport>> = vec![None; jobs.len()];
    let mut moved_lists = vec![Vec::new(); targets.len()];
    let mut refined_lists = vec![Refinement::default(); targets.len()];
    for (t, mut refined, positions, moved, reports) in applied {
        moved_lists[t] = moved.iter().enumerate().filter(|(_, m)| **m).map(|(v, _)| v as u32).collect();
        refined.commit_positions(&mut targets[t], positions, &moved);
        if !refined.refinement.is_empty() {
            refined_lists[t] = std::mem::take(&mut refined.refinement);
        }
        for (job, report) in reports {
            out[job] = Some(report);
        }
    }
    Ok(BatchOutcome {
        reports: out.into_iter().map(|r| r.unwrap_or_default()).collect(),
        moved: moved_lists,
        refined: refined_lists,
    })
}
