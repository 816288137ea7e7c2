//! How deep a dent an impact makes (paper Algorithm 1, line 2): a threshold, a gain and a cap on
//! the normal impact speed.

use super::error::invalid;
use super::{DentError, Impact};

/// A dentable material's response to impact speed: no dent below `threshold`, then
/// `d = gain·(v_n − threshold)`, at most `cap`.
///
/// # Example
/// ```
/// use dentbend::{dent::DentMaterial, glam::Vec3, Impact};
/// let steel = DentMaterial { threshold: 2.0, gain: 0.01, cap: 0.3 };
/// let hit = Impact { point: Vec3::ZERO, normal: -Vec3::Y, relative_velocity: Vec3::new(1.0, -12.0, 0.0) };
/// let d = steel.dent_distance(&hit)?.unwrap(); // 0.01·(12 − 2) m
/// assert!((d - 0.1).abs() < 1e-6);
/// # Ok::<(), dentbend::DentError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DentMaterial {
    /// Normal impact speed below which nothing dents, m/s (≥ 0).
    pub threshold: f32,
    /// Dent distance per m/s above the threshold, world units per m/s (≥ 0).
    pub gain: f32,
    /// Largest dent distance, world units (> 0).
    pub cap: f32,
}

impl DentMaterial {
    /// The dent distance for `impact`, or `None` when its normal speed does not exceed the
    /// threshold (the relative velocity's component along the denting normal, m/s).
    ///
    /// # Errors
    /// An invalid impact, or a material field out of range.
    pub fn dent_distance(&self, impact: &Impact) -> Result<Option<f32>, DentError> {
        self.validate()?;
        impact.validate()?;
        let normal_speed = impact.relative_velocity.dot(impact.unit_normal());
        if normal_speed <= self.threshold {
            return Ok(None);
        }
        let d = (self.gain * (normal_speed - self.threshold)).min(self.cap);
        Ok((d > 0.0).then_some(d))
    }

    pub(crate) fn validate(&self) -> Result<(), DentError> {
        if !(self.threshold.is_finite() && self.threshold >= 0.0) {
            return Err(invalid("threshold", self.threshold, "must be finite and >= 0"));
        }
        if !(self.gain.is_finite() && self.gain >= 0.0) {
            return Err(invalid("gain", self.gain, "must be finite and >= 0"));
        }
        if !(self.cap.is_finite() && self.cap > 0.0) {
            return Err(invalid("cap", self.cap, "must be finite and > 0"));
        }
        Ok(())
    }
}
