//! A rigid body as the dent decision sees it, in the caller's solver's terms: where its centre
//! of mass is, how it moves, and how hard it is to push (for the contact's relative velocity and
//! the energy model). World coordinates, read before the solver's step.

use glam::{Mat3, Vec3};

use super::DentError;

/// One body's state at a contact, world coordinates, before the step that resolved the contact.
///
/// Fixed and kinematic bodies have `inverse_mass` 0 and a zero `inverse_inertia` (they take no
/// impulse); their velocities still count in the relative velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState {
    /// Centre of mass, world, m.
    pub center_of_mass: Vec3,
    /// Velocity of the centre of mass, m/s.
    pub linear_velocity: Vec3,
    /// Angular velocity, world, rad/s.
    pub angular_velocity: Vec3,
    /// 1 / mass, 1/kg (0: fixed or kinematic).
    pub inverse_mass: f32,
    /// Inverse inertia tensor about the centre of mass, world axes, 1/(kg·m²).
    pub inverse_inertia: Mat3,
    /// Coefficient of restitution of the body's surface, in [0, 1].
    pub restitution: f32,
}

impl BodyState {
    /// A body that does not move and takes no impulse (the ground, a wall).
    pub const FIXED: Self = Self {
        center_of_mass: Vec3::ZERO,
        linear_velocity: Vec3::ZERO,
        angular_velocity: Vec3::ZERO,
        inverse_mass: 0.0,
        inverse_inertia: Mat3::ZERO,
        restitution: 0.0,
    };

    /// A free body of `mass` kg and world inverse inertia `inverse_inertia` at `center_of_mass`,
    /// moving at `linear_velocity` m/s and spinning at `angular_velocity` rad/s, restitution 0.
    pub fn moving(
        center_of_mass: Vec3,
        linear_velocity: Vec3,
        angular_velocity: Vec3,
        mass: f32,
        inverse_inertia: Mat3,
    ) -> Self {
        let inverse_mass = if mass > 0.0 { 1.0 / mass } else { 0.0 };
        Self { center_of_mass, linear_velocity, angular_velocity, inverse_mass, inverse_inertia, restitution: 0.0 }
    }

    /// Velocity of the body's material point at `point` (world), m/s: v + ω × r.
    pub fn velocity_at(&self, point: Vec3) -> Vec3 {
        self.linear_velocity + self.angular_velocity.cross(point - self.center_of_mass)
    }

    /// The body's inverse effective mass along unit `normal` at `point` (rotation included),
    /// 1/kg: 1/m + (I⁻¹ (r × n)) · (r × n).
    pub fn inverse_mass_along(&self, point: Vec3, normal: Vec3) -> f32 {
        let rn = (point - self.center_of_mass).cross(normal);
        self.inverse_mass + (self.inverse_inertia * rn).dot(rn)
    }

    /// Checks that every field is finite, the inverse mass and inertia are not negative and the
    /// restitution is in [0, 1]; `name` says which body in the error.
    ///
    /// # Errors
    /// [`DentError::InvalidBody`] naming the body and the field.
    pub fn validate(&self, name: &str) -> Result<(), DentError> {
        let bad = |field: &str, value: String| DentError::InvalidBody {
            body: name.to_owned(),
            field: field.to_owned(),
            value,
        };
        for (field, v) in [
            ("center_of_mass", self.center_of_mass),
            ("linear_velocity", self.linear_velocity),
            ("angular_velocity", self.angular_velocity),
        ] {
            if !v.is_finite() {
                return Err(bad(field, v.to_string()));
            }
        }
        if !(self.inverse_mass.is_finite() && self.inverse_mass >= 0.0) {
            return Err(bad("inverse_mass", self.inverse_mass.to_string()));
        }
        let diagonal =
            Vec3::new(self.inverse_inertia.x_axis.x, self.inverse_inertia.y_axis.y, self.inverse_inertia.z_axis.z);
        if !self.inverse_inertia.is_finite() || diagonal.min_element() < 0.0 {
            return Err(bad("inverse_inertia", format!("{:?}", self.inverse_inertia)));
        }
        if !(0.0..=1.0).contains(&self.restitution) {
            return Err(bad("restitution", self.restitution.to_string()));
        }
        Ok(())
    }
}

impl Default for BodyState {
    fn default() -> Self {
        Self::FIXED
    }
}
