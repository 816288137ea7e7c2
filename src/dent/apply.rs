//! Denting a target mesh: one projectile (`dent`), or two dentable bodies at once (`dent_pair`).

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
    let stages = dent_map_stages(projectile, impact, params, Some(target.mean_edge_length()))?;
    let mut pending = stages.map.displaced(target, &params.attenuation)?;
    guard(&mut pending, target, params);
    let displaced = pending.commit(target);
    Ok(report(&stages, displaced))
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
    let stages_a = dent_map_stages(b, impact, params_a, Some(a.mean_edge_length()))?;
    let stages_b = dent_map_stages(a, &impact.reversed(), params_b, Some(b.mean_edge_length()))?;
    let mut pending_a = stages_a.map.displaced(a, &params_a.attenuation)?;
    let mut pending_b = stages_b.map.displaced(b, &params_b.attenuation)?;
    guard(&mut pending_a, a, params_a);
    guard(&mut pending_b, b, params_b);
    let report_a = report(&stages_a, pending_a.commit(a));
    let report_b = report(&stages_b, pending_b.commit(b));
    Ok((report_a, report_b))
}

/// The intersection guard, when `params` ask for it.
fn guard(pending: &mut super::map::PendingDisplacement, target: &TriMesh, params: &DentParams) {
    if params.guard_crossings {
        super::guard::guard_crossings(pending, target.faces(), target.positions());
    }
}

pub(crate) fn report(stages: &super::DentStages, displaced: super::DisplaceReport) -> DentReport {
    DentReport {
        moved_vertices: displaced.moved_vertices,
        max_displacement: displaced.max_displacement,
        theta_deg: stages.frame.theta_deg(),
        resolution: stages.zbuffer_grid.res,
        map_resolution: stages.map.grid.res,
        cell_size: stages.zbuffer_grid.cell_size,
        sigma: stages.sigma,
        warnings: displaced.warnings,
        limited_to: displaced.limited_to,
    }
}
