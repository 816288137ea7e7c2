//! A whole-mesh certificate that a closed mesh has no crossing faces: it is star-shaped about
//! its vertex mean. Cheap for small closed meshes that a dent moves a large part of (a ball the
//! size of what hits it), where the local checks of `dent::guard_pairs` cost more.
//!
//! # Why it certifies
//!
//! Let `S` be the mesh, closed and consistently oriented (each directed edge once, its reverse
//! once), and `c` a point strictly behind every face's plane. Project `S` radially from `c` onto
//! the unit sphere. Each face maps one-to-one and with positive orientation, and two faces on an
//! edge map to opposite sides of its image, so the projection is a covering branched at most at
//! vertices. Its degree is the total solid angle of the faces seen from `c` over 4π. With degree
//! 1, every component of `S` (a component covers the sphere at least once) is one; and by
//! Riemann–Hurwitz, `χ(S') = 2·1 − Σ(branching)` for the surface `S'` got by pulling apart
//! vertices where separate fans meet, so `χ(S') ≤ 2`, while `χ(S') = χ(S) + (pulled vertices)`.
//! Hence with `χ(S) = V − E + F = 2` nothing is pulled apart or branched: the projection is a
//! homeomorphism, and `S` is embedded (no two faces cross, none meets another but along their
//! common edges and corners).

use std::cmp::Ordering;

use glam::{DVec3, Vec3};

/// Relative margin of "strictly behind a face's plane": `c` must lie this fraction of the
/// mesh's box diagonal behind each plane.
const MARGIN: f64 = 1e-9;

/// Bound on the f64 rounding of the test `n·a` (`n = (b − a) × (c − a)`, corners relative to
/// the centre), as a multiple of `R·|a|·(|b − a| + |c − a|)` with `R` the largest distance of
/// a corner or the centre from the origin: forming each corner errs by an ulp of `R`, which the
/// cross product carries into `n` along the edges, whatever the face's area (a sliver's normal
/// is not trusted). The f64 unit roundoff is 1.1e-16; this is about 100 of them.
const ROUNDING: f64 = 1e-14;

/// Whether `faces` over `positions` (any frame, m) form a closed, consistently oriented surface
/// that is star-shaped about its corners' mean, hence embedded (module documentation). `false`
/// says nothing: the mesh may still be embedded.
pub(crate) fn star_shaped_closed(positions: &[Vec3], faces: &[[u32; 3]]) -> bool {
    if faces.len() < 4 {
        return false;
    }
    let mut used = vec![false; positions.len()];
    for f in faces {
        for &v in f {
            match (used.get_mut(v as usize), positions.get(v as usize)) {
                (Some(u), Some(p)) if p.is_finite() => *u = true,
                _ => return false,
            }
        }
    }
    let (mut sum, mut count, mut lo, mut hi) = (DVec3::ZERO, 0usize, DVec3::INFINITY, DVec3::NEG_INFINITY);
    for p in positions.iter().zip(&used).filter(|(_, u)| **u).map(|(p, _)| p.as_dvec3()) {
        (sum, count, lo, hi) = (sum + p, count + 1, lo.min(p), hi.max(p));
    }
    let centre = sum / count as f64;
    let margin = MARGIN * (hi - lo).length();
    let reach = lo.abs().max(hi.abs()).length() + centre.length();
    if !margin.is_finite() || !reach.is_finite() {
        return false;
    }
    // Every face faces away from the centre (the cheap test, first: most meshes fail it fast),
    // and their solid angles seen from it add up to one sphere.
    let mut solid_angle = 0.0;
    for f in faces {
        let [a, b, c] = f.map(|v| positions[v as usize].as_dvec3() - centre);
        let normal = (b - a).cross(c - a);
        let rounding = ROUNDING * reach * a.length() * ((b - a).length() + (c - a).length());
        if normal.dot(a).partial_cmp(&(margin * normal.length() + rounding)) != Some(Ordering::Greater) {
            return false;
        }
        solid_angle += triangle_solid_angle(a, b, c);
    }
    if (solid_angle - 4.0 * std::f64::consts::PI).abs().partial_cmp(&1.0) != Some(Ordering::Less) {
        return false;
    }
    closed_sphere_topology(faces, count)
}

/// Solid angle (sr) of triangle `a, b, c` seen from the origin, positive for a counter-clockwise
/// one (Van Oosterom and Strackee).
fn triangle_solid_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let numerator = a.dot(b.cross(c));
    let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * numerator.atan2(denominator)
}

