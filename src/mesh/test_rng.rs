//! A seeded xorshift generator for the mesh layer's randomized unit tests.

/// Uniform numbers in `[0, 1]` from a 32-bit xorshift seeded with `seed` (non-zero).
pub(crate) fn unit_floats(mut seed: u32) -> impl FnMut() -> f32 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed as f32 / u32::MAX as f32
    }
}
