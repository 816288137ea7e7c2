//! The refine stage on its own, for backends that displace elsewhere (the GPU refines on the
//! host, then uploads the refined targets).

use super::apply::note_refinement;
use super::error::invalid;
use super::refine_setting::Refine;
use super::refine_target::{Footprint, refine_for_dents};
use super::{BatchError, DentJob, DentReport, plan_dent};
use crate::mesh::{Refinement, TriMesh};

/// What [`refine_targets`] did: per target, its refined mesh (`None` when left as it was) and
/// what was appended; per job, a report with only its refinement counts and warnings filled in.
#[derive(Debug, Clone, Default)]
pub struct RefinedTargets {
    /// Per target (batch order): the refined mesh, `None` when nothing was refined.
    pub meshes: Vec<Option<TriMesh>>,
    /// Per target: what refinement appended (empty when nothing).
    pub refinements: Vec<Refinement>,
    /// Per job: `refined_vertices`, `refined_triangles` and warnings.
    pub reports: Vec<DentReport>,
}

/// The refine stage on its own, for backends that displace elsewhere (the GPU): plans every job
/// (as [`plan_dent`] does, with the target's mean edge) and refines its target where it will
/// land, each target's jobs in order, all from the targets as they are.
///
/// # Errors
/// [`BatchError`] naming the first job (in job order) whose plan or refinement failed.
pub fn refine_targets(targets: &[TriMesh], jobs: &[DentJob<'_>]) -> Result<RefinedTargets, BatchError> {
    if let Some((job, bad)) = jobs.iter().enumerate().find(|(_, j)| j.target >= targets.len()) {
        return Err(BatchError { job, error: invalid("target", bad.target, "must index the batch's target list") });
    }
    let mut plans = Vec::with_capacity(jobs.len());
    for (job, j) in jobs.iter().enumerate() {
        if matches!(j.params.refine, Refine::Off) {
            plans.push(None);
            continue;
        }
        let edge = targets[j.target].mean_edge_length();
        let plan =
            plan_dent(j.projectile, &j.impact, &j.params, Some(edge)).map_err(|error| BatchError { job, error })?;
        plans.push(Some((plan.map_grid, plan.sigma)));
    }
    let mut out = RefinedTargets { reports: vec![DentReport::default(); jobs.len()], ..RefinedTargets::default() };
    for (t, target) in targets.iter().enumerate() {
        let mine: Vec<usize> = (0..jobs.len()).filter(|&j| jobs[j].target == t && plans[j].is_some()).collect();
        let dents: Vec<Footprint<'_>> = mine
            .iter()
            .filter_map(|&j| plans[j].map(|(grid, sigma)| Footprint { grid, sigma, params: &jobs[j].params }))
            .collect();
        let mut done =
            refine_for_dents(target, &dents, None).map_err(|(k, error)| BatchError { job: mine[k], error })?;
        for (k, &j) in mine.iter().enumerate() {
            note_refinement(&mut out.reports[j], &done, k);
        }
        out.meshes.push(done.take_parts().map(|(positions, faces)| TriMesh::from_valid(positions, faces)));
        out.refinements.push(done.refinement);
    }
    Ok(out)
}
