//! The collision data a dent starts from.

use glam::Vec3;

use super::DentError;
use crate::mesh::MAX_COORDINATE;

/// Fastest relative velocity an impact may have, units/s (10⁵: 300 times the speed of sound in
/// air when the unit is the metre). Kinetic energies of such speeds stay far inside f32.
pub const MAX_SPEED: f32 = 1.0e5;

/// One contact between a target A (the body being dented) and a projectile B, as a rigid-body
/// solver reports it.
///
/// # Example
/// ```
/// use dentbend::{glam::Vec3, Impact};
/// // B hits the top face of A straight down at 3 m/s.
/// let impact = Impact { point: Vec3::ZERO, normal: -Vec3::Y, relative_velocity: Vec3::new(0.0, -3.0, 0.0) };
/// assert!(impact.validate().is_ok());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    /// Contact point, world units.
    pub point: Vec3,
    /// Denting normal: points from the contact into A (need not be unit length, must be non-zero).
    pub normal: Vec3,
    /// Velocity of B relative to A at the contact point (`v_B + ω_B×r_B − v_A − ω_A×r_A`), m/s.
    /// A zero vector means head-on along `normal`.
    pub relative_velocity: Vec3,
}

impl Impact {
    /// A head-on impact at `point` along `normal`.
    pub fn head_on(point: Vec3, normal: Vec3) -> Self {
        Self { point, normal, relative_velocity: normal }
    }

    /// Checks that every field is finite and the normal is non-zero.
    ///
    /// # Errors
    /// [`DentError::InvalidImpact`] naming the bad field, or [`DentError::Separating`] when the
    /// relative velocity points out of A.
    pub fn validate(&self) -> Result<(), DentError> {
        for (name, v) in [("point", self.point), ("normal", self.normal), ("relative_velocity", self.relative_velocity)]
        {
            if !v.is_finite() {
                return Err(DentError::InvalidImpact(format!("{name} {v} is not finite")));
            }
        }
        if self.point.abs().max_element() > MAX_COORDINATE {
            return Err(DentError::InvalidImpact(format!(
                "point {} lies beyond ±1e6, the supported coordinate range",
                self.point
            )));
        }
        if self.relative_velocity.length() > MAX_SPEED {
            return Err(DentError::InvalidImpact(format!(
                "relative_velocity {} is faster than {MAX_SPEED:e} units/s, the supported range",
                self.relative_velocity
            )));
        }
        let Some(normal) = unit(self.normal) else {
            return Err(DentError::InvalidImpact("normal is the zero vector".into()));
        };
        if self.relative_velocity != Vec3::ZERO && unit(self.relative_velocity).is_none() {
            return Err(DentError::InvalidImpact(format!(
                "relative_velocity {} has no direction in f32",
                self.relative_velocity
            )));
        }
        let normal_speed = self.relative_velocity.dot(normal);
        if normal_speed < -1e-6 * self.relative_velocity.length() {
            return Err(DentError::Separating { normal_speed });
        }
        Ok(())
    }

    /// Unit denting normal (zero if [`validate`](Self::validate) would fail).
    pub fn unit_normal(&self) -> Vec3 {
        unit(self.normal).unwrap_or(Vec3::ZERO)
    }

    /// Unit viewing direction of the Z-buffer: the relative velocity's direction, or the normal
    /// when the velocity is zero.
    pub fn view_direction(&self) -> Vec3 {
        unit(self.relative_velocity).unwrap_or_else(|| self.unit_normal())
    }

    /// The same contact seen from B: normal and velocity reversed.
    pub fn reversed(&self) -> Self {
        Self { point: self.point, normal: -self.normal, relative_velocity: -self.relative_velocity }
    }
}

/// `v` scaled to unit length, computed without overflow for huge components; `None` for the zero
/// vector and non-finite input.
fn unit(v: Vec3) -> Option<Vec3> {
    let largest = v.abs().max_element();
    (largest > 0.0 && largest.is_finite()).then(|| (v / largest).try_normalize()).flatten()
}
