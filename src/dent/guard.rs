//! The intersection guard, the last stage of a dent: if the dent makes faces around the moved
//! vertices cross where they did not cross before it, or turns a face over (its normal
//! reversed, `mesh::turned_over`: a fold with no crossing), the dent is scaled back (every moved
//! vertex to `before + s·(after − before)`, the largest `s` found by bisection) until no new
//! crossing and no turned face is left. Crossings that were there before the dent are not its
//! business. Turned faces are looked for among the faces with a moved corner, at every step of
//! the bisection (a face's orientation is quadratic in `s`: it can turn and turn back).
//!
//! Cost: one pass over the faces to find the moved ones and the unmoved ones near them (the
//! volume stage's own pass, when it ran and its region holds them), a check
//! of whether the moved faces' patches are height fields after the dent (`mesh::height_field`:
//! a crater and its rim on a surface seen from one side are; then no two faces of a patch
//! cross, and its pairs are never listed), a grid for the other pairs whose boxes after the
//! dent overlap, and the exact test (see [`TriMesh::self_intersections`]) of each such pair at
//! the full displacement, less the pairs of neighbours around a vertex whose umbrella is
//! certified embedded (`mesh::umbrella`). Only for a dent
//! that does make faces cross, the pairs whose swept boxes meet are found and those that their
//! vertices' relative motion cannot clear (`guard_pairs`: neighbours moving together need no
//! test; this is sound for every scale, no motion is too small to matter) are tested at each
//! step of the bisection, up to the first that crosses; as the bisection's upper end falls, the
//! pairs those bounds clear for the smaller displacement are dropped. A dent with a volume rim is checked once, dent and rim together; only
//! when they cross is the dent limited first and its rim made again for what is left.
//!
//! [`TriMesh::self_intersections`]: crate::mesh::TriMesh::self_intersections

use std::collections::HashSet;

use glam::Vec3;
use rayon::prelude::*;

use super::guard_pairs::{Reach, pairs_to_test, pairs_within_scale};
use super::map::PendingDisplacement;
use crate::mesh::face_sort::FaceSort;
use crate::mesh::self_intersect::faces_cross;
use crate::mesh::turned_over::is_turned_over;

/// Bisection steps: the scale found is within 2⁻¹² of the largest crossing-free one.
const BISECTION_STEPS: u32 = 12;

/// Limits `pending` (computed from `before`, the positions of a mesh with `faces`) so that it
/// makes no new pair of faces cross and turns no face over; records the scale kept and a
/// warning naming the cause in its report.
pub(crate) fn guard_crossings(pending: &mut PendingDisplacement, faces: &[[u32; 3]], before: &[Vec3]) {
    let Some(limit) = crossing_free_scale(faces, before, &pending.positions, &pending.moved) else {
        return;
    };
    let scale = limit.scale;
    for ((p, &b), _) in pending.positions.iter_mut().zip(before).zip(&pending.moved).filter(|(_, m)| **m) {
        *p = scaled(b, *p, scale);
    }
    let report = &mut pending.report;
    report.max_displacement *= scale;
    if scale == 0.0 {
        report.moved_vertices = 0;
    }
    report.limited_to = Some(scale);
    let message = limit.message();
    log::warn!("{message}");
    report.warnings.push(message);
}

/// Why and how far the guard scales a dent back.
struct Limit {
    /// The scale kept.
    scale: f32,
    /// Whether the full dent makes new pairs of faces cross.
    crosses: bool,
    /// The faces the full dent turns over, ascending.
    turned_over: Vec<u32>,
}

impl Limit {
    fn message(&self) -> String {
        let kept = 100.0 * self.scale;
        let turned = match self.turned_over.as_slice() {
            [] => String::new(),
            [face] => format!("face {face} would turn over (its normal reversed)"),
            [first, ..] => {
                format!("{} faces would turn over (their normals reversed; face {first} first)", self.turned_over.len())
            }
        };
        match (self.crosses, turned.is_empty()) {
            (true, true) => format!(
                "dent limited to {kept:.1} % of its displacement: any deeper, faces near it would cross (a fold through the body)"
            ),
            (true, false) => format!(
                "dent limited to {kept:.1} % of its displacement: any deeper, faces near it would cross (a fold through the body) and {turned}"
            ),
            (false, _) => format!("dent limited to {kept:.1} % of its displacement: any deeper, {turned}"),
        }
    }
}

