//! Inputs shared by the envelope parity tests.

use dentbend::cpu::{self, EnvelopeParams};

use super::SplitMix64;

/// The CPU rows pass on one dent.
pub fn cpu_rows(params: &EnvelopeParams, profile: &[f32]) -> Vec<f32> {
    let mut out = vec![f32::NAN; profile.len()];
    cpu::envelope_rows(params, profile, &mut out);
    out
}

/// A `res × res` profile where each cell is a source with probability `density`, of height in
/// [0.01, 1)·`d`.
pub fn random_profile(rng: &mut SplitMix64, res: u32, density: f32, d: f32) -> Vec<f32> {
    (0..res * res).map(|_| if rng.next_f32() < density { d * rng.range_f32(0.01, 1.0) } else { 0.0 }).collect()
}
