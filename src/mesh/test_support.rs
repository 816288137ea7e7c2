//! Helpers for the crate's unit tests: a seeded xorshift generator and a meshed height field.

use glam::Vec3;

/// Uniform numbers in `[0, 1]` from a 32-bit xorshift seeded with `seed` (non-zero).
pub(crate) fn unit_floats(mut seed: u32) -> impl FnMut() -> f32 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed as f32 / u32::MAX as f32
    }
}

/// Uniform numbers in `[−½, ½]`, as [`unit_floats`] less a half.
pub(crate) fn centred_floats(seed: u32) -> impl FnMut() -> f32 {
    let mut unit = unit_floats(seed);
    move || unit() - 0.5
}

/// A grid of `n × n` quads (two faces each, quad `(i, j)` being faces `2(n·i + j)` and
/// `2(n·i + j) + 1`) over the unit square of the xz-plane at height `h(x, z)`, wound to face +y.
pub(crate) fn sheet(n: usize, h: impl Fn(f32, f32) -> f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut positions = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let (x, z) = (i as f32 / n as f32, j as f32 / n as f32);
            positions.push(Vec3::new(x, h(x, z), z));
        }
    }
    let id = |i: usize, j: usize| (i * (n + 1) + j) as u32;
    let mut faces = Vec::new();
    for i in 0..n {
        for j in 0..n {
            faces.push([id(i, j), id(i, j + 1), id(i + 1, j + 1)]);
            faces.push([id(i, j), id(i + 1, j + 1), id(i + 1, j)]);
        }
    }
    (positions, faces)
}
