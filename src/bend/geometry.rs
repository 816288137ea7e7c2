//! Small geometric queries shared by the bending modules: points against segments and triangles,
//! solid angles, segment–triangle crossings. All lengths are in the mesh's units (metres).

use glam::{DVec3, Vec3};

/// Parameter `t ∈ [0, 1]` of the point of segment `a`–`b` closest to `p` (0 for a degenerate
/// segment).
pub(crate) fn segment_param(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let ab = b - a;
    let len2 = ab.length_squared();
    if len2 > 0.0 { ((p - a).dot(ab) / len2).clamp(0.0, 1.0) } else { 0.0 }
}

/// Squared distance from `p` to the segment `a`–`b`.
pub(crate) fn segment_dist2(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let t = segment_param(p, a, b);
    p.distance_squared(a + (b - a) * t)
}

/// Squared distance from `p` to the triangle `a`, `b`, `c` (Ericson, *Real-Time Collision
/// Detection* §5.1.5, by Voronoi regions).
#[inline]
pub(crate) fn triangle_dist2(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length_squared();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length_squared();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return p.distance_squared(a + ab * v);
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length_squared();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return p.distance_squared(a + ac * w);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return p.distance_squared(b + (c - b) * w);
    }
    let denom = va + vb + vc;
    if denom.abs() <= f32::MIN_POSITIVE {
        // Degenerate triangle that slipped past the edge regions: nearest of its corners.
        return ap.length_squared().min(bp.length_squared()).min(cp.length_squared());
    }
    let (v, w) = (vb / denom, vc / denom);
    p.distance_squared(a + ab * v + ac * w)
}

/// Signed solid angle of triangle `a`, `b`, `c` seen from `p`, steradians (Van Oosterom and
/// Strackee); positive when the triangle winds counter-clockwise seen from `p`'s side opposite
/// its normal, so a closed outward-wound mesh sums to 4π at an interior point.
pub(crate) fn solid_angle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (a, b, c) = (a - p, b - p, c - p);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let numerator = a.dot(b.cross(c));
    let denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    2.0 * numerator.atan2(denominator)
}

/// Whether the closed segment `p`–`q` meets the triangle `a`, `b`, `c` (Möller–Trumbore with the
/// segment's parameter restricted to `[0, 1]`; a segment in the triangle's plane counts as a miss).
pub(crate) fn segment_hits_triangle(p: Vec3, q: Vec3, a: Vec3, b: Vec3, c: Vec3) -> bool {
    let dir = q - p;
    let (e1, e2) = (b - a, c - a);
    let h = dir.cross(e2);
    let det = e1.dot(h);
    if det.abs() <= f32::EPSILON * e1.length() * e2.length() * dir.length() {
        return false;
    }
    let inv = 1.0 / det;
    let s = p - a;
    let u = s.dot(h) * inv;
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let qv = s.cross(e1);
    let v = dir.dot(qv) * inv;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let t = e2.dot(qv) * inv;
    (0.0..=1.0).contains(&t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_distance_regions() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        assert_eq!(triangle_dist2(Vec3::new(0.25, 0.25, 2.0), a, b, c), 4.0);
        assert_eq!(triangle_dist2(Vec3::new(-1.0, -1.0, 0.0), a, b, c), 2.0);
        assert!((triangle_dist2(Vec3::new(1.0, 1.0, 0.0), a, b, c) - 0.5).abs() < 1e-6);
        assert_eq!(triangle_dist2(Vec3::new(0.5, -2.0, 0.0), a, b, c), 4.0);
    }

    #[test]
    fn solid_angle_of_octant() {
        let s = solid_angle(DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z);
        assert!((s - std::f64::consts::PI / 2.0).abs() < 1e-12, "{s}");
    }

    #[test]
    fn segment_crossing() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        assert!(segment_hits_triangle(Vec3::new(0.2, 0.2, -1.0), Vec3::new(0.2, 0.2, 1.0), a, b, c));
        assert!(!segment_hits_triangle(Vec3::new(0.2, 0.2, 0.5), Vec3::new(0.2, 0.2, 1.0), a, b, c));
        assert!(!segment_hits_triangle(Vec3::new(0.8, 0.8, -1.0), Vec3::new(0.8, 0.8, 1.0), a, b, c));
    }
}
