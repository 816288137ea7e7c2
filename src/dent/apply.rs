//! Denting a target mesh: one projectile (`dent`), or two dentable bodies at once (`dent_pair`).

use super::guard::{guard_crossings, makes_new_crossings};
use super::map::PendingDisplacement;
use super::plan::check_target;
use super::refine_target::{Footprint, RefinedTarget, refine_for_dents};
use super::volume::{restore_volume, volume_change};
use super::{DentError, DentParams, Impact, dent_map_stages};
use crate::mesh::TriMesh;

/// What one dent did to its target.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DentReport {
    /// Vertices that moved.
    pub moved_vertices: usize,
    /// Largest vertex displacement, world units.
    pub max_displacement: f32,
    /// Angle between the relative velocity and the denting normal after clamping, degrees.
    pub theta_deg: f32,
    /// Side of the Z-buffer grid, cells.
    pub resolution: u32,
    /// Side of the dent-map grid on the collision plane, cells (larger than `resolution` when
    /// the impact glances).
    pub map_resolution: u32,
    /// Z-buffer cell side, world units.
    pub cell_size: f32,
    /// Gaussian width used, world units.
    pub sigma: f32,
    /// Warnings raised while applying the map.
    pub warnings: Vec<String>,
    /// Vertices the refine stage added to the target before this dent (appended after the
    /// existing ones).
    pub refined_vertices: usize,
    /// Triangles the refine stage added to the target before this dent.
    pub refined_triangles: usize,
    /// Enclosed volume after the dent minus before, cubic world units, signed (after the rim of
    /// [`VolumeMode::Preserve`](super::VolumeMode::Preserve) when asked); meaningful for a
    /// closed target.
    pub volume_change: f64,
    /// The cavity: |volume change| the displacement alone made, before any rim, cubic world
    /// units. With `Preserve`, `|volume_change| ≤ 0.02·cavity_volume`.
    pub cavity_volume: f64,
    /// Fraction of the dent's displacement kept when the intersection guard scaled it back so
    /// that no faces cross (`None`: not limited; see [`DentParams::guard_crossings`]).
    pub limited_to: Option<f32>,
}

/// Dents `target` where `projectile` hits it (paper Algorithm 1).
///
/// Both meshes are in world coordinates as at the moment of impact; `impact.normal` points into
/// the target and `impact.relative_velocity` is the projectile's velocity relative to it.
///
/// # Errors
/// Any [`DentError`]; `target` is unchanged then.
pub fn dent(
    target: &mut TriMesh,
    projectile: &TriMesh,
    impact: &Impact,
    params: &DentParams,
) -> Result<DentReport, DentError> {
    check_target(target)?;
    let edges = target.edge_lengths();
    let stages = dent_map_stages(projectile, impact, params, Some(edges.mean))?;
    let mut refined =
        refine_for_dents(target, &[footprint(&stages, params)], Some(edges.longest)).map_err(|(_, e)| e)?;
    let pending = displace_keep_volume_and_guard(&refined, target, &stages.map, params)?;
    let mut out = report(&stages, refined.commit(target, pending));
    note_refinement(&mut out, &refined, 0);
    Ok(out)
}

/// Dents two dentable bodies against each other (paper Figure 1): both maps are computed from
/// the undented meshes, then both are applied (Jacobi), so identical bodies get mirror-image
/// dents. `impact.normal` points into `a`; `params_a` shapes the dent in `a`.
///
/// # Example
/// ```
/// use dentbend::{DentParams, Impact, dent_pair, glam::{Affine3A, Vec3}, mesh};
/// let mut lower = mesh::builtin("sphere")?;
/// let mut upper = mesh::builtin("sphere")?;
/// upper.transform(Affine3A::from_translation(Vec3::new(0.0, 2.0, 0.0)))?;
/// // The upper ball falls on the lower one: the normal points into the lower ball.
/// let impact = Impact { point: Vec3::Y, normal: -Vec3::Y, relative_velocity: -Vec3::Y };
/// let params = DentParams::new(0.1);
/// let (a, b) = dent_pair(&mut lower, &mut upper, &impact, &params, &params)?;
/// assert!((a.max_displacement - b.max_displacement).abs() < 1e-5);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// Any [`DentError`]; neither mesh changes then.
pub fn dent_pair(
    a: &mut TriMesh,
    b: &mut TriMesh,
    impact: &Impact,
    params_a: &DentParams,
    params_b: &DentParams,
) -> Result<(DentReport, DentReport), DentError> {
    check_target(a)?;
    check_target(b)?;
    let (edges_a, edges_b) = (a.edge_lengths(), b.edge_lengths());
    let stages_a = dent_map_stages(b, impact, params_a, Some(edges_a.mean))?;
    let stages_b = dent_map_stages(a, &impact.reversed(), params_b, Some(edges_b.mean))?;
    let mut refined_a =
        refine_for_dents(a, &[footprint(&stages_a, params_a)], Some(edges_a.longest)).map_err(|(_, e)| e)?;
    let mut refined_b =
        refine_for_dents(b, &[footprint(&stages_b, params_b)], Some(edges_b.longest)).map_err(|(_, e)| e)?;
    let pending_a = displace_keep_volume_and_guard(&refined_a, a, &stages_a.map, params_a)?;
    let pending_b = displace_keep_volume_and_guard(&refined_b, b, &stages_b.map, params_b)?;
    let mut report_a = report(&stages_a, refined_a.commit(a, pending_a));
    let mut report_b = report(&stages_b, refined_b.commit(b, pending_b));
    note_refinement(&mut report_a, &refined_a, 0);
    note_refinement(&mut report_b, &refined_b, 0);
    Ok((report_a, report_b))
}