/// Whether `pending` (computed from `before`, the positions of a mesh with `faces`) makes a
/// pair of faces cross that did not cross before it: what [`guard_crossings`] would limit.
/// `presorted`: a sort of the faces made beforehand, as `guard_pairs::pairs_to_test` takes.
pub(crate) fn makes_new_crossings(
    pending: &PendingDisplacement,
    faces: &[[u32; 3]],
    before: &[Vec3],
    presorted: Option<FaceSort>,
) -> bool {
    let moved_faces = faces_with_moved_corner(faces, &pending.moved);
    if !turned_over(faces, before, &pending.positions, &moved_faces).is_empty() {
        return true;
    }
    let pairs = pairs_to_test(faces, before, &pending.positions, &pending.moved, Reach::Full, presorted);
    let after = crossing_pairs(faces, &pending.positions, &pairs);
    !after.is_empty() && {
        let crossed_before: HashSet<(u32, u32)> = crossing_pairs(faces, before, &after).into_iter().collect();
        after.iter().any(|p| !crossed_before.contains(p))
    }
}

/// The faces with a moved corner, ascending: the only ones a displacement can turn over.
fn faces_with_moved_corner(faces: &[[u32; 3]], moved: &[bool]) -> Vec<u32> {
    let with_moved = |f: &u32| faces[*f as usize].iter().any(|&v| moved[v as usize]);
    if faces.len() < PARALLEL_FACES {
        (0..faces.len() as u32).filter(with_moved).collect()
    } else {
        (0..faces.len() as u32).into_par_iter().with_min_len(PARALLEL_FACES / 2).filter(with_moved).collect()
    }
}

/// The faces of `candidates` (ascending) that moving `before` to `positions` turns over.
fn turned_over(faces: &[[u32; 3]], before: &[Vec3], positions: &[Vec3], candidates: &[u32]) -> Vec<u32> {
    let turned = |f: &&u32| is_turned_over(faces[**f as usize], before, positions);
    candidates.iter().filter(turned).copied().collect()
}

/// The pairs of `pairs` whose faces cross at `positions`.
fn crossing_pairs(faces: &[[u32; 3]], positions: &[Vec3], pairs: &[(u32, u32)]) -> Vec<(u32, u32)> {
    let crosses = |&&(a, b): &&(u32, u32)| faces_cross(positions, faces, a, b);
    if pairs.len() < PARALLEL_TESTS {
        pairs.iter().filter(crosses).copied().collect()
    } else {
        pairs.par_iter().with_min_len(PARALLEL_TESTS / 2).filter(crosses).copied().collect()
    }
}

/// A pair of `pairs` whose faces cross at `positions`; `None` if none does.
fn first_crossing(faces: &[[u32; 3]], positions: &[Vec3], pairs: &[(u32, u32)]) -> Option<(u32, u32)> {
    let crosses = |&(a, b): &(u32, u32)| faces_cross(positions, faces, a, b);
    if pairs.len() < PARALLEL_TESTS {
        pairs.iter().copied().find(crosses)
    } else {
        pairs.par_iter().with_min_len(PARALLEL_TESTS / 2).copied().find_any(crosses)
    }
}

/// `before + s·(after − before)`, exactly `after` at `s = 1`.
fn scaled(before: Vec3, after: Vec3, s: f32) -> Vec3 {
    if s == 1.0 { after } else { before + (after - before) * s }
}

