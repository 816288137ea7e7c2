//! Capping a cut: the loops where a plane crosses a closed mesh bound the cross-section, which
//! for a general mesh is non-convex and may have holes (and islands in the holes). Outer loops
//! run counter-clockwise in the plane's 2D frame, holes clockwise; each hole is bridged into the
//! smallest outer loop that holds it, and the resulting simple polygons are ear-clipped. No
//! vertex is added, so the cap shares every vertex with the cut it closes.

use glam::DVec2;

use super::pattern::shoelace;

/// Chains directed edges (each vertex with as many edges out as in) into closed loops: from
/// each edge's start in turn, following the latest-listed unused edge out of every vertex.
/// Without hashing: the edges sorted by start (then listing order) give each start a run.
pub(crate) fn loops(edges: &[(u32, u32)]) -> Vec<Vec<u32>> {
    let mut by_start: Vec<(u32, u32)> = edges.to_vec();
    // Stable: within a start's run the edges keep their listing order.
    by_start.sort_by_key(|&(a, _)| a);
    // The run of each start, as (start, first, end); edges are taken from the end of a run.
    let mut runs: Vec<(u32, usize, usize)> = Vec::new();
    for (k, &(a, _)) in by_start.iter().enumerate() {
        match runs.last_mut() {
            Some(run) if run.0 == a => run.2 = k + 1,
            _ => runs.push((a, k, k + 1)),
        }
    }
    let mut take = |at: u32| {
        let r = runs.binary_search_by_key(&at, |run| run.0).ok()?;
        let run = &mut runs[r];
        (run.2 > run.1).then(|| {
            run.2 -= 1;
            by_start[run.2].1
        })
    };
    let mut result = Vec::new();
    for &(start, _) in edges {
        let mut chain = Vec::new();
        let mut at = start;
        while let Some(next) = take(at) {
            chain.push(at);
            at = next;
            if at == start {
                break;
            }
        }
        if chain.len() >= 3 {
            result.push(chain);
        }
    }
    result
}

/// Triangles covering the region bounded by `loops` (vertex ids; counter-clockwise outer
/// loops, clockwise holes, seen in the 2D frame `at` maps ids into), each counter-clockwise.
pub(crate) fn triangulate(loops: &[Vec<u32>], at: &impl Fn(u32) -> DVec2) -> Vec<[u32; 3]> {
    let points = |l: &Vec<u32>| l.iter().map(|&v| at(v)).collect::<Vec<_>>();
    let mut triangles = Vec::new();
    // The usual cap: one loop, no hole.
    if let [only] = loops {
        if shoelace(&points(only)) > 0.0 {
            ear_clip(only, at, &mut triangles);
        }
        return triangles;
    }
    let areas: Vec<f64> = loops.iter().map(|l| shoelace(&points(l))).collect();
    let outers: Vec<usize> = (0..loops.len()).filter(|&k| areas[k] > 0.0).collect();
    let mut holes_of: Vec<Vec<usize>> = vec![Vec::new(); loops.len()];
    for hole in (0..loops.len()).filter(|&k| areas[k] <= 0.0) {
        let probe = at(loops[hole][0]);
        let holder = outers
            .iter()
            .copied()
            .filter(|&o| contains(&points(&loops[o]), probe))
            .min_by(|&a, &b| areas[a].total_cmp(&areas[b]))
            .or_else(|| outers.iter().copied().max_by(|&a, &b| areas[a].total_cmp(&areas[b])));
        if let Some(o) = holder {
            holes_of[o].push(hole);
        }
    }
    for &o in &outers {
        let mut polygon = loops[o].clone();
        let mut holes: Vec<&Vec<u32>> = holes_of[o].iter().map(|&h| &loops[h]).collect();
        let right = |l: &Vec<u32>| l.iter().map(|&v| at(v).x).fold(f64::NEG_INFINITY, f64::max);
        holes.sort_by(|a, b| right(b).total_cmp(&right(a)));
        for (k, hole) in holes.iter().enumerate() {
            bridge(&mut polygon, hole, &holes[k + 1..], at);
        }
        ear_clip(&polygon, at, &mut triangles);
    }
    triangles
}