pub(crate) fn report(stages: &super::DentStages, displaced: super::DisplaceReport) -> DentReport {
    let grids = (&stages.zbuffer_grid, &stages.map.grid);
    report_from(&stages.frame, grids, stages.sigma, displaced)
}

/// A dent's report from its frame, its Z-buffer and map grids, σ and what its displacement did
/// (the refine counts left at zero for the caller to fill).
pub(crate) fn report_from(
    frame: &super::DentFrame,
    (zbuffer_grid, map_grid): (&super::Grid, &super::Grid),
    sigma: f32,
    displaced: super::DisplaceReport,
) -> DentReport {
    DentReport {
        moved_vertices: displaced.moved_vertices,
        max_displacement: displaced.max_displacement,
        theta_deg: frame.theta_deg(),
        resolution: zbuffer_grid.res,
        map_resolution: map_grid.res,
        cell_size: zbuffer_grid.cell_size,
        sigma,
        warnings: displaced.warnings,
        refined_vertices: 0,
        refined_triangles: 0,
        volume_change: displaced.volume_change,
        cavity_volume: displaced.cavity_volume,
        limited_to: displaced.limited_to,
    }
}

/// Adds dent `k`'s refinement counts and warning (from `refined`) to `report`.
pub(crate) fn note_refinement(report: &mut DentReport, refined: &RefinedTarget, k: usize) {
    let (vertices, faces, warning) = refined.added_by(k);
    report.refined_vertices = vertices;
    report.refined_triangles = faces;
    report.warnings.extend(warning.map(str::to_owned));
}

/// The refine stage's view of a dent whose map is `stages`.
pub(crate) fn footprint<'p>(stages: &super::DentStages, params: &'p DentParams) -> Footprint<'p> {
    Footprint { grid: stages.map.grid, sigma: stages.sigma, params }
}

/// Stages 2–4 of one dent on a target after its refine stage: displaces the surface to dent
/// (refined, or the target's own) by `map` with the falloff fitted to its thickness, then
/// [`guard_and_keep_volume`]; nothing is written yet.
pub(crate) fn displace_keep_volume_and_guard(
    refined: &RefinedTarget,
    target: &TriMesh,
    map: &super::DentMap,
    params: &DentParams,
) -> Result<PendingDisplacement, DentError> {
    let before = refined.positions(target);
    let (faces, normals) = refined.surface(target);
    let mut pending = map.displaced_positions(before, faces, &params.attenuation)?;
    guard_and_keep_volume(&mut pending, faces, &normals, before, map, params)?;
    Ok(pending)
}

/// Stages 3–4 of a dent displaced from `before` (a mesh of `faces` with vertex `normals`): the
/// intersection guard scales the dent back if it would make faces cross (when
/// `params.guard_crossings`); then the volume stage measures it and, under
/// [`VolumeMode::Preserve`](super::VolumeMode::Preserve), raises the rim that puts the limited
/// dent's cavity back; a rim that would make faces cross is scaled back by the guard too, and the
/// reported volume change is measured again then.
pub(crate) fn guard_and_keep_volume(
    pending: &mut PendingDisplacement,
    faces: &[[u32; 3]],
    normals: &[glam::Vec3],
    before: &[glam::Vec3],
    map: &super::DentMap,
    params: &DentParams,
) -> Result<(), DentError> {
    let preserve = params.volume == super::VolumeMode::Preserve;
    if params.guard_crossings && preserve {
        // Most dents make nothing cross: one guard pass over the dent and its rim together
        // settles them. Otherwise the dent is limited first and its rim made for what is left.
        let (rim, sorted) = restore_volume(faces, normals, before, pending, map, params.volume, true)?;
        if !makes_new_crossings(pending, faces, before, sorted) {
            return Ok(());
        }
        rim.undo(pending);
    }
    if params.guard_crossings {
        guard_crossings(pending, faces, before);
    }
    restore_volume(faces, normals, before, pending, map, params.volume, false)?;
    if params.guard_crossings && preserve {
        let limited = pending.report.limited_to;
        guard_crossings(pending, faces, before);
        if pending.report.limited_to != limited {
            pending.report.volume_change = volume_change(faces, before, &pending.positions, &pending.moved);
        }
    }
    Ok(())
}