/// `None` when moving `before` to `after` makes no new face pair cross and turns no face over;
/// otherwise the largest scale (to 2⁻¹²) of the displacement that does neither (0 at worst:
/// nothing moves), and why.
fn crossing_free_scale(faces: &[[u32; 3]], before: &[Vec3], after: &[Vec3], moved: &[bool]) -> Option<Limit> {
    let moved_faces = faces_with_moved_corner(faces, moved);
    let turned_over_after = turned_over(faces, before, after, &moved_faces);
    // The pairs whose boxes after the dent overlap, tested at the full displacement.
    let pairs = pairs_to_test(faces, before, after, moved, Reach::Full, None);
    let crossing_after = crossing_pairs(faces, after, &pairs);
    if crossing_after.is_empty() && turned_over_after.is_empty() {
        return None;
    }
    // Those that could cross at any scale (a superset), less those that crossed before. They are
    // watched whenever the dent is limited, also for turned faces only: a scale below 1 may
    // make a pair cross that the full dent does not.
    let pairs = pairs_to_test(faces, before, after, moved, Reach::Scaled, None);
    let crossed_before: HashSet<(u32, u32)> = crossing_pairs(faces, before, &pairs).into_iter().collect();
    let crosses = !crossing_after.iter().all(|p| crossed_before.contains(p));
    if !crosses && turned_over_after.is_empty() {
        return None;
    }
    let mut watched: Vec<(u32, u32)> = pairs.into_iter().filter(|p| !crossed_before.contains(p)).collect();
    let mut positions = before.to_vec();
    let (mut lo, mut hi) = (0.0f32, 1.0f32);
    // Each step needs only whether some watched pair crosses: the last pair found crossing is
    // tried first (it often crosses again), and the search stops at the first. Before a step
    // scans the watched pairs, those that cannot cross at any scale up to `hi` are dropped if
    // `hi` fell since the last such pass (`pairs_within_scale`: the same bounds, on the smaller
    // displacement; later steps try only scales below `hi`; a hint dropped so cannot cross
    // either). Neither changes a step's outcome, so the scale found is the same.
    let (mut hint, mut filtered_at) = (None, 1.0f32);
    for _ in 0..BISECTION_STEPS {
        let mid = 0.5 * (lo + hi);
        for ((p, (&b, &a)), _) in positions.iter_mut().zip(before.iter().zip(after)).zip(moved).filter(|(_, m)| **m) {
            *p = scaled(b, a, mid);
        }
        let clear = turned_over(faces, before, &positions, &moved_faces).is_empty()
            && !hint.is_some_and(|(f, g)| faces_cross(&positions, faces, f, g))
            && {
                if hi < filtered_at {
                    watched = pairs_within_scale(faces, before, after, &watched, hi);
                    filtered_at = hi;
                }
                let found = first_crossing(faces, &positions, &watched);
                hint = found.or(hint);
                found.is_none()
            };
        if clear { lo = mid } else { hi = mid }
    }
    Some(Limit { scale: lo, crosses, turned_over: turned_over_after })
}

/// Below this many faces the moved ones are listed on one thread.
const PARALLEL_FACES: usize = 65536;

/// Below this many pair tests they run on one thread (waking the pool costs more).
const PARALLEL_TESTS: usize = 16384;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dent::DisplaceReport;

    /// A flap folded over its neighbour, hovering above it: nothing crosses (they share only
    /// their hinge edge), but the flap's normal is reversed. The guard limits the dent to where
    /// the flap stands upright, within its tolerance: its normal's z is 1 − 1.5·s (flat at
    /// s = 2/3), so the scale kept lies within the bisection's 2⁻¹² below 2/3 plus the
    /// tolerance's 10⁻³·L² (L² ≤ 1.4 here) over the 1.5 rate.
    #[test]
    fn a_face_turned_over_without_a_crossing_is_limited() {
        let before = vec![Vec3::ZERO, Vec3::X, Vec3::new(0.5, 1.0, 0.0), Vec3::new(0.5, -1.0, 0.0)];
        let faces = [[0, 1, 2], [1, 0, 3]];
        let mut after = before.clone();
        after[3] = Vec3::new(0.5, 0.5, 0.2);
        assert!(!faces_cross(&after, &faces, 0, 1), "the folded flap touches its neighbour only");
        assert!(is_turned_over(faces[1], &before, &after));
        let mut pending = PendingDisplacement {
            positions: after,
            moved: vec![false, false, false, true],
            report: DisplaceReport { moved_vertices: 1, max_displacement: 1.5, ..Default::default() },
        };
        guard_crossings(&mut pending, &faces, &before);
        let kept = pending.report.limited_to.expect("limited");
        assert!((2.0 / 3.0 - 2f32.powi(-12)..=2.0 / 3.0 + 1e-3).contains(&kept), "kept {kept}");
        assert!(!is_turned_over(faces[1], &before, &pending.positions));
        let warning = pending.report.warnings.join("\n");
        assert!(warning.contains("face 1 would turn over"), "{warning}");
        // Nothing moved toward a turn: not limited.
        let mut upright = PendingDisplacement {
            positions: vec![before[0], before[1], before[2], Vec3::new(0.5, -1.0, 0.3)],
            moved: vec![false, false, false, true],
            report: DisplaceReport::default(),
        };
        guard_crossings(&mut upright, &faces, &before);
        assert_eq!(upright.report.limited_to, None);
    }
}
