//! One dent made during a run, as the world reports and logs it.

use glam::Vec3;
use serde::Serialize;

/// One dent made during a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DentRecord {
    /// Step at which it happened (1 = after the first step).
    pub step: u64,
    /// The dented body.
    pub target: String,
    /// The body that dented it.
    pub projectile: String,
    /// Contact point, world, m (carried with the target to where it is after the step).
    pub point: Vec3,
    /// Denting normal (into the target), world.
    pub normal: Vec3,
    /// Projectile's velocity relative to the target at the contact, m/s.
    pub relative_velocity: Vec3,
    /// Dent distance used, m (for progressive dents: the accumulated distance).
    pub dent_distance: f32,
    /// Enclosed volume the dent changed, m³, signed (after any rim; zero where not measured:
    /// bending bodies' dents).
    pub volume_change: f64,
    /// The dent's cavity (|volume change| before any rim), m³.
    pub cavity_volume: f64,
}
