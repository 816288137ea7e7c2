//! The energy model of dent depth: the plastic work of a dent, hardness × the volume of the
//! projectile's tip pressed into the surface, equals the kinetic energy lost along the normal.

use super::{BodyState, DentError, DentParams, Impact, dent_map_stages};
use crate::mesh::TriMesh;

/// The dent distance d in [0, `params.dent_distance`] (the cap) with `hardness`·V(d) = `energy`,
/// where V(d) is the volume of the projectile within d of its most advanced point along the
/// viewing direction, measured on the dent's own Z-buffer: V(d) = h²·Σ max(0, d + s) over
/// cells, s ≤ 0 the surface depth per cell. Returns the cap when even the cap absorbs less than
/// `energy`; 0 when `energy` ≤ 0.
///
/// `hardness` in Pa (J/m³), `energy` in J, the projectile and impact in world coordinates.
///
/// # Errors
/// As [`dent_map_stages`].
pub(crate) fn energy_dent_distance(
    projectile: &TriMesh,
    impact: &Impact,
    params: &DentParams,
    hardness: f32,
    energy: f32,
) -> Result<f32, DentError> {
    let cap = params.dent_distance;
    if energy.is_nan() || energy <= 0.0 {
        return Ok(0.0);
    }
    let stages = dent_map_stages(projectile, impact, params, None)?;
    let cell_area = stages.zbuffer_grid.cell_size.powi(2);
    // Depth below the tip per covered cell: P = max(0, cap + s) ⇒ s = P − cap where P > 0.
    let depths: Vec<f32> = stages.zbuffer.iter().filter(|&&p| p > 0.0).map(|&p| p - cap).collect();
    let work = |d: f32| hardness * cell_area * depths.iter().map(|&s| (d + s).max(0.0)).sum::<f32>();
    if work(cap) <= energy {
        return Ok(cap);
    }
    // work is continuous and non-decreasing in d: bisection to 1e-4 of the cap.
    let (mut lo, mut hi) = (0.0f32, cap);
    while hi - lo > 1e-4 * cap {
        let mid = 0.5 * (lo + hi);
        if work(mid) < energy { lo = mid } else { hi = mid }
    }
    Ok(0.5 * (lo + hi))
}

/// Kinetic energy a collision removes along the normal, J: ½·m_eff·v_n²·(1 − e²), with m_eff the
/// pair's effective mass along the normal at the contact point (rotation included), v_n the
/// closing speed along the normal (m/s, taken from `impact`) and e the larger restitution of
/// the two. 0 when neither body takes an impulse (both fixed or kinematic).
pub(crate) fn normal_energy_lost(impact: &Impact, target: &BodyState, projectile: &BodyState) -> f32 {
    let normal = impact.unit_normal();
    let k = target.inverse_mass_along(impact.point, normal) + projectile.inverse_mass_along(impact.point, normal);
    if k.is_nan() || k <= 0.0 {
        return 0.0;
    }
    let normal_speed = impact.relative_velocity.dot(normal).max(0.0);
    let e = target.restitution.max(projectile.restitution);
    0.5 / k * normal_speed.powi(2) * (1.0 - e * e)
}
