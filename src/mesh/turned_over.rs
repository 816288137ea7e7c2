//! Faces a displacement turns over: whose normal after points against their normal before.
//!
//! A face is turned over when, in f64 on the f32 positions, with `n` the doubled-area normal
//! `(p₁ − p₀) × (p₂ − p₀)` and `L` the longest edge,
//!
//! * before, it has an orientation to lose: `|n_before| > SHAPE_TOLERANCE · L_before²` (a
//!   sliver thinner than that, smallest angle below about 0.06°, has a normal that any
//!   sub-ulp nudge of a corner swings around; it is left to the crossing test), and
//! * after, its doubled area along the unit normal before is negative beyond the same
//!   tolerance: `n_after · n̂_before < −SHAPE_TOLERANCE · L_after²`. A face squeezed flat (to
//!   a sliver of either sign within the tolerance) is not counted: flattening is not turning
//!   over, and rounding alone can give it either sign.
//!
//! Turning over without any crossing happens where a dent drags a face's corners past each
//! other sideways (a steep crater wall pulling a thin face through itself).

use glam::{DVec3, Vec3};

/// Doubled area over the longest edge squared below which a face's orientation is not trusted
/// (an equilateral face has √3/2 ≈ 0.87).
pub const SHAPE_TOLERANCE: f64 = 1e-3;

/// Whether `face` is turned over from `before` to `after` (module documentation).
pub(crate) fn is_turned_over(face: [u32; 3], before: &[Vec3], after: &[Vec3]) -> bool {
    let (n_before, l_before) = normal_and_longest_sq(face, before);
    let length = n_before.length();
    // Also false for a NaN length: no orientation to lose.
    let oriented = length > SHAPE_TOLERANCE * l_before;
    if !oriented {
        return false;
    }
    let (n_after, l_after) = normal_and_longest_sq(face, after);
    n_after.dot(n_before) / length < -SHAPE_TOLERANCE * l_after
}

/// Whether `face` could be turned over (as [`is_turned_over`] decides) at some scale
/// `s ∈ [0, 1]` of its corners' displacement from `before` to `after`, the scaled positions
/// written in f32 as `b + (a − b)·s`; `false` when this bound clears it:
///
/// with edges `e₁, e₂` from the first corner before, `n` their cross product and `δ₁, δ₂` the
/// edges' changes from before to after, an edge at scale `s` is `e_k + s·δ_k` up to the
/// rounding of the written positions (`η`, at most a few f32 ulps of the corners' largest
/// coordinate and displacement, per corner), so with `r_k = |δ_k| + 2η`,
/// `n(s)·n̂ ≥ |n| − r₁|e₂| − |e₁|r₂ − r₁r₂`: while that is positive the face keeps its
/// orientation at every scale (and a face with no orientation to lose is never turned over).
pub(crate) fn may_turn_over(face: [u32; 3], before: &[Vec3], after: &[Vec3]) -> bool {
    let [b0, b1, b2] = face.map(|v| before[v as usize]);
    let [a0, a1, a2] = face.map(|v| after[v as usize]);
    let extent = [b0, b1, b2, a0, a1, a2].iter().fold(0.0f32, |m, p| m.max(p.abs().max_element()));
    let rounding = 4.0 * f64::from(f32::EPSILON) * 3f64.sqrt() * 2.0 * f64::from(extent);
    let (e1, e2) = (b1.as_dvec3() - b0.as_dvec3(), b2.as_dvec3() - b0.as_dvec3());
    let change = |a: Vec3, b: Vec3| (a.as_dvec3() - b.as_dvec3()) - (a0.as_dvec3() - b0.as_dvec3());
    let (r1, r2) = (change(a1, b1).length() + 2.0 * rounding, change(a2, b2).length() + 2.0 * rounding);
    let n = e1.cross(e2).length();
    let (l1, l2) = (e1.length(), e2.length());
    // The f64 terms carry relative errors near 10⁻¹⁶; the margin covers them many times over.
    // A NaN anywhere clears nothing.
    let cleared = n > (r1 * l2 + l1 * r2 + r1 * r2) * (1.0 + 1e-9);
    !cleared
}

/// Doubled-area normal and longest edge squared of `face` at `positions`.
fn normal_and_longest_sq(face: [u32; 3], positions: &[Vec3]) -> (DVec3, f64) {
    let [a, b, c] = face.map(|v| positions[v as usize].as_dvec3());
    let (ab, bc, ca) = (b - a, c - b, a - c);
    let longest = ab.length_squared().max(bc.length_squared()).max(ca.length_squared());
    (ab.cross(c - a), longest)
}

