//! Whether two triangles cross: their relative interiors share a point (transversal crossings)
//! or, coplanar and facing the same way, an area (a doubled surface). Touching along an edge or
//! at a vertex is not a crossing, so faces sharing a vertex or an edge are reported only when
//! they overlap beyond it; nor are coplanar faces facing opposite ways (two sheets back to back,
//! or a fold flattened exactly onto itself: the limit of a fold, which crosses once pushed on).
//!
//! Arithmetic is f64 on the f32 inputs. Every side-of-plane and side-of-line decision uses a
//! determinant whose sign is trusted only beyond Shewchuk's static rounding bound and counts as
//! zero (on the plane or line) otherwise: a point that really lies on a plane is always
//! classified as on it, and so is one within rounding distance of it. Where two faces touch
//! without a shared vertex (a T-junction), the one interpolated quantity — where their common
//! line leaves each face — is compared with a relative tolerance of 1e-9.

use glam::DVec3;

/// ε of Shewchuk's predicates: half an ulp of 1 in f64.
const EPS: f64 = f64::EPSILON * 0.5;
/// Static error bound of `orient3d` relative to its permanent (Shewchuk 1997, `o3derrboundA`).
const ORIENT3D_BOUND: f64 = (7.0 + 56.0 * EPS) * EPS;
/// Static error bound of `orient2d` relative to its permanent (`ccwerrboundA`).
const ORIENT2D_BOUND: f64 = (3.0 + 16.0 * EPS) * EPS;
/// Two intervals on the faces' common line overlap only past this fraction of their lengths.
const OVERLAP_TOLERANCE: f64 = 1e-9;

