//! Triangle shape quality, to see whether repeated dents wear a mesh into slivers.
//!
//! The quality of a triangle with area A and edge lengths a, b, c is q = 4√3·A / (a² + b² + c²):
//! 1 for an equilateral triangle, smaller the flatter it is, 0 for a degenerate one (three points
//! on a line). It is scale-free, and 4√3 is the factor that makes the equilateral triangle 1
//! (A = √3/4·s², a² + b² + c² = 3s²). A right isosceles triangle, the cells of the built-in
//! boxes, has q = √3/2 ≈ 0.866.

use dentbend::TriMesh;
use dentbend::glam::DVec3;
use serde::Serialize;

/// q = 4√3·A / (a² + b² + c²) of the triangle with corners `a`, `b`, `c`; 0 when all three
/// coincide.
pub fn quality(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let twice_area = (b - a).cross(c - a).length();
    let squares = (b - a).length_squared() + (c - b).length_squared() + (a - c).length_squared();
    if squares > 0.0 { 2.0 * 3f64.sqrt() * twice_area / squares } else { 0.0 }
}

/// The worst and the mean triangle quality of a mesh.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct QualityStats {
    /// Smallest q over the triangles.
    pub min: f64,
    /// Mean q over the triangles.
    pub mean: f64,
}

/// Quality statistics of every triangle of `mesh`.
pub fn quality_stats(mesh: &TriMesh) -> QualityStats {
    let p = mesh.positions();
    let (mut min, mut sum) = (f64::INFINITY, 0.0);
    for f in mesh.faces() {
        let [a, b, c] = f.map(|v| p[v as usize].as_dvec3());
        let q = quality(a, b, c);
        min = min.min(q);
        sum += q;
    }
    QualityStats { min, mean: sum / mesh.face_count() as f64 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equilateral_is_one_and_flat_is_zero() {
        let equilateral = quality(DVec3::ZERO, DVec3::X, DVec3::new(0.5, 3f64.sqrt() / 2.0, 0.0));
        assert!((equilateral - 1.0).abs() < 1e-12, "{equilateral}");
        let right_isosceles = quality(DVec3::ZERO, DVec3::X, DVec3::Y);
        assert!((right_isosceles - 3f64.sqrt() / 2.0).abs() < 1e-12, "{right_isosceles}");
        assert_eq!(quality(DVec3::ZERO, DVec3::X, 2.0 * DVec3::X), 0.0);
        assert_eq!(quality(DVec3::ONE, DVec3::ONE, DVec3::ONE), 0.0);
        // Scale-free: the same shape 1000× larger.
        let big = quality(DVec3::ZERO, 1e3 * DVec3::X, 1e3 * DVec3::Y);
        assert!((big - right_isosceles).abs() < 1e-12);
    }
}
