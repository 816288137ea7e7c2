//! Global settings of a world: time step, gravity, iterations, sleep, contact tolerances.

use glam::Vec3;

use super::SimError;
use super::error::invalid;

/// Global settings of a world.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WorldSettings {
    /// Gravity, m/s².
    pub gravity: Vec3,
    /// Time step, s.
    pub dt: f32,
    /// Sweeps of the collision (restitution) phase.
    pub collision_iterations: u32,
    /// Sweeps of the contact phase (the last one with shock propagation).
    pub contact_iterations: u32,
    /// Closing speeds below this bounce with no restitution (resting contact), m/s.
    pub restitution_threshold: f32,
    /// Overlap left alone by the position correction, m.
    pub slop: f32,
    /// Fraction of the overlap beyond the slop removed per step (by a split position
    /// correction that adds no velocity).
    pub baumgarte: f32,
    /// Contacts are sought this far beyond touching, plus how far the bodies move in a step, m.
    pub margin: f32,
    /// GBF shock propagation in the last contact sweep (stable stacks).
    pub shock_propagation: bool,
    /// An island of touching bodies falls asleep when every body in it has been slower than this
    /// (centre plus rim, velocities smoothed over 0.1 s), m/s, for `sleep_time`.
    pub sleep_speed: f32,
    /// Seconds of stillness before a body sleeps; ≤ 0 disables sleeping.
    pub sleep_time: f32,
    /// Fraction of angular velocity lost per second (air drag stand-in), 1/s.
    pub angular_damping: f32,
    /// Rolling (and spinning) resistance coefficient, dimensionless: at each resting contact
    /// the contact phase resists the bodies' relative rotation with an angular impulse of at
    /// most this × the contact's normal impulse × the rolling radius (the shorter distance from
    /// a centre of mass to the point). Real contacts are patches, not points; without this a
    /// ball rolls on a floor or spins on its support until `angular_damping` stops it, and a
    /// pile never settles. A ball stays on slopes with tan α ≤ this and rolls down steeper ones
    /// at (5/7) g (sin α − this × cos α). 0.005 (a 0.5 mm lever on a 10 cm ball, hard materials)
    /// stops a ball rolling at 5 cm/s on a floor in about 1.5 s; much larger values let balls
    /// dropped onto each other stand as columns.
    pub rolling_resistance: f32,
    /// Most a body's angular velocity may turn it in one step, rad (finite, > 0): a faster spin
    /// left by a step is scaled down to this (as Box2D and Bullet do). The position update's
    /// first-order quaternion step and the joints' linearization of it are only accurate for
    /// modest turns per step; a thin strut rolling on its axis (inertia m r²/2 of a 2.5 cm
    /// radius) can be spun past 10 rad per step by one friction impulse, and its joints then
    /// run away. π/2 is 94 rad/s at 60 steps per second.
    pub max_turn: f32,
    /// Fastest a joint's drift (anchors apart, m) is closed, m/s (finite, > 0). Pre-stabilization
    /// removes drift with real velocity, so closing d metres in one step leaves the bodies
    /// d/dt faster: a 10 cm drift closed at once is 6 m/s at 60 steps per second, and a
    /// truss whose joints were torn apart that way by one hard step gained energy step after
    /// step. Drift beyond this × dt is left for the following steps.
    pub joint_correction_speed: f32,
    /// Fastest a locked joint's angular drift (relative orientation off its target, rad) is
    /// closed, rad/s (finite, > 0); as `joint_correction_speed`.
    pub joint_correction_spin: f32,
}

impl Default for WorldSettings {
    fn default() -> Self {
        Self {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            dt: 1.0 / 60.0,
            collision_iterations: 5,
            contact_iterations: 12,
            restitution_threshold: 0.5,
            slop: 0.002,
            baumgarte: 0.2,
            margin: 0.01,
            shock_propagation: true,
            sleep_speed: 0.05,
            sleep_time: 0.5,
            angular_damping: 0.05,
            rolling_resistance: 0.005,
            max_turn: std::f32::consts::FRAC_PI_2,
            joint_correction_speed: 1.0,
            joint_correction_spin: std::f32::consts::PI,
        }
    }
}

impl WorldSettings {
    /// `spin` (rad/s) scaled down to at most `max_turn` per step.
    pub(crate) fn limit_spin(&self, spin: Vec3) -> Vec3 {
        let limit = self.max_turn / self.dt;
        let speed = spin.length();
        if speed > limit { spin * (limit / speed) } else { spin }
    }

    /// Checks every number.
    ///
    /// # Errors
    /// [`SimError::Invalid`] naming the first bad field.
    pub fn validate(&self) -> Result<(), SimError> {
        if !(self.gravity.is_finite() && self.gravity.length() <= 1.0e4) {
            return Err(invalid("gravity", self.gravity, "must be finite and at most 1e4 m/s² (a thousand g)"));
        }
        if !(self.dt.is_finite() && self.dt > 0.0 && self.dt <= 1.0) {
            return Err(invalid("dt", self.dt, "must be in (0, 1] s"));
        }
        for (what, value) in [
            ("restitution_threshold", self.restitution_threshold),
            ("slop", self.slop),
            ("margin", self.margin),
            ("sleep_speed", self.sleep_speed),
            ("angular_damping", self.angular_damping),
            ("rolling_resistance", self.rolling_resistance),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(invalid(what, value, "must be finite and >= 0"));
            }
        }
        for (what, value) in [
            ("max_turn", self.max_turn),
            ("joint_correction_speed", self.joint_correction_speed),
            ("joint_correction_spin", self.joint_correction_spin),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(invalid(what, value, "must be finite and > 0"));
            }
        }
        if !(0.0..=1.0).contains(&self.baumgarte) {
            return Err(invalid("baumgarte", self.baumgarte, "must be in [0, 1]"));
        }
        if !self.sleep_time.is_finite() {
            return Err(invalid("sleep_time", self.sleep_time, "must be finite"));
        }
        if self.contact_iterations == 0 || self.contact_iterations > 1000 || self.collision_iterations > 1000 {
            return Err(invalid("contact_iterations", self.contact_iterations, "must be in 1..=1000"));
        }
        Ok(())
    }
}
