//! The scenes of the examples `rapier_rain`, `rapier_plank`, `rapier_network` and `rapier_wall`, shared with
//! their tests.

pub mod network;
pub mod plank;
pub mod rain;
pub mod report;
pub mod wall;

/// A small deterministic generator (64-bit LCG) for scene jitter: no dependency, same numbers
/// on every platform.
#[derive(Debug, Clone)]
pub struct Lcg(u64);

impl Lcg {
    /// Seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407))
    }

    /// Uniform in [0, 1).
    pub fn next_f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next_f32()
    }
}