/// Sign (−1, 0, 1) of det[a−d; b−d; c−d]: positive when `d` lies below the plane of `a, b, c`
/// (seen with `a, b, c` counter-clockwise), zero when on it or within rounding of it; also the
/// determinant itself (positive × six times the tetrahedron's volume).
fn orient3d(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> (i8, f64) {
    let (ad, bd, cd) = (a - d, b - d, c - d);
    let bc = bd.x * cd.y - cd.x * bd.y;
    let ca = cd.x * ad.y - ad.x * cd.y;
    let ab = ad.x * bd.y - bd.x * ad.y;
    let det = ad.z * bc + bd.z * ca + cd.z * ab;
    let permanent = (bd.x * cd.y).abs() + (cd.x * bd.y).abs();
    let permanent = ad.z.abs() * permanent
        + bd.z.abs() * ((cd.x * ad.y).abs() + (ad.x * cd.y).abs())
        + cd.z.abs() * ((ad.x * bd.y).abs() + (bd.x * ad.y).abs());
    (certain_sign(det, ORIENT3D_BOUND * permanent), det)
}

/// Sign of the 2D orientation of `c` relative to the directed line `a → b` (counter-clockwise
/// positive), zero within rounding.
pub(super) fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> i8 {
    let left = (a[0] - c[0]) * (b[1] - c[1]);
    let right = (a[1] - c[1]) * (b[0] - c[0]);
    certain_sign(left - right, ORIENT2D_BOUND * (left.abs() + right.abs()))
}

fn certain_sign(det: f64, bound: f64) -> i8 {
    if det > bound {
        1
    } else if det < -bound {
        -1
    } else {
        0
    }
}

/// Whether triangles `p` and `q` cross (see the module documentation). A zero-area triangle
/// never crosses anything.
pub(crate) fn triangles_cross(p: [DVec3; 3], q: [DVec3; 3]) -> bool {
    // Work relative to one vertex so that magnitudes are those of the triangles, not the world.
    let origin = p[0];
    let p = p.map(|v| v - origin);
    let q = q.map(|v| v - origin);
    let np = (p[1] - p[0]).cross(p[2] - p[0]);
    let nq = (q[1] - q[0]).cross(q[2] - q[0]);
    if np == DVec3::ZERO || nq == DVec3::ZERO {
        return false;
    }
    let q_side = q.map(|v| orient3d(p[0], p[1], p[2], v));
    let q_signs = q_side.map(|s| s.0);
    if q_signs == [0; 3] {
        return np.dot(nq) > 0.0 && coplanar_overlap(p, q, np);
    }
    if !straddles(q_signs) {
        return false;
    }
    let p_side = p.map(|v| orient3d(q[0], q[1], q[2], v));
    let p_signs = p_side.map(|s| s.0);
    if p_signs == [0; 3] {
        return np.dot(nq) > 0.0 && coplanar_overlap(p, q, nq);
    }
    if !straddles(p_signs) {
        return false;
    }
    let direction = np.cross(nq);
    let a = chord(p, p_side, direction);
    let b = chord(q, q_side, direction);
    let overlap = a.1.min(b.1) - a.0.max(b.0);
    overlap > OVERLAP_TOLERANCE * (a.1 - a.0).max(b.1 - b.0)
}

/// Whether the vertices lie strictly on both sides of the other triangle's plane; otherwise the
/// triangle meets that plane in at most a vertex or an edge, which is touching, not crossing.
fn straddles(signs: [i8; 3]) -> bool {
    signs.contains(&1) && signs.contains(&-1)
}

/// The interval `(min, max)` of `t = x·direction` over the segment where `tri` (which straddles
/// the other plane) meets it; `side` holds each vertex's sign and determinant for that plane.
fn chord(tri: [DVec3; 3], side: [(i8, f64); 3], direction: DVec3) -> (f64, f64) {
    let mut ends = [0.0; 2];
    let mut count = 0;
    for i in 0..3 {
        let j = (i + 1) % 3;
        let (si, di) = side[i];
        let (sj, dj) = side[j];
        let point = if si == 0 {
            Some(tri[i])
        } else if si * sj < 0 {
            Some(tri[i] + (tri[j] - tri[i]) * (di / (di - dj)))
        } else {
            None
        };
        if let Some(point) = point
            && count < 2
        {
            ends[count] = point.dot(direction);
            count += 1;
        }
    }
    (ends[0].min(ends[1]), ends[0].max(ends[1]))
}

/// Coplanar triangles overlap when their interiors share an area: no edge line of either one has
/// the other triangle entirely on its far closed side (separating axes through the edges).
fn coplanar_overlap(p: [DVec3; 3], q: [DVec3; 3], normal: DVec3) -> bool {
    let drop = normal.abs().max_position();
    let flat = |v: DVec3| {
        let (u, w) = ((drop + 1) % 3, (drop + 2) % 3);
        [v[u], v[w]]
    };
    let p2 = p.map(flat);
    let q2 = q.map(flat);
    if orient2d(p2[0], p2[1], p2[2]) == 0 || orient2d(q2[0], q2[1], q2[2]) == 0 {
        return false;
    }
    !(separated_by_an_edge(p2, q2) || separated_by_an_edge(q2, p2))
}

/// Whether the line through some edge of `owner` has `other` on its far closed side.
fn separated_by_an_edge(owner: [[f64; 2]; 3], other: [[f64; 2]; 3]) -> bool {
    (0..3).any(|i| {
        let (a, b, c) = (owner[i], owner[(i + 1) % 3], owner[(i + 2) % 3]);
        let inside = orient2d(a, b, c);
        other.iter().all(|&v| orient2d(a, b, v) * inside <= 0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [DVec3; 3] {
        [DVec3::from(a), DVec3::from(b), DVec3::from(c)]
    }

    #[test]
    fn piercing_triangles_cross_both_ways() {
        let flat = tri([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]);
        let spike = tri([0.5, 0.5, -1.0], [0.5, 0.5, 1.0], [3.0, 3.0, 0.5]);
        assert!(triangles_cross(flat, spike));
        assert!(triangles_cross(spike, flat));
    }

    #[test]
    fn separated_and_touching_triangles_do_not_cross() {
        let flat = tri([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]);
        // Above the plane.
        assert!(!triangles_cross(flat, tri([0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 2.0])));
        // One vertex resting on the interior (a T-junction touch).
        assert!(!triangles_cross(flat, tri([0.5, 0.5, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 1.0])));
        // An edge lying in the interior, the rest above.
        assert!(!triangles_cross(flat, tri([0.2, 0.2, 0.0], [0.8, 0.2, 0.0], [0.5, 0.5, 1.0])));
        // Crossing the plane beside the triangle, not through it.
        assert!(!triangles_cross(flat, tri([3.0, 3.0, -1.0], [3.0, 3.0, 1.0], [4.0, 4.0, 0.0])));
        // Piercing the plane through a vertex of `flat` and leaving it: touch at that point only.
        assert!(!triangles_cross(flat, tri([0.0, 0.0, 0.0], [-1.0, -1.0, 1.0], [-1.0, -0.5, -1.0])));
    }

    #[test]
    fn neighbours_sharing_an_edge_or_vertex_cross_only_when_folded_over() {
        let a = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        // Flat neighbour across the edge (1,0)-(0,1), and a bent one.
        assert!(!triangles_cross(a, tri([1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0])));
        assert!(!triangles_cross(a, tri([1.0, 0.0, 0.0], [1.0, 1.0, 0.7], [0.0, 1.0, 0.0])));
        // Folded flat back onto `a`: the limit of a fold, touching (faces opposite ways).
        assert!(!triangles_cross(a, tri([1.0, 0.0, 0.0], [0.2, 0.2, 0.0], [0.0, 1.0, 0.0])));
        // Folded on past flat: faces sharing an edge, not coplanar, meet only along it.
        assert!(!triangles_cross(a, tri([1.0, 0.0, 0.0], [0.2, 0.2, 0.1], [0.0, 1.0, 0.0])));
        // Sharing vertex 0 and pointing into `a` from below: crosses beyond the shared vertex.
        assert!(triangles_cross(a, tri([0.0, 0.0, 0.0], [0.6, 0.6, 0.3], [0.6, 0.6, -0.3])));
        // Sharing vertex 0 and pointing away: touches only there.
        assert!(!triangles_cross(a, tri([0.0, 0.0, 0.0], [-0.6, -0.6, 0.3], [-0.6, -0.6, -0.3])));
    }

    #[test]
    fn coplanar_cases() {
        let a = tri([0.0, 0.0, 1.0], [2.0, 0.0, 1.0], [0.0, 2.0, 1.0]);
        assert!(triangles_cross(a, tri([0.5, 0.5, 1.0], [3.0, 0.5, 1.0], [0.5, 3.0, 1.0])));
        assert!(triangles_cross(a, a));
        // Facing the other way (back to back): touching.
        assert!(!triangles_cross(a, tri([0.5, 0.5, 1.0], [0.5, 3.0, 1.0], [3.0, 0.5, 1.0])));
        // Touching corner to corner, and disjoint.
        assert!(!triangles_cross(a, tri([2.0, 0.0, 1.0], [3.0, 0.0, 1.0], [3.0, 1.0, 1.0])));
        assert!(!triangles_cross(a, tri([5.0, 5.0, 1.0], [6.0, 5.0, 1.0], [5.0, 6.0, 1.0])));
    }

    #[test]
    fn degenerate_triangles_never_cross() {
        let a = tri([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]);
        let needle = tri([0.5, 0.5, -1.0], [0.5, 0.5, 1.0], [0.5, 0.5, 0.0]);
        assert!(!triangles_cross(a, needle));
    }

    #[test]
    fn far_from_the_origin_and_tiny_still_decided() {
        let shift = DVec3::new(1.0e5, -2.0e5, 3.0e5);
        let s = 1.0e-3;
        let flat = tri([0.0, 0.0, 0.0], [2.0 * s, 0.0, 0.0], [0.0, 2.0 * s, 0.0]).map(|v| v + shift);
        let spike = tri([0.5 * s, 0.5 * s, -s], [0.5 * s, 0.5 * s, s], [3.0 * s, 3.0 * s, 0.5 * s]).map(|v| v + shift);
        assert!(triangles_cross(flat, spike));
    }
}
