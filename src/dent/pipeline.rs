//! One impact to one dent map: frame, grid, then the kernels in order (paper Algorithm 1,
//! lines 2–7).

use super::{DentError, DentFrame, DentMap, DentParams, Grid, Impact, plan_dent};
use crate::cpu;
use crate::mesh::TriMesh;

/// Every intermediate stage of one dent map, for inspection, pictures and tests.
#[derive(Debug, Clone)]
#[cfg_attr(not(feature = "kernels"), allow(dead_code, reason = "its stages are read with `kernels`"))]
pub struct DentStages {
    /// The Z-buffer grid, perpendicular to the relative velocity; `origin` is the projectile's
    /// most advanced point along `axis_z`, which the dent map places on the impact point.
    pub zbuffer_grid: Grid,
    /// Profile P (0..=d) on `zbuffer_grid`, row-major.
    pub zbuffer: Vec<f32>,
    /// Exact upper envelope of the Gaussians on `zbuffer_grid`.
    pub envelope: Vec<f32>,
    /// Envelope after heat smoothing, peak d.
    pub smoothed: Vec<f32>,
    /// The final 3-vector map on the collision plane.
    pub map: DentMap,
    /// The impact's frame (θ clamped).
    pub frame: DentFrame,
    /// Gaussian width used, world units.
    pub sigma: f32,
}

/// Builds the dent map that `projectile` leaves at `impact`, keeping every stage.
///
/// `target_edge` is the target's mean edge length (world units), used with the projectile's
/// for the automatic resolution; `None` uses the projectile's alone. The profile is measured
/// from the projectile's most advanced point along the viewing direction, wherever the
/// projectile is, and that point is placed on `impact.point`: the map is centred there.
///
/// # Example
/// ```
/// use dentbend::dent::dent_map_stages;
/// use dentbend::{DentParams, Impact, Resolution, glam::Vec3, mesh};
/// let bunny = mesh::builtin("bunny")?;
/// // Ears first along +y: the impact point is the bunny's highest vertex.
/// let impact = Impact::head_on(bunny.support_point(Vec3::Y), Vec3::Y);
/// let params = DentParams { resolution: Resolution::Fixed(100), ..DentParams::new(3.0) };
/// let stages = dent_map_stages(&bunny, &impact, &params, None)?;
/// let peak = stages.smoothed.iter().copied().fold(0.0, f32::max);
/// assert!((peak - 3.0).abs() < 1e-5 && stages.zbuffer.len() == 100 * 100);
/// # Ok::<(), dentbend::DentError>(())
/// ```
///
/// # Errors
/// Invalid parameters, impact or mesh; [`DentError::ProjectileBehindPlane`];
/// [`DentError::EmptyProfile`] when nothing is left of the profile (a σ or d far outside the
/// projectile's scale).
pub fn dent_map_stages(
    projectile: &TriMesh,
    impact: &Impact,
    params: &DentParams,
    target_edge: Option<f32>,
) -> Result<DentStages, DentError> {
    let plan = plan_dent(projectile, impact, params, target_edge)?;
    let (res, cells) = (plan.zbuffer_grid.res, plan.zbuffer_grid.cell_count());
    let mut zbuffer = vec![0.0; cells];
    cpu::zbuffer(&plan.zbuffer, projectile.positions(), projectile.faces(), &mut zbuffer);
    if zbuffer.iter().all(|&p| p <= 0.0) {
        return Err(DentError::EmptyProfile);
    }

    let mut rows = vec![0.0; cells];
    let mut envelope = vec![0.0; cells];
    cpu::envelope_rows(&plan.envelope, &zbuffer, &mut rows);
    cpu::envelope_cols(&plan.envelope, &rows, &mut envelope);

    let mut smoothed = envelope.clone();
    let d = plan.dent_distance;
    cpu::heat(&mut smoothed, res, plan.heat_rate, plan.heat_iters, plan.clamp_iters, d);
    if !smoothed.iter().any(|&h| h > 0.0) {
        return Err(DentError::EmptyProfile);
    }

    // Zeroed, then only the rows that can read a height are written (a steep glance's map is
    // mostly empty rows: `cpu::glance_band`).
    let mut map_cells = vec![[0.0; 4]; plan.map_grid.cell_count()];
    let band = cpu::glance_band(&plan.glance, &smoothed, &mut map_cells);
    let width = plan.map_grid.res as usize;
    if map_cells[band.start * width..band.end * width].iter().flatten().any(|v| !v.is_finite()) {
        return Err(super::error::invalid("dent_distance", d, "is too large for f32 arithmetic"));
    }
    let map = DentMap { grid: plan.map_grid, cells: map_cells, dent_distance: d };
    let (zbuffer_grid, frame, sigma) = (plan.zbuffer_grid, plan.frame, plan.sigma);
    Ok(DentStages { zbuffer_grid, zbuffer, envelope, smoothed, map, frame, sigma })
}

/// Builds only the final dent map (`dent_map_stages`, public with the `kernels` feature, keeps
/// every stage).
///
/// # Errors
/// Invalid parameters, impact or mesh; [`DentError::ProjectileBehindPlane`];
/// [`DentError::EmptyProfile`] when nothing is left of the profile.
pub fn dent_map(
    projectile: &TriMesh,
    impact: &Impact,
    params: &DentParams,
    target_edge: Option<f32>,
) -> Result<DentMap, DentError> {
    dent_map_stages(projectile, impact, params, target_edge).map(|stages| stages.map)
}
