//! Everything decided on the host before a kernel runs (paper Algorithm 1, lines 2–3): the frame,
//! the two grids and each kernel's parameter block. The CPU pipeline and GPU batches share it.

use glam::Vec3;

use super::{DentError, DentFrame, DentParams, Grid, Impact, MAX_RESOLUTION, Resolution};
use crate::cpu::{EnvelopeParams, GlanceParams, ZbufferParams};
use crate::mesh::TriMesh;

/// Gaussian tails kept on each side of a footprint, in σ: `e^{−3.5²/2} ≈ 0.2 %` of a cell's
/// height remains at the border, and the heat steps' zero border takes it the rest of the way.
pub(crate) const TAIL_SIGMAS: f32 = 3.5;

/// Cells per mean edge of the finer mesh when the resolution is automatic.
const CELLS_PER_EDGE: f32 = 2.0;

/// The host-side plan of one dent.
#[derive(Debug, Clone, PartialEq)]
pub struct DentPlan {
    /// The impact's frame (θ clamped).
    pub frame: DentFrame,
    /// Gaussian width, world units.
    pub sigma: f32,
    /// Z-buffer grid: perpendicular to the velocity, `origin` on the projectile's tip.
    pub zbuffer_grid: Grid,
    /// Dent-map grid on the collision plane, centred on the impact point.
    pub map_grid: Grid,
    /// Inputs of `zbuffer`.
    pub zbuffer: ZbufferParams,
    /// Inputs of `envelope_rows` and `envelope_cols`.
    pub envelope: EnvelopeParams,
    /// Inputs of `glance`.
    pub glance: GlanceParams,
    /// α of the heat steps.
    pub heat_rate: f32,
    /// k₁ plain heat steps.
    pub heat_iters: u32,
    /// k₂ clamped heat steps.
    pub clamp_iters: u32,
    /// Dent distance d, world units.
    pub dent_distance: f32,
}

/// Whether `mesh`'s triangles have area: more than 1e-10 of its bounding box diagonal
/// squared.
fn has_area(mesh: &TriMesh) -> bool {
    let (lo, hi) = mesh.bounds();
    // Positions are finite and bounded (a `TriMesh` invariant), so the area is never NaN.
    mesh.area_exceeds(1e-10 * f64::from(lo.distance_squared(hi)))
}

/// Checks that `target` has a surface to dent.
///
/// # Errors
/// [`DentError::DegenerateTarget`] when its triangles have no area.
pub(crate) fn check_target(target: &TriMesh) -> Result<(), DentError> {
    if has_area(target) { Ok(()) } else { Err(DentError::DegenerateTarget) }
}

/// Validates one dent's inputs and plans it: frame, grids, and the parameter block of each kernel.
///
/// `target_edge` is the target's mean edge length (world units), used with the projectile's for
/// the automatic resolution; `None` uses the projectile's alone.
///
/// # Errors
/// Invalid parameters, impact or target edge; [`DentError::DegenerateProjectile`];
/// [`DentError::ProjectileBehindPlane`]; σ or d too large for f32 grids.
pub fn plan_dent(
    projectile: &TriMesh,
    impact: &Impact,
    params: &DentParams,
    target_edge: Option<f32>,
) -> Result<DentPlan, DentError> {
    params.validate()?;
    impact.validate()?;
    if let Some(edge) = target_edge
        && !(edge.is_finite() && edge >= 0.0)
    {
        return Err(super::error::invalid("target_edge", edge, "must be finite and >= 0"));
    }
    if !has_area(projectile) {
        return Err(DentError::DegenerateProjectile);
    }
    let frame = DentFrame::new(impact, params.min_cos);
    check_in_front(projectile, impact, &frame)?;
    let sigma = params.sigma_or_default();
    let zbuffer_grid = zbuffer_grid(projectile, &frame, params, sigma, target_edge)?;
    let d = params.dent_distance;
    let zbuffer = ZbufferParams {
        grid: zbuffer_grid.uniform(),
        dent_distance: d,
        face_count: projectile.face_count() as u32,
        face_offset: 0,
        cell_offset: 0,
    };
    let envelope = EnvelopeParams::new(zbuffer_grid.res, sigma / zbuffer_grid.cell_size);
    let map_grid = map_grid(&zbuffer_grid, impact.point, &frame);
    let glance = glance_params(&zbuffer_grid, &map_grid, &frame, params.widen);
    Ok(DentPlan {
        frame,
        sigma,
        zbuffer_grid,
        map_grid,
        zbuffer,
        envelope,
        glance,
        heat_rate: params.heat_rate,
        heat_iters: params.heat_iters,
        clamp_iters: params.clamp_iters,
        dent_distance: d,
    })
}

