//! The intersection guard, the last stage of a dent: if the dent makes faces around the moved
//! vertices cross where they did not cross before it, the dent is scaled back (every moved
//! vertex to `before + s·(after − before)`, the largest `s` found by bisection) until no new
//! crossing is left. Crossings that were there before the dent are not its business.
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
//! step of the bisection. A dent with a volume rim is checked once, dent and rim together; only
//! when they cross is the dent limited first and its rim made again for what is left.
//!
//! [`TriMesh::self_intersections`]: crate::mesh::TriMesh::self_intersections

use std::collections::HashSet;

use glam::Vec3;
use rayon::prelude::*;

use super::guard_pairs::{Reach, pairs_to_test};
use super::map::PendingDisplacement;
use crate::mesh::face_sort::FaceSort;
use crate::mesh::self_intersect::faces_cross;

/// Bisection steps: the scale found is within 2⁻¹² of the largest crossing-free one.
const BISECTION_STEPS: u32 = 12;

/// Limits `pending` (computed from `before`, the positions of a mesh with `faces`) so that it
/// makes no new pair of faces cross; records the scale kept and a warning in its report.
pub(crate) fn guard_crossings(pending: &mut PendingDisplacement, faces: &[[u32; 3]], before: &[Vec3]) {
    let Some(scale) = crossing_free_scale(faces, before, &pending.positions, &pending.moved) else {
        return;
    };
    for ((p, &b), _) in pending.positions.iter_mut().zip(before).zip(&pending.moved).filter(|(_, m)| **m) {
        *p = scaled(b, *p, scale);
    }
    let report = &mut pending.report;
    report.max_displacement *= scale;
    if scale == 0.0 {
        report.moved_vertices = 0;
    }
    report.limited_to = Some(scale);
    let message = format!(
        "dent limited to {:.1} % of its displacement: any deeper, faces near it would cross (a fold through the body)",
        100.0 * scale
    );
    log::warn!("{message}");
    report.warnings.push(message);
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
    let pairs = pairs_to_test(faces, before, &pending.positions, &pending.moved, Reach::Full, presorted);
    let after = crossing_pairs(faces, &pending.positions, &pairs);
    !after.is_empty() && {
        let crossed_before: HashSet<(u32, u32)> = crossing_pairs(faces, before, &after).into_iter().collect();
        after.iter().any(|p| !crossed_before.contains(p))
    }
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

/// `before + s·(after − before)`, exactly `after` at `s = 1`.
fn scaled(before: Vec3, after: Vec3, s: f32) -> Vec3 {
    if s == 1.0 { after } else { before + (after - before) * s }
}

/// `None` when moving `before` to `after` makes no new face pair cross; otherwise the largest
/// scale (to 2⁻¹²) of the displacement that makes none (0 at worst: nothing moves).
fn crossing_free_scale(faces: &[[u32; 3]], before: &[Vec3], after: &[Vec3], moved: &[bool]) -> Option<f32> {
    // The pairs whose boxes after the dent overlap, tested at the full displacement.
    let pairs = pairs_to_test(faces, before, after, moved, Reach::Full, None);
    let crossing_after = crossing_pairs(faces, after, &pairs);
    if crossing_after.is_empty() {
        return None;
    }
    // Those that could cross at any scale (a superset), less those that crossed before.
    let pairs = pairs_to_test(faces, before, after, moved, Reach::Scaled, None);
    let crossed_before: HashSet<(u32, u32)> = crossing_pairs(faces, before, &pairs).into_iter().collect();
    if crossing_after.iter().all(|p| crossed_before.contains(p)) {
        return None;
    }
    let watched: Vec<(u32, u32)> = pairs.into_iter().filter(|p| !crossed_before.contains(p)).collect();
    let mut positions = before.to_vec();
    let (mut lo, mut hi) = (0.0f32, 1.0f32);
    for _ in 0..BISECTION_STEPS {
        let mid = 0.5 * (lo + hi);
        for ((p, (&b, &a)), _) in positions.iter_mut().zip(before.iter().zip(after)).zip(moved).filter(|(_, m)| **m) {
            *p = scaled(b, a, mid);
        }
        if crossing_pairs(faces, &positions, &watched).is_empty() { lo = mid } else { hi = mid }
    }
    Some(lo)
}

/// Below this many pair tests they run on one thread (waking the pool costs more).
const PARALLEL_TESTS: usize = 16384;