/// Indices of the faces of `faces` that moving the vertices from `before` to `after` turns
/// over, ascending (the tolerance: [`SHAPE_TOLERANCE`], module documentation). Faces whose
/// corners did not move are skipped.
///
/// # Example
/// ```
/// use dentbend::glam::Vec3;
/// let before = [Vec3::ZERO, Vec3::X, Vec3::Y];
/// // The third corner dragged past the first edge: the face now faces the other way.
/// let after = [Vec3::ZERO, Vec3::X, -Vec3::Y];
/// assert_eq!(dentbend::mesh::turned_over_faces(&[[0, 1, 2]], &before, &after), vec![0]);
/// ```
///
/// # Panics
/// When a face names a vertex outside `before` or `after` (a [`TriMesh`](super::TriMesh)'s
/// faces never do).
pub fn turned_over_faces(faces: &[[u32; 3]], before: &[Vec3], after: &[Vec3]) -> Vec<u32> {
    let moved = |face: &[u32; 3]| face.iter().any(|&v| before[v as usize] != after[v as usize]);
    (0..faces.len() as u32)
        .filter(|&f| {
            let face = faces[f as usize];
            moved(&face) && is_turned_over(face, before, after)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A face dragged over counts; squeezed flat (either sign within the tolerance), or a sliver
    /// before, it does not.
    #[test]
    fn turned_over_beyond_the_tolerance_only() {
        let before = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let face = [0, 1, 2];
        let with_third = |p: Vec3| [Vec3::ZERO, Vec3::X, p];
        assert!(is_turned_over(face, &before, &with_third(Vec3::new(0.5, -0.5, 0.0))));
        // Tilted up to 89° and squeezed onto its first edge: not over.
        assert!(!is_turned_over(face, &before, &with_third(Vec3::new(0.0, 0.02, 1.0))));
        // Doubled area along the old normal −0.5·10⁻³ with L² = 1 (the first edge): within the
        // tolerance of 10⁻³.
        assert!(!is_turned_over(face, &before, &with_third(Vec3::new(0.5, -0.5e-3, 0.0))));
        // −2·10⁻³ with L² = 1: beyond it.
        assert!(is_turned_over(face, &before, &with_third(Vec3::new(0.5, -2e-3, 0.0))));
        // A sliver before (doubled area 10⁻⁴ over L² = 1) has no trusted orientation.
        let sliver = with_third(Vec3::new(0.5, 1e-4, 0.0));
        assert!(!is_turned_over(face, &sliver, &with_third(Vec3::new(0.5, -0.5, 0.0))));
        assert_eq!(turned_over_faces(&[face], &before, &before), Vec::<u32>::new());
    }

    /// Wherever the bound clears a face, no scale of its displacement turns it over, written as
    /// the guard writes it; and the bound clears faces that move nearly together.
    #[test]
    fn a_face_the_bound_clears_never_turns_over() {
        let mut next = crate::mesh::test_support::centred_floats(5);
        let (mut cleared, mut turned_seen) = (0, 0);
        for round in 0..3000 {
            let before: Vec<Vec3> = (0..3).map(|_| Vec3::new(next(), next(), next()) * 2.0 + 100.0).collect();
            // Displacements from a common shift plus a spread from tiny to larger than the face.
            let spread = 10f32.powf(-4.0 + 5.0 * (round % 100) as f32 / 100.0);
            let shift = Vec3::new(next(), next(), next()) * 3.0;
            let after: Vec<Vec3> =
                before.iter().map(|&p| p + shift + Vec3::new(next(), next(), next()) * spread).collect();
            let face = [0, 1, 2];
            let turns = (0..=64).any(|k| {
                let s = k as f32 / 64.0;
                let at: Vec<Vec3> = before.iter().zip(&after).map(|(&b, &a)| b + (a - b) * s).collect();
                is_turned_over(face, &before, &at)
            });
            turned_seen += usize::from(turns);
            if !may_turn_over(face, &before, &after) {
                cleared += 1;
                assert!(!turns, "round {round}: cleared, yet turned over: {before:?} → {after:?}");
            }
        }
        assert!(cleared > 1000 && turned_seen > 100, "{cleared} cleared, {turned_seen} turned over");
    }
}