/// A glancing map keeps the heights' cell size along its 1/cos θ stretch up to this many times
/// the heights' resolution (or [`GLANCE_RESOLUTION_FLOOR`] cells, whichever is more); past it
/// its cells grow (they are square, so across the slide too: at the cap an 84° map's cell is
/// 2.4 heights cells wide). The cell count, and the time of every stage over the map, grows as
/// 1/cos²θ without the cap: at θ = 84° a
/// 72-cell heights grid would give a 689² map; 288² is 5.7× fewer cells and moved no vertex by
/// more than 1.7 % of the dent's depth on `block` (0.4 % on `block-fine` and `plank`; soak-size
/// dents at 70–84°).
pub const GLANCE_STRETCH_CAP: u32 = 4;
/// The fewest cells a side of a glancing map may be capped to (see [`GLANCE_STRETCH_CAP`]).
pub const GLANCE_RESOLUTION_FLOOR: u32 = 256;
const _: () = assert!(GLANCE_RESOLUTION_FLOOR <= MAX_RESOLUTION, "the cap's clamp needs floor ≤ ceiling");

/// The dent-map grid for heights on `heights_grid`: on the collision plane through `point`,
/// keeping the heights' cell size over the 1/cos θ stretch (side `res/cos θ` cells), up to
/// [`GLANCE_STRETCH_CAP`]·`res` cells (at least [`GLANCE_RESOLUTION_FLOOR`], at most
/// [`MAX_RESOLUTION`]), past which its cells grow.
pub(crate) fn map_grid(heights_grid: &Grid, point: Vec3, frame: &DentFrame) -> Grid {
    let res = heights_grid.res;
    let stretch = 1.0 / frame.cos_theta;
    let cap = (GLANCE_STRETCH_CAP * res).clamp(GLANCE_RESOLUTION_FLOOR, MAX_RESOLUTION);
    let dst_res = ((res as f32 * stretch).ceil() as u32).clamp(res, cap.max(res));
    let cell_size = heights_grid.extent() * stretch / dst_res as f32;
    let (axis_x, axis_y, axis_z) = frame.plane_axes();
    Grid { origin: point, axis_x, axis_y, axis_z, cell_size, res: dst_res }
}

/// Inputs of `glance` from heights on `heights_grid` to the map on `map_grid`.
pub(crate) fn glance_params(heights_grid: &Grid, map_grid: &Grid, frame: &DentFrame, widen: f32) -> GlanceParams {
    GlanceParams {
        src_res: heights_grid.res,
        src_cell_size: heights_grid.cell_size,
        dst_res: map_grid.res,
        dst_cell_size: map_grid.cell_size,
        cos_theta: frame.cos_theta,
        sin_theta: frame.sin_theta,
        widen,
        src_offset: 0,
        normal: frame.normal.to_array(),
        dst_offset: 0,
        tangent: frame.tangent.to_array(),
        _pad: 0,
    }
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
            let own = projectile.mean_edge_length();
            let edge = target_edge.filter(|e| *e > 0.0).map_or(own, |t| t.min(own));
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
