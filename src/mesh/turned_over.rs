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
}
