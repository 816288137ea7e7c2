//! A body's sleep bookkeeping (the islands that fall asleep are in `sleep.rs`).

use glam::Vec3;

/// A body's sleep bookkeeping.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Activity {
    /// Seconds the body has been still.
    pub still_for: f32,
    /// Whether the body is asleep (not integrated until something wakes it).
    pub asleep: bool,
    /// Smoothed linear velocity, m/s, and angular velocity, rad/s.
    pub smoothed: [Vec3; 2],
    /// The island the body fell asleep with (woken together).
    pub island: u64,
}

impl Activity {
    /// Awake, with its smoothing restarted.
    pub fn wake(&mut self) {
        *self = Self::default();
    }

    /// Whether a body moving at `velocity` (linear, m/s, and angular, rad/s) moves enough to
    /// wake what it touches: not asleep, and either its smoothed or its current speed (centre
    /// plus rim at `radius`, m) above `threshold`, m/s.
    pub fn disturbs(&self, [linear, angular]: [Vec3; 2], radius: f32, threshold: f32) -> bool {
        let speed = |v: Vec3, w: Vec3| v.length() + w.length() * radius;
        !self.asleep
            && (speed(self.smoothed[0], self.smoothed[1]) >= threshold || speed(linear, angular) >= 2.0 * threshold)
    }
}
