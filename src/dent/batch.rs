//! Many dents at once on the CPU (all cores): maps in parallel, then each target's dents in
//! submission order. The GPU batch (`gpu::GpuDenter`) follows the same rules.

use rayon::prelude::*;

use super::map::PendingDisplacement;
use super::{DentError, DentParams, DentReport, Impact, dent_map_stages};
use crate::mesh::TriMesh;

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

/// One target's new positions and the report of each of its jobs (job index, report).
type AppliedTarget = (usize, PendingDisplacement, Vec<(usize, super::DisplaceReport)>);

/// Dents `targets` by every job: dent maps are built in parallel from the undented meshes, then
/// each target's dents are applied in submission order (a later dent moves the vertices an
/// earlier one moved). Reports come back in job order.
///
/// # Errors
/// [`BatchError`] naming the first bad job (in job order); every target is unchanged then.
pub fn dent_batch(targets: &mut [TriMesh], jobs: &[DentJob<'_>]) -> Result<Vec<DentReport>, BatchError> {
    dent_batch_tracked(targets, jobs).map(|outcome| outcome.reports)
}

/// What a batch did: each job's report and, per target, the vertices that moved.
#[derive(Debug, Clone, Default)]
pub struct BatchOutcome {
    /// One report per job, in job order.
    pub reports: Vec<DentReport>,
    /// Per target (batch order), the indices of the vertices the batch moved, ascending; empty
    /// for a target no job dented. A caller refits its own collider over these.
    pub moved: Vec<Vec<u32>>,
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
    let stages: Vec<_> = jobs
        .par_iter()
        .enumerate()
        .map(|(job, j)| {
            let edge = targets[j.target].mean_edge_length();
            dent_map_stages(j.projectile, &j.impact, &j.params, Some(edge)).map_err(|error| BatchError { job, error })
        })
        .collect::<Result<_, _>>()?;

    // Each target's jobs in submission order, targets in parallel.
    let applied: Vec<AppliedTarget> = (0..targets.len())
        .into_par_iter()
        .filter_map(|t| {
            let mine: Vec<usize> = (0..jobs.len()).filter(|&j| jobs[j].target == t).collect();
            (!mine.is_empty()).then_some((t, mine))
        })
        .map(|(t, mine)| {
            let target = &targets[t];
            let mut positions = target.positions().to_vec();
            let mut moved = vec![false; positions.len()];
            let mut reports = Vec::with_capacity(mine.len());
            for job in mine {
                let params = &jobs[job].params;
                let mut pending = stages[job]
                    .map
                    .displaced_positions(&positions, target.faces(), &params.attenuation)
                    .map_err(|error| BatchError { job, error })?;
                if params.guard_crossings {
                    super::guard::guard_crossings(&mut pending, target.faces(), &positions);
                }
                moved.iter_mut().zip(&pending.moved).for_each(|(m, &p)| *m |= p);
                positions = pending.positions;
                reports.push((job, pending.report));
            }
            let report = super::DisplaceReport::default();
            Ok((t, PendingDisplacement { positions, moved, report }, reports))
        })
        .collect::<Result<_, BatchError>>()?;

    let mut out: Vec<Option<DentReport>> = vec![None; jobs.len()];
    let mut moved = vec![Vec::new(); targets.len()];
    for (t, pending, reports) in applied {
        moved[t] = pending.moved.iter().enumerate().filter(|(_, m)| **m).map(|(v, _)| v as u32).collect();
        pending.commit(&mut targets[t]);
        for (job, displaced) in reports {
            out[job] = Some(super::apply::report(&stages[job], displaced));
        }
    }
    Ok(BatchOutcome { reports: out.into_iter().map(|r| r.unwrap_or_default()).collect(), moved })
}