/// Whether each directed edge of `faces` appears once and its reverse once, and
/// `V − E + F = 2` with `V` the `corners` the faces use.
fn closed_sphere_topology(faces: &[[u32; 3]], corners: usize) -> bool {
    // Each directed edge as its undirected key and its direction in the lowest bit: sorted,
    // a closed, consistently oriented surface lists every key exactly twice, once each way.
    let mut edges: Vec<u128> = Vec::with_capacity(3 * faces.len());
    for f in faces {
        for (a, b) in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
            if a == b {
                return false;
            }
            let (lo, hi) = (u128::from(a.min(b)), u128::from(a.max(b)));
            edges.push((lo << 33) | (hi << 1) | u128::from(a < b));
        }
    }
    edges.sort_unstable();
    let paired = edges.chunks(2).all(|pair| matches!(pair, [one, other] if one ^ other == 1 && one & 1 == 0));
    let (v, e, f) = (corners as i64, edges.len() as i64 / 2, faces.len() as i64);
    paired && v - e + f == 2
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh;

    #[test]
    fn spheres_and_boxes_are_certified_and_a_pushed_through_dent_is_not() {
        let ball = mesh::icosphere(0.15, 2).expect("icosphere");
        assert!(star_shaped_closed(ball.positions(), ball.faces()));
        let block = mesh::subdivided_box(Vec3::new(1.0, 0.5, 0.2), [3, 2, 1]).expect("box");
        assert!(star_shaped_closed(block.positions(), block.faces()));
        // A cap flattened (each point above y = 0.12 pulled halfway down to it) stays star-shaped.
        let mut dented = ball.positions().to_vec();
        for p in dented.iter_mut().filter(|p| p.y > 0.12) {
            p.y -= 0.5 * (p.y - 0.12);
        }
        assert!(star_shaped_closed(&dented, ball.faces()));
        // A cap pushed through the centre: faces then face it, and some cross.
        let mut through = ball.positions().to_vec();
        for p in through.iter_mut().filter(|p| p.y > 0.1) {
            p.y -= 0.4;
        }
        assert!(!star_shaped_closed(&through, ball.faces()));
        let mut crossed = ball.clone();
        crossed.set_positions(through).expect("positions");
        assert!(!crossed.self_intersections().is_empty(), "it does cross");
    }

    #[test]
    fn open_doubled_or_non_sphere_meshes_are_not_certified() {
        let ball = mesh::icosphere(0.15, 1).expect("icosphere");
        // One face removed: not closed.
        let open: Vec<[u32; 3]> = ball.faces()[1..].to_vec();
        assert!(!star_shaped_closed(ball.positions(), &open));
        // Every face twice: each directed edge twice.
        let doubled: Vec<[u32; 3]> = ball.faces().iter().chain(ball.faces()).copied().collect();
        assert!(!star_shaped_closed(ball.positions(), &doubled));
        // Two copies of the ball on one centre (every face still faces away, but the solid
        // angle is two spheres).
        let n = ball.vertex_count() as u32;
        let mut positions = ball.positions().to_vec();
        positions.extend(ball.positions().iter().map(|p| *p * 0.5));
        let faces: Vec<[u32; 3]> =
            ball.faces().iter().copied().chain(ball.faces().iter().map(|f| f.map(|v| v + n))).collect();
        assert!(!star_shaped_closed(&positions, &faces));
        // A fan of slivers: a face whose height is below the rounding of its normal is not
        // trusted to face away, however the rounded normal points.
        let mut sliver = ball.positions().to_vec();
        let [a, b, c] = ball.faces()[0];
        sliver[c as usize] = (sliver[a as usize] + sliver[b as usize]) * 0.5 + Vec3::splat(1e-12);
        assert!(!star_shaped_closed(&sliver, ball.faces()));
        // An index past the positions.
        assert!(!star_shaped_closed(&ball.positions()[1..], ball.faces()));
        // Non-finite positions.
        let mut nan = ball.positions().to_vec();
        nan[0].x = f32::NAN;
        assert!(!star_shaped_closed(&nan, ball.faces()));
        // f32's largest magnitudes square and cube within f64's range: certified as at any scale.
        let huge: Vec<Vec3> = ball.positions().iter().map(|p| *p * 1e37).collect();
        assert!(star_shaped_closed(&huge, ball.faces()));
    }
}
