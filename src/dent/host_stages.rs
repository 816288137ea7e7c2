//! The dent stages a backend that displaces elsewhere (the GPU kernels) runs on the host, with
//! the CPU pipeline's own functions and in its order: before the displacement, the falloff
//! fitted to the target's thickness (`thickness`); after it, the intersection guard, the volume
//! rim under [`VolumeMode::Preserve`](super::VolumeMode::Preserve), the guard again and the
//! volume measured again ([`guard_and_keep_volume`]).

use glam::Vec3;

use super::apply::{guard_and_keep_volume, report_from};
use super::map::PendingDisplacement;
use super::thickness::{FittedFalloff, MapView, fit_falloff, may_fold};
use super::{Attenuation, DentError, DentMap, DentParams, DentPlan, DentReport};

/// A dent after its host stages: the target's new positions, which vertices moved, and the
/// report (the refine counts left at zero for the caller to fill).
#[derive(Debug, Clone)]
pub(crate) struct HostDent {
    pub(crate) positions: Vec<Vec3>,
    pub(crate) moved: Vec<bool>,
    pub(crate) report: DentReport,
}

/// Whether the dent planned as `plan` with `params` may need its falloff fitted, so its map must
/// be read before it is displaced. No map cell pushes further than d along the axis (heights are
/// rescaled to peak d, the clamped heat steps never raise the peak, and the push is
/// `height·cos θ`); where even a push of d cannot fold a wall, the fit keeps the falloff
/// whatever the map holds (the default logistic falloff is such a one).
pub(crate) fn falloff_may_need_fit(plan: &DentPlan, params: &DentParams) -> bool {
    may_fold(&params.attenuation, plan.dent_distance, plan.dent_distance)
}

/// `attenuation` fitted to a target (`positions` with `faces`) under `map`, as the CPU pipeline
/// fits it: stretched in depth where it would leave less than half of a wall, with the thin-wall
/// warning where it would have folded it.
pub(crate) fn fit_to_target(
    map: &DentMap,
    positions: &[Vec3],
    faces: &[[u32; 3]],
    attenuation: &Attenuation,
) -> FittedFalloff {
    let view = MapView { grid: map.grid, cells: &map.cells, dent_distance: map.dent_distance };
    fit_falloff(&view, positions, faces, attenuation)
}

/// The stages after the displacement of a dent planned as `plan` with `params`, displaced
/// elsewhere from `before` to `after` (a target with `faces` whose vertex `normals` are those
/// before its batch, as the CPU batch's rim uses) with the falloff `fitted` (`None`: the
/// caller's, which could not fold a wall). A vertex moved if its position changed.
///
/// # Errors
/// [`DentError::NonFiniteResult`] if a displaced vertex (or the rim) left finite space.
pub(crate) fn finish_displaced(
    before: &[Vec3],
    after: Vec<Vec3>,
    faces: &[[u32; 3]],
    normals: &[Vec3],
    plan: &DentPlan,
    params: &DentParams,
    fitted: Option<FittedFalloff>,
) -> Result<HostDent, DentError> {
    let moved: Vec<bool> = after.iter().zip(before).map(|(a, b)| a != b).collect();
    let mut pending = PendingDisplacement::checked(before, after, moved, fitted)?;
    // The guard and volume stages read only the map's grid (its frame and cell size), which the
    // plan holds; the cells stay where the displacement ran.
    let map = DentMap { grid: plan.map_grid, cells: Vec::new(), dent_distance: plan.dent_distance };
    guard_and_keep_volume(&mut pending, faces, normals, before, &map, params)?;
    let report = report_from(&plan.frame, (&plan.zbuffer_grid, &plan.map_grid), plan.sigma, pending.report);
    Ok(HostDent { positions: pending.positions, moved: pending.moved, report })
}