/// Whether `p` is inside the polygon `corners` (even-odd rule).
fn contains(corners: &[DVec2], p: DVec2) -> bool {
    let mut inside = false;
    for k in 0..corners.len() {
        let (a, b) = (corners[k], corners[(k + 1) % corners.len()]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
}

/// Twice the signed area of triangle (a, b, c), positive counter-clockwise.
fn cross(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Whether segments pq and rs cross at a point inside both (touching ends do not count).
fn crosses(p: DVec2, q: DVec2, r: DVec2, s: DVec2) -> bool {
    let (d1, d2) = (cross(p, q, r), cross(p, q, s));
    let (d3, d4) = (cross(r, s, p), cross(r, s, q));
    ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
}

/// Splices `hole` into `polygon` through a bridge from the hole's rightmost vertex to the
/// nearest polygon vertex it can see (crossing no edge of the polygon or of the `later` holes).
fn bridge(polygon: &mut Vec<u32>, hole: &[u32], later: &[&Vec<u32>], at: &impl Fn(u32) -> DVec2) {
    let m = (0..hole.len()).max_by(|&a, &b| at(hole[a]).x.total_cmp(&at(hole[b]).x)).unwrap_or(0);
    let pm = at(hole[m]);
    let mut order: Vec<usize> = (0..polygon.len()).collect();
    order.sort_by(|&a, &b| at(polygon[a]).distance_squared(pm).total_cmp(&at(polygon[b]).distance_squared(pm)));
    let blocked = |pp: DVec2, edges: &[u32]| {
        (0..edges.len()).any(|k| crosses(pm, pp, at(edges[k]), at(edges[(k + 1) % edges.len()])))
    };
    let visible = order.iter().copied().find(|&i| {
        let pp = at(polygon[i]);
        !blocked(pp, polygon) && !blocked(pp, hole) && !later.iter().any(|h| blocked(pp, h))
    });
    let i = visible.unwrap_or(order[0]);
    let mut spliced = Vec::with_capacity(polygon.len() + hole.len() + 2);
    spliced.extend_from_slice(&polygon[..=i]);
    spliced.extend((0..=hole.len()).map(|k| hole[(m + k) % hole.len()]));
    spliced.push(polygon[i]);
    spliced.extend_from_slice(&polygon[i + 1..]);
    *polygon = spliced;
}

/// Ear-clips the simple (possibly self-touching) counter-clockwise polygon into `out`. Every
/// corner is removed by exactly one triangle, so the triangles' boundary is the polygon whatever
/// the numerics; strictly convex ears holding no reflex corner are preferred, then flat ones,
/// then the most convex corner. Only reflex corners can lie inside an ear of a simple polygon,
/// and flat ones on its diagonal, so only they are tested (a corner blocks when it is inside or
/// on the diagonal, not when it lies on the ear's own sides' lines within rounding): O(n·r) for
/// n corners, r of them reflex or flat.
fn ear_clip(polygon: &[u32], at: &impl Fn(u32) -> DVec2, out: &mut Vec<[u32; 3]>) {
    let n = polygon.len();
    if n < 3 {
        return;
    }
    let pts: Vec<DVec2> = polygon.iter().map(|&v| at(v)).collect();
    let mut next: Vec<usize> = (1..=n).map(|k| k % n).collect();
    let mut prev: Vec<usize> = (0..n).map(|k| (k + n - 1) % n).collect();
    let mut removed = vec![false; n];
    let scale = pts.iter().fold(0.0f64, |m, p| m.max(p.abs().max_element())).max(1e-300);
    let flat = 1e-12 * scale * scale;
    let turn = |k: usize, prev: &[usize], next: &[usize]| cross(pts[prev[k]], pts[k], pts[next[k]]);
    // Corners that can block an ear: reflex ones, and flat ones (which may lie on a diagonal).
    let mut reflex: Vec<bool> = (0..n).map(|k| turn(k, &prev, &next) <= flat).collect();
    let mut reflex_list: Vec<usize> = (0..n).filter(|&k| reflex[k]).collect();
    let is_ear = |i: usize,
                  (prev, next): (&[usize], &[usize]),
                  (reflex_list, reflex): (&[usize], &[bool]),
                  removed: &[bool],
                  strict: bool| {
        let (p, q) = (prev[i], next[i]);
        let area = turn(i, prev, next);
        if if strict { area <= flat } else { area < -flat } {
            return false;
        }
        let (a, b, c) = (pts[p], pts[i], pts[q]);
        !reflex_list.iter().any(|&j| {
            let x = pts[j];
            let same = |k: usize| polygon[j] == polygon[k] || x == pts[k];
            !removed[j]
                && reflex[j]
                && !(same(p) || same(i) || same(q))
                && cross(a, b, x) > flat
                && cross(b, c, x) > flat
                && cross(c, a, x) >= -flat
        })
    };
    let mut left = n;
    let mut i = 0;
    while left > 3 {
        let found = [true, false].into_iter().find_map(|strict| {
            let mut k = i;
            for _ in 0..left {
                if is_ear(k, (&prev, &next), (&reflex_list, &reflex), &removed, strict) {
                    return Some(k);
                }
                k = next[k];
            }
            None
        });
        let ear = found.unwrap_or_else(|| {
            let (mut best, mut k) = (i, i);
            for _ in 0..left {
                if turn(k, &prev, &next) > turn(best, &prev, &next) {
                    best = k;
                }
                k = next[k];
            }
            best
        });
        let (p, q) = (prev[ear], next[ear]);
        out.push([polygon[p], polygon[ear], polygon[q]]);
        next[p] = q;
        prev[q] = p;
        removed[ear] = true;
        for k in [p, q] {
            let now = turn(k, &prev, &next) <= flat;
            if now && !reflex[k] {
                reflex_list.push(k);
            }
            reflex[k] = now;
        }
        left -= 1;
        i = q;
    }
    out.push([polygon[prev[i]], polygon[i], polygon[next[i]]]);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square with a square hole: 8 triangles (n + 2·holes − 2 for 8 corners), covering the
    /// area between them exactly, every triangle counter-clockwise.
    #[test]
    fn a_square_with_a_hole_is_covered_exactly() {
        let corners = [
            DVec2::new(0.0, 0.0),
            DVec2::new(4.0, 0.0),
            DVec2::new(4.0, 4.0),
            DVec2::new(0.0, 4.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(1.0, 3.0),
            DVec2::new(3.0, 3.0),
            DVec2::new(3.0, 1.0),
        ];
        let at = |v: u32| corners[v as usize];
        let triangles = triangulate(&[vec![0, 1, 2, 3], vec![4, 5, 6, 7]], &at);
        assert_eq!(triangles.len(), 8);
        let area: f64 = triangles.iter().map(|t| 0.5 * cross(at(t[0]), at(t[1]), at(t[2]))).sum();
        assert!((area - 12.0).abs() < 1e-12, "{area}");
        assert!(triangles.iter().all(|t| cross(at(t[0]), at(t[1]), at(t[2])) > 0.0));
    }

    /// A comb (non-convex, 12 corners, three corners on one line) is covered by 10 counter-clockwise
    /// triangles of its area (15 m² less two 1 × 2 notches), none of them flat.
    #[test]
    fn a_comb_is_covered_exactly() {
        let corners: Vec<DVec2> = [
            (0.0, 0.0),
            (5.0, 0.0),
            (5.0, 3.0),
            (4.0, 3.0),
            (4.0, 1.0),
            (3.0, 1.0),
            (3.0, 3.0),
            (2.0, 3.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 3.0),
            (0.0, 3.0),
        ]
        .into_iter()
        .map(|(x, y)| DVec2::new(x, y))
        .collect();
        let at = |v: u32| corners[v as usize];
        let triangles = triangulate(&[(0..12).collect()], &at);
        assert_eq!(triangles.len(), 10);
        let area: f64 = triangles.iter().map(|t| 0.5 * cross(at(t[0]), at(t[1]), at(t[2]))).sum();
        assert!((area - 11.0).abs() < 1e-12, "{area}");
        assert!(triangles.iter().all(|t| cross(at(t[0]), at(t[1]), at(t[2])) > 0.0));
    }
}
