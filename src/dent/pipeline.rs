//! One impact to one dent map: frame, grid, then the kernels in order (paper Algorithm 1,
//! lines 2–7).

use glam::Vec3;

use super::{DentError, DentFrame, DentMap, DentParams, Grid, Impact, MAX_RESOLUTION, Resolution};
use crate::cpu::{self, EnvelopeParams, GlanceParams, ZbufferParams};
use crate::mesh::TriMesh;

/// Gaussian tails kept on each side of a footprint, in σ: `e^{−3.5²/2} ≈ 0.2 %` of a cell's
/// height remains at the border, and the heat steps' zero border takes it the rest of the way.
pub(crate) const TAIL_SIGMAS: f32 = 3.5;

/// Cells per mean edge of the finer mesh when the resolution is automatic.
const CELLS_PER_EDGE: f32 = 2.0;

/// Every intermediate stage of one dent map, for inspection, pictures and tests.
#[derive(Debug, Clone)]
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
/// use dentbend::{DentParams, Impact, Resolution, dent_map_stages, glam::Vec3, mesh};
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
    params.validate()?;
    impact.validate()?;
    if let Some(edge) = target_edge
        && !(edge.is_finite() && edge >= 0.0)
    {
        return Err(super::error::invalid("target_edge", edge, "must be finite and >= 0"));
    }
    let (lo, hi) = projectile.bounds();
    let area = projectile.area();
    if area.is_nan() || area <= 1e-10 * lo.distance_squared(hi) {
        return Err(DentError::DegenerateProjectile);
    }
    let frame = DentFrame::new(impact, params.min_cos);
    check_in_front(projectile, impact, &frame)?;
    let d = params.dent_distance;
    let sigma = params.sigma_or_default();

    let zbuffer_grid = zbuffer_grid(projectile, &frame, params, sigma, target_edge)?;
    let res = zbuffer_grid.res;
    let cells = zbuffer_grid.cell_count();
    let mut zbuffer = vec![0.0; cells];
    let zparams = ZbufferParams {
        grid: zbuffer_grid.uniform(),
        dent_distance: d,
        face_count: projectile.face_count() as u32,
        face_offset: 0,
        cell_offset: 0,
    };
    cpu::zbuffer(&zparams, projectile.positions(), projectile.faces(), &mut zbuffer);
    if zbuffer.iter().all(|&p| p <= 0.0) {
        return Err(DentError::EmptyProfile);
    }

    let eparams = EnvelopeParams::new(res, sigma / zbuffer_grid.cell_size);
    let mut rows = vec![0.0; cells];
    let mut envelope = vec![0.0; cells];
    cpu::envelope_rows(&eparams, &zbuffer, &mut rows);
    cpu::envelope_cols(&eparams, &rows, &mut envelope);

    let mut smoothed = envelope.clone();
    cpu::heat(&mut smoothed, res, params.heat_rate, params.heat_iters, params.clamp_iters, d);
    if !smoothed.iter().any(|&h| h > 0.0) {
        return Err(DentError::EmptyProfile);
    }

    let map = glance(&smoothed, &zbuffer_grid, impact.point, &frame, params);
    if map.cells.iter().flatten().any(|v| !v.is_finite()) {
        return Err(super::error::invalid("dent_distance", d, "is too large for f32 arithmetic"));
    }
    Ok(DentStages { zbuffer_grid, zbuffer, envelope, smoothed, map, frame, sigma })
}

/// Builds only the final dent map; see [`dent_map_stages`].
///
/// # Errors
/// As [`dent_map_stages`].
pub fn dent_map(
    projectile: &TriMesh,
    impact: &Impact,
    params: &DentParams,
    target_edge: Option<f32>,
) -> Result<DentMap, DentError> {
    dent_map_stages(projectile, impact, params, target_edge).map(|stages| stages.map)
}

