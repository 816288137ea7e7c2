//! The GPU-vs-CPU skinning tolerance shared by `parity_skin` and `sim_gpu_skinning` (the reasoning
//! is in `tests/parity_skin.rs`'s module comment): a position component may move by a few ε of
//! its blend terms' magnitude, a unit normal by a few ε times its cofactor terms' magnitude over
//! `|cof(A)·n|`.

use dentbend::cpu::{SkinBone, SkinInfluence};
use dentbend::glam::DVec3;

/// Position tolerance in ε of the terms' magnitude.
pub const POSITION_ULPS: f64 = 16.0;
/// Normal tolerance in ε·κ.
pub const NORMAL_ULPS: f64 = 32.0;
/// ε = 2⁻²³, one ulp at 1.
pub const EPS: f64 = f32::EPSILON as f64;

/// The absolute values of one vertex's blend terms in f64: `|M|` with `M = Σ wᵢ·Sᵢ` and the
/// missing weight on the identity, each entry the sum of its terms' absolute values.
pub fn blend_magnitude(bones: &[SkinBone], influence: &SkinInfluence) -> [[f64; 4]; 3] {
    let mut rows = [[0.0; 4]; 3];
    let mut total = 0.0;
    for (&b, &w) in influence.bones.iter().zip(&influence.weights) {
        for (row, bone_row) in rows.iter_mut().zip(&bones[b as usize].rows) {
            for (entry, value) in row.iter_mut().zip(bone_row) {
                *entry += (f64::from(w) * f64::from(*value)).abs();
            }
        }
        total += f64::from(w);
    }
    for (r, row) in rows.iter_mut().enumerate() {
        row[r] += (1.0 - total).abs();
    }
    rows
}

/// Tolerance of position component `r` of a vertex at rest position `|p|` (component-wise
/// absolute, f64) blended with magnitude `m`, m.
pub fn position_tolerance(m: &[[f64; 4]; 3], p: DVec3, r: usize) -> f64 {
    let row = m[r];
    let scale = row[0] * p.x + row[1] * p.y + row[2] * p.z + row[3];
    POSITION_ULPS * EPS * scale.max(f64::MIN_POSITIVE)
}

/// The magnitudes of the cofactor terms of `m` applied to the normal's absolute values `n`:
/// per component of `cof(A)·n`, the sum of its products' absolute values.
pub fn cofactor_terms(m: &[[f64; 4]; 3], n: DVec3) -> DVec3 {
    let a = |r: usize, c: usize| m[r][c];
    DVec3::new(
        (a(1, 1) * a(2, 2) + a(1, 2) * a(2, 1)) * n.x
            + (a(1, 2) * a(2, 0) + a(1, 0) * a(2, 2)) * n.y
            + (a(1, 0) * a(2, 1) + a(1, 1) * a(2, 0)) * n.z,
        (a(2, 1) * a(0, 2) + a(2, 2) * a(0, 1)) * n.x
            + (a(2, 2) * a(0, 0) + a(2, 0) * a(0, 2)) * n.y
            + (a(2, 0) * a(0, 1) + a(2, 1) * a(0, 0)) * n.z,
        (a(0, 1) * a(1, 2) + a(0, 2) * a(1, 1)) * n.x
            + (a(0, 2) * a(1, 0) + a(0, 0) * a(1, 2)) * n.y
            + (a(0, 0) * a(1, 1) + a(0, 1) * a(1, 0)) * n.z,
    )
}
