//! The refine stage on its own, for backends that displace elsewhere (the GPU refines on the
//! host, then uploads the refined targets).

use super::apply::note_refinement;
use super::error::invalid;
use super::refine_target::{Footprint, refine_for_dents, refined_mesh};
use super::{BatchError, DentJob, DentPlan, DentReport, plan_dent};
use crate::mesh::{EdgeLengths, Refinement, TriMesh};
use rayon::prelude::*;

/// What [`refine_planned`] did: per target, its refined mesh (`None` when left as it was) and
/// what was appended; per job, a report with only its refinement counts and warnings filled in.
#[derive(Debug, Clone, Default)]
pub(crate) struct RefinedTargets {
    /// Per target (batch order): the refined mesh, `None` when nothing was refined.
    pub meshes: Vec<Option<TriMesh>>,
    /// Per target: what refinement appended (empty when nothing).
    pub refinements: Vec<Refinement>,
    /// Per job: `refined_vertices`, `refined_triangles` and warnings.
    pub reports: Vec<DentReport>,
}

/// Every job planned on the host as the CPU batch plans it, from its target as given (the mean
/// edge sets the automatic resolution), with each dented target's edge lengths, measured once.
///
/// # Errors
/// [`BatchError`] naming the first job (in job order) whose target index or plan is bad.
#[cfg(feature = "gpu")]
pub(crate) fn plan_jobs(
    targets: &[&TriMesh],
    jobs: &[DentJob<'_>],
) -> Result<(Vec<Option<EdgeLengths>>, Vec<DentPlan>), BatchError> {
    let edges = edges_of_dented(targets, jobs)?;
    let plans = jobs
        .par_iter()
        .enumerate()
        .map(|(job, j)| {
            let edge = edges[j.target].map(|e| e.mean);
            plan_dent(j.projectile, &j.impact, &j.params, edge).map_err(|error| BatchError { job, error })
        })
        .collect::<Result<_, _>>()?;
    Ok((edges, plans))
}

/// Per target, its edge lengths if a job dents it (`None` otherwise), after checking that every
/// job names a target of the list.
fn edges_of_dented(targets: &[&TriMesh], jobs: &[DentJob<'_>]) -> Result<Vec<Option<EdgeLengths>>, BatchError> {
    if let Some((job, bad)) = jobs.iter().enumerate().find(|(_, j)| j.target >= targets.len()) {
        return Err(BatchError { job, error: invalid("target", bad.target, "must index the batch's target list") });
    }
    Ok(targets
        .par_iter()
        .enumerate()
        .map(|(t, mesh)| jobs.iter().any(|j| j.target == t).then(|| mesh.edge_lengths()))
        .collect())
}

/// The refine stage of `jobs` planned as `plans` (`None` for a job that does not refine), on
/// `targets` whose edge lengths `edges` holds (as [`edges_of_dented`] measures them).
pub(crate) fn refine_planned(
    targets: &[&TriMesh],
    edges: &[Option<EdgeLengths>],
    jobs: &[DentJob<'_>],
    plans: &[Option<&DentPlan>],
) -> Result<RefinedTargets, BatchError> {
    let mut out = RefinedTargets { reports: vec![DentReport::default(); jobs.len()], ..RefinedTargets::default() };
    for (t, &target) in targets.iter().enumerate() {
        let mine: Vec<usize> = (0..jobs.len()).filter(|&j| jobs[j].target == t && plans[j].is_some()).collect();
        let dents: Vec<Footprint<'_>> = mine
            .iter()
            .filter_map(|&j| {
                plans[j].map(|plan| Footprint { grid: plan.map_grid, sigma: plan.sigma, params: &jobs[j].params })
            })
            .collect();
        let longest = edges[t].map(|e| e.longest);
        let mut done =
            refine_for_dents(target, &dents, longest).map_err(|(k, error)| BatchError { job: mine[k], error })?;
        for (k, &j) in mine.iter().enumerate() {
            note_refinement(&mut out.reports[j], &done, k);
        }
        let refined = done.take_parts();
        out.meshes
            .push(refined.map(|(positions, faces)| refined_mesh(target, positions, faces, &done.refinement, &[])));
        out.refinements.push(done.refinement);
    }
    Ok(out)
}