/// Places smoothed heights given on a grid perpendicular to the velocity (`heights_grid`) onto
/// the collision plane through `point`, stretched by 1/cos θ and sheared (paper §3.3). The map
/// keeps the heights' cell size (side `res/cos θ` cells) up to [`MAX_RESOLUTION`] cells, past
/// which its cells grow.
pub(crate) fn glance(
    heights: &[f32],
    heights_grid: &Grid,
    point: Vec3,
    frame: &DentFrame,
    params: &DentParams,
) -> DentMap {
    let res = heights_grid.res;
    let stretch = 1.0 / frame.cos_theta;
    let dst_res = ((res as f32 * stretch).ceil() as u32).clamp(res, MAX_RESOLUTION.max(res));
    let dst_cell_size = heights_grid.extent() * stretch / dst_res as f32;
    let (axis_x, axis_y, axis_z) = frame.plane_axes();
    let grid = Grid { origin: point, axis_x, axis_y, axis_z, cell_size: dst_cell_size, res: dst_res };
    let gparams = GlanceParams {
        src_res: res,
        src_cell_size: heights_grid.cell_size,
        dst_res,
        dst_cell_size,
        cos_theta: frame.cos_theta,
        sin_theta: frame.sin_theta,
        widen: params.widen,
        src_offset: 0,
        normal: frame.normal.to_array(),
        dst_offset: 0,
        tangent: frame.tangent.to_array(),
        _pad: 0,
    };
    let mut cells = vec![[0.0; 4]; grid.cell_count()];
    cpu::glance(&gparams, heights, &mut cells);
    DentMap { grid, cells, dent_distance: params.dent_distance }
}

/// Fails when the whole projectile lies past the collision plane, inside the target.
fn check_in_front(projectile: &TriMesh, impact: &Impact, frame: &DentFrame) -> Result<(), DentError> {
    let nearest = (projectile.support_point(-frame.normal) - impact.point).dot(frame.normal);
    if nearest > 0.0 {
        return Err(DentError::ProjectileBehindPlane { distance: nearest });
    }
    Ok(())
}

/// The Z-buffer grid: centred on the projectile's most advanced point along the viewing
/// direction, wide enough for the footprint plus the Gaussian tails, with cells no larger than
/// half the finer mesh's mean edge or σ when the resolution is automatic.
fn zbuffer_grid(
    projectile: &TriMesh,
    frame: &DentFrame,
    params: &DentParams,
    sigma: f32,
    target_edge: Option<f32>,
) -> Result<Grid, DentError> {
    let (axis_x, axis_y, axis_z) = frame.zbuffer_axes();
    let origin = projectile.support_point(axis_z);
    let footprint = footprint_half_width(projectile, origin, (axis_x, axis_y, axis_z), params.dent_distance);
    let half = footprint + TAIL_SIGMAS * sigma;
    let res = match params.resolution {
        Resolution::Fixed(n) => n,
        Resolution::Auto { min, max } => {
            let edge = target_edge
                .filter(|e| *e > 0.0)
                .map_or(projectile.mean_edge_length(), |t| t.min(projectile.mean_edge_length()));
            let cell = (edge / CELLS_PER_EDGE).min(sigma);
            let wanted = (2.0 * half / cell.max(f32::MIN_POSITIVE)).ceil();
            (wanted.min(max as f32) as u32).clamp(min, max)
        }
    };
    let cell_size = 2.0 * half / res as f32;
    if !(cell_size.is_finite() && cell_size > 0.0) {
        // A σ the user set can overflow on its own; otherwise d (and σ = d/2 with it) did.
        let (name, value) = match params.sigma {
            Some(s) if (4.0 * TAIL_SIGMAS * s).is_infinite() => ("sigma", s),
            _ => ("dent_distance", params.dent_distance),
        };
        return Err(super::error::invalid(name, value, "makes the dent grid too large for f32 arithmetic"));
    }
    Ok(Grid { origin, axis_x, axis_y, axis_z, cell_size, res })
}

/// Largest lateral distance (max of |x| and |y| in the Z-buffer frame, world units) from
/// `origin` of the projectile's surface within `d` of its tip: each triangle is clipped at depth
/// `−d` and its clipped corners measured.
fn footprint_half_width(projectile: &TriMesh, origin: Vec3, axes: (Vec3, Vec3, Vec3), d: f32) -> f32 {
    let (ax, ay, az) = axes;
    let local = |p: Vec3| {
        let r = p - origin;
        Vec3::new(r.dot(ax), r.dot(ay), r.dot(az) + d)
    };
    let lateral = |q: Vec3| q.x.abs().max(q.y.abs());
    let mut widest: f32 = 0.0;
    for face in projectile.faces() {
        let corners = face.map(|v| local(projectile.positions()[v as usize]));
        for k in 0..3 {
            let (a, b) = (corners[k], corners[(k + 1) % 3]);
            if a.z >= 0.0 {
                widest = widest.max(lateral(a));
            }
            if (a.z >= 0.0) != (b.z >= 0.0) {
                let t = a.z / (a.z - b.z);
                widest = widest.max(lateral(a.lerp(b, t)));
            }
        }
    }
    widest
}
