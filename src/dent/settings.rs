//! How a body dents when it is hit (paper Algorithm 1, lines 14–20).

use super::error::invalid;
use super::{DentError, DentMaterial, DentParams, Impact};

/// A dentable body's denting behaviour.
#[derive(Debug, Clone)]
pub struct DentSettings {
    /// Threshold, gain and cap of the dent distance on the normal impact speed.
    pub material: DentMaterial,
    /// Shape of the dent (σ, resolution, smoothing, falloff…); `dent_distance` is replaced by
    /// the distance each hit earns.
    pub params: DentParams,
    /// Energy model: when set, the hit's dent distance is the one whose plastic work,
    /// `hardness` × the volume the projectile's tip sweeps into the surface, equals the kinetic
    /// energy the collision removes along the normal (capped by `material.cap`). Pa = J/m³.
    pub hardness: Option<f32>,
    /// Move the projectile into the dent (by the dent distance along the normal), so it rests
    /// in the hollow it made instead of hovering above it.
    pub move_projectile: bool,
    /// Repeated hits by the same body while the contact lasts deepen one dent from the
    /// pre-dent surface (the paper's Figure 3) instead of stacking new dents.
    pub progressive: bool,
}

impl DentSettings {
    /// Threshold `threshold` m/s, `gain` m per m/s above it, at most `cap` m; default dent shape.
    pub fn new(threshold: f32, gain: f32, cap: f32) -> Self {
        Self {
            material: DentMaterial { threshold, gain, cap },
            params: DentParams::new(cap),
            hardness: None,
            move_projectile: false,
            progressive: false,
        }
    }

    /// Whether a hit at `impact` can dent at all: its speed along the denting normal is above the
    /// material's threshold (m/s). A cheap test to run on every contact before gathering the
    /// bodies' states for [`Hit`](crate::damage::Hit)s; [`decide_dent_distance`](super::decide_dent_distance)
    /// makes the same test first, so skipping what fails it changes nothing.
    pub fn may_dent(&self, impact: &Impact) -> bool {
        impact.relative_velocity.dot(impact.unit_normal()) > self.material.threshold
    }

    /// Checks the material, the hardness and the dent shape.
    ///
    /// # Errors
    /// [`DentError::InvalidParameter`] naming the bad field.
    pub fn validate(&self) -> Result<(), DentError> {
        self.material.validate()?;
        if let Some(h) = self.hardness
            && !(h.is_finite() && h > 0.0)
        {
            return Err(invalid("hardness", h, "must be finite and > 0"));
        }
        DentParams { dent_distance: self.material.cap, ..self.params.clone() }.validate()
    }
}
