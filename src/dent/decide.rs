//! Whether a hit dents its target and how deep (paper Algorithm 1, lines 14–20), from the
//! contact alone: the threshold / gain / cap material, or the energy model when the target has a
//! hardness. Engine-neutral: the caller's solver supplies the contact and the two bodies' states.

use glam::{Affine3A, Vec3};

use super::energy::{energy_dent_distance, normal_energy_lost};
use super::{BodyState, DentError, DentParams, DentSettings, Impact, Surface};

impl Impact {
    /// The impact of a contact at `point` (world, m) whose denting normal `normal` points into
    /// the target: the projectile's velocity relative to the target there comes from both
    /// bodies' states, rotation included (v + ω × r on each side).
    ///
    /// # Errors
    /// [`DentError::InvalidBody`] for a non-finite state, [`DentError::InvalidImpact`] for a
    /// non-finite point or a zero normal.
    pub fn from_contact(
        point: Vec3,
        normal: Vec3,
        target: &BodyState,
        projectile: &BodyState,
    ) -> Result<Self, DentError> {
        target.validate("target")?;
        projectile.validate("projectile")?;
        let relative_velocity = projectile.velocity_at(point) - target.velocity_at(point);
        let impact = Self { point, normal, relative_velocity };
        match impact.validate() {
            // A contact the solver reports as closing may read as separating by rounding.
            Err(DentError::Separating { .. }) => Ok(impact),
            other => other.map(|()| impact),
        }
    }

    /// The same contact in other coordinates: point, normal and velocity through the rigid `map`.
    pub fn transformed(&self, map: Affine3A) -> Self {
        Self {
            point: map.transform_point3(self.point),
            normal: map.transform_vector3(self.normal),
            relative_velocity: map.transform_vector3(self.relative_velocity),
        }
    }
}

/// The dent distance (m) `impact` earns on a target denting with `settings`, or `None` when it
/// makes no dent: the material's threshold / gain / cap on the normal speed, or, when
/// `settings.hardness` is set, the depth whose plastic work equals the kinetic energy the
/// collision removes along the normal (`normal_energy_lost` from both bodies' `target` and
/// `projectile` states; the projectile's shape from `projectile`'s surface), capped by the
/// material. A separating impact makes no dent.
///
/// # Errors
/// Invalid settings, impact or body states.
pub fn decide_dent_distance(
    settings: &DentSettings,
    impact: &Impact,
    target: &BodyState,
    projectile: &BodyState,
    projectile_surface: &Surface<'_>,
) -> Result<Option<f32>, DentError> {
    if matches!(impact.validate(), Err(DentError::Separating { .. })) {
        return Ok(None);
    }
    let Some(distance) = settings.material.dent_distance(impact)? else {
        return Ok(None);
    };
    let Some(hardness) = settings.hardness else {
        return Ok(Some(distance));
    };
    target.validate("target")?;
    projectile.validate("projectile")?;
    let lost = normal_energy_lost(impact, target, projectile);
    let params = DentParams { dent_distance: settings.material.cap, ..settings.params.clone() };
    let distance = energy_dent_distance(&projectile_surface.world_mesh(), impact, &params, hardness, lost)?;
    Ok((distance > 0.0).then_some(distance))
}

/// How far a dynamic projectile moves into the dent it made (world, m): `dent_distance` along
/// the impact's normal when `settings` ask for it, else zero. Moving it lets it rest in the
/// hollow instead of hovering above it; only dynamic projectiles should be moved.
pub fn projectile_offset(settings: &DentSettings, impact: &Impact, dent_distance: f32) -> Vec3 {
    if settings.move_projectile { impact.unit_normal() * dent_distance } else { Vec3::ZERO }
}
