//! The intersection guard, the last stage of a dent: if the dent makes faces around the moved
//! vertices cross where they did not cross before it, or turns a face over (its normal
//! reversed, `mesh::turned_over`: a fold with no crossing), the dent is scaled back (every moved
//! vertex to `before + s·(after − before)`, the largest `s` found by bisection) until no new
//! crossing and no turned face is left. Crossings that were there before the dent are not its
//! business. Turned faces are looked for among the faces with a moved corner, at every step of
//! the bisection (a face's orientation is quadratic in `s`: it can turn and turn back), less
//! those whose corners move so nearly together that no scale turns them
//! (`mesh::turned_over::may_turn_over`).
//!
//! A small closed mesh whose faces the dent moved a large share of (a ball dented by something
//! its size) is first checked whole: when it is star-shaped about its vertex mean after the
//! dent (`mesh::star`), no two of its faces cross, and the local checks below are skipped.
//!
//! Cost: one pass over the faces to find the moved ones and the unmoved ones near them (the
//! volume stage's own pass, when it ran and its region holds them), a check
//! of whether the moved faces' patches are height fields after the dent (`mesh::height_field`:
//! a crater and its rim on a surface seen from one side are; then no two faces of a patch
//! cross, and its pairs are never listed), a grid for the other pairs whose boxes after the
//! dent overlap, and the exact test (see [`TriMesh::self_intersections`]) of each such pair at
//! the full displacement, less the pairs of neighbours around a vertex whose umbrella is
//! certified embedded (`mesh::umbrella`). Only for a dent
//! that does make faces cross (or turn over), the bisection runs on the pairs found crossing
//! at the full displacement, and the scale it finds is checked as the full displacement was
//! (every pair whose boxes at that scale overlap); a pair crossing there joins the watched ones
//! and the bisection goes on below it. The scale kept is always one at which that check found
//! nothing. Only after several such rounds does the guard watch every pair that could cross at
//! some scale: those whose swept boxes meet and that their vertices' relative motion cannot
//! clear (`guard_pairs`: neighbours moving together need no test; this is sound for every
//! scale, no motion is too small to matter), dropping, as the bisection's upper end falls, the
//! pairs those bounds clear for the smaller displacement. A dent with a volume rim is checked
//! once, dent and rim together; only when they cross is the dent limited first and its rim made
//! again for what is left.
//!
//! [`TriMesh::self_intersections`]: crate::mesh::TriMesh::self_intersections

use std::collections::HashSet;

use glam::Vec3;
use rayon::prelude::*;

use super::guard_pairs::{KnownPatches, Reach, pairs_to_test, pairs_within_scale};
use super::map::PendingDisplacement;
use crate::mesh::face_sort::FaceSort;
use crate::mesh::self_intersect::faces_cross;
use crate::mesh::star::star_shaped_closed;
use crate::mesh::turned_over::{is_turned_over, may_turn_over};

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
    let (positions, moved) = (&pending.positions, &pending.moved);
    !turned_over(faces, before, positions, &moved_faces).is_empty()
        || !new_crossing_pairs(
            faces,
            before,
            positions,
            moved,
            moved_faces.len(),
            presorted,
            &mut KnownPatches::default(),
        )
        .is_empty()
}

/// A closed mesh with at most this many faces per face the dent moved is first checked whole
/// (`mesh::star`: one pass over its faces), before the local checks near the dent.
const WHOLE_MESH_FACES_PER_MOVED: usize = 8;

/// Whether `positions` are certified free of crossings as a whole: the mesh is small next to
/// what the dent moved (`moved_faces` faces), closed, and star-shaped about its vertex mean.
fn certified_whole(faces: &[[u32; 3]], positions: &[Vec3], moved_faces: usize) -> bool {
    faces.len() <= WHOLE_MESH_FACES_PER_MOVED * moved_faces && star_shaped_closed(positions, faces)
}

/// The pairs of faces that cross at `positions` (`before` with the vertices `moved` flags
/// moved, which `moved_faces` faces have a corner of) but did not cross at `before`: none when
/// the mesh is certified whole ([`certified_whole`]); else every pair whose boxes at `positions`
/// overlap, less the certified ones, tested exactly. `presorted` as
/// `guard_pairs::pairs_to_test` takes it.
fn new_crossing_pairs(
    faces: &[[u32; 3]],
    before: &[Vec3],
    positions: &[Vec3],
    moved: &[bool],
    moved_faces: usize,
    presorted: Option<FaceSort>,
    known: &mut KnownPatches,
) -> Vec<(u32, u32)> {
    if certified_whole(faces, positions, moved_faces) {
        return Vec::new();
    }
    let pairs = pairs_to_test(faces, before, positions, moved, Reach::Full, presorted, known);
    let crossing = crossing_pairs(faces, positions, &pairs);
    if crossing.is_empty() {
        return crossing;
    }
    let crossed_before: HashSet<(u32, u32)> = crossing_pairs(faces, before, &crossing).into_iter().collect();
    crossing.into_iter().filter(|p| !crossed_before.contains(p)).collect()
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

/// The faces of `candidates` (ascending) that some scale of the move from `before` to `after`
/// could turn over (`mesh::turned_over::may_turn_over`: the others never turn).
fn faces_that_may_turn_over(faces: &[[u32; 3]], before: &[Vec3], after: &[Vec3], candidates: &[u32]) -> Vec<u32> {
    let may_turn = |f: &u32| may_turn_over(faces[*f as usize], before, after);
    if candidates.len() < PARALLEL_FACES {
        candidates.iter().copied().filter(may_turn).collect()
    } else {
        candidates.par_iter().with_min_len(PARALLEL_FACES / 2).copied().filter(may_turn).collect()
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
///
/// The scale is searched first on the pairs known to cross (at the full displacement, to begin
/// with), and the scale found is then checked against every pair as the full displacement was
/// (pairs whose boxes at that scale overlap, less the certified ones). Where that finds a new
/// crossing, its pairs join the watched ones and the search goes on below that scale. After
/// [`MAX_VERIFIED_SEARCHES`] searches it falls back to watching every pair that could cross at
/// any scale (`guard_pairs`' bounds), which needs no check afterwards.
fn crossing_free_scale(faces: &[[u32; 3]], before: &[Vec3], after: &[Vec3], moved: &[bool]) -> Option<Limit> {
    let moved_faces = faces_with_moved_corner(faces, moved);
    let turned_over_after = turned_over(faces, before, after, &moved_faces);
    // The checks at the scales the search finds try the patches the first one certified.
    let mut known = KnownPatches::default();
    let mut new_crossings =
        |positions: &[Vec3]| new_crossing_pairs(faces, before, positions, moved, moved_faces.len(), None, &mut known);
    let crossing_after = new_crossings(after);
    let crosses = !crossing_after.is_empty();
    if !crosses && turned_over_after.is_empty() {
        return None;
    }
    let limit = |scale| Some(Limit { scale, crosses, turned_over: turned_over_after.clone() });
    // The searches look for turned faces only among those a bound does not clear at every scale.
    let may_turn = faces_that_may_turn_over(faces, before, after, &moved_faces);
    let mut positions = before.to_vec();
    let mut watched = crossing_after;
    let mut hi = 1.0f32;
    for _ in 0..MAX_VERIFIED_SEARCHES {
        let lo = search_scale(faces, before, after, moved, &may_turn, watched.clone(), (0.0, hi), &mut positions);
        if lo == 0.0 {
            return limit(0.0);
        }
        // The search wrote the positions at `lo` last; every pair is checked there.
        set_scale(&mut positions, before, after, moved, lo);
        let found = new_crossings(&positions);
        if found.is_empty() {
            return limit(lo);
        }
        watched.extend(found);
        hi = lo;
    }
    // Every pair that could cross at some scale, less those that crossed before.
    let pairs = pairs_to_test(faces, before, after, moved, Reach::Scaled, None, &mut KnownPatches::default());
    let crossed_before: HashSet<(u32, u32)> = crossing_pairs(faces, before, &pairs).into_iter().collect();
    let watched: Vec<(u32, u32)> = pairs.into_iter().filter(|p| !crossed_before.contains(p)).collect();
    limit(search_scale(faces, before, after, moved, &may_turn, watched, (0.0, hi), &mut positions))
}

/// Searches at most this many times on the watched pairs before watching every pair.
const MAX_VERIFIED_SEARCHES: usize = 8;

/// `positions`' moved vertices at `scale` of the displacement from `before` to `after`.
fn set_scale(positions: &mut [Vec3], before: &[Vec3], after: &[Vec3], moved: &[bool], scale: f32) {
    for ((p, (&b, &a)), _) in positions.iter_mut().zip(before.iter().zip(after)).zip(moved).filter(|(_, m)| **m) {
        *p = scaled(b, a, scale);
    }
}

/// Bisects `bracket` (its lower end clear) for the largest scale, to 2⁻¹² of its width, at which
/// no face of `may_turn` is turned over and no pair of `watched` crosses; `positions` is
/// left at the last scale tried.
///
/// Each step needs only whether some watched pair crosses: the last pair found crossing is
/// tried first (it often crosses again), and the search stops at the first. With many watched
/// pairs (every pair that could cross at some scale), before a step scans them those that
/// cannot cross at any scale up to the bracket's upper end are dropped if it fell since the
/// last such pass (`pairs_within_scale`: the same bounds, on the smaller displacement; later
/// steps try only scales below it; a hint dropped so cannot cross either). Neither changes a
/// step's outcome.
#[allow(clippy::too_many_arguments)]
fn search_scale(
    faces: &[[u32; 3]],
    before: &[Vec3],
    after: &[Vec3],
    moved: &[bool],
    may_turn: &[u32],
    mut watched: Vec<(u32, u32)>,
    (mut lo, mut hi): (f32, f32),
    positions: &mut [Vec3],
) -> f32 {
    let (mut hint, mut filtered_at) = (None, hi);
    for _ in 0..BISECTION_STEPS {
        let mid = 0.5 * (lo + hi);
        set_scale(positions, before, after, moved, mid);
        let clear = turned_over(faces, before, positions, may_turn).is_empty()
            && !hint.is_some_and(|(f, g)| faces_cross(positions, faces, f, g))
            && {
                if hi < filtered_at && watched.len() >= PARALLEL_TESTS {
                    watched = pairs_within_scale(faces, before, after, &watched, hi);
                    filtered_at = hi;
                }
                let found = first_crossing(faces, positions, &watched);
                hint = found.or(hint);
                found.is_none()
            };
        if clear { lo = mid } else { hi = mid }
    }
    lo
}

/// Below this many faces the moved ones are listed on one thread.
const PARALLEL_FACES: usize = 65536;

/// Below this many pair tests they run on one thread (waking the pool costs more).
const PARALLEL_TESTS: usize = 16384;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dent::DisplaceReport;

    /// Blades rising through still triangles: per blade `(height, rise)`, its base from z = −2
    /// up by `rise` at the full displacement, so that it crosses its triangle (in z = 0) for
    /// the scales `s` in `((2 − height) / rise, 2 / rise)`. Each blade and triangle pair sits
    /// 10 apart along x. Faces `2k` and `2k + 1` are the k-th triangle and blade.
    fn rising_blades(blades: &[(f32, f32)]) -> (Vec<Vec3>, Vec<[u32; 3]>, PendingDisplacement) {
        let (mut before, mut faces, mut moved, mut rise) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (k, &(height, by)) in blades.iter().enumerate() {
            let (x, first) = (10.0 * k as f32, before.len() as u32);
            before.extend([Vec3::new(x - 1.0, -1.0, 0.0), Vec3::new(x + 1.0, -1.0, 0.0), Vec3::new(x, 1.0, 0.0)]);
            before.extend([
                Vec3::new(x - 0.3, 0.0, -2.0),
                Vec3::new(x + 0.3, 0.0, -2.0),
                Vec3::new(x, 0.0, height - 2.0),
            ]);
            faces.extend([[first, first + 1, first + 2], [first + 3, first + 4, first + 5]]);
            moved.extend([false, false, false, true, true, true]);
            rise.extend([0.0, 0.0, 0.0, by, by, by]);
        }
        let positions: Vec<Vec3> = before.iter().zip(&rise).map(|(p, &r)| *p + Vec3::Z * r).collect();
        let report = DisplaceReport { moved_vertices: 3 * blades.len(), ..Default::default() };
        (before, faces, PendingDisplacement { positions, moved, report })
    }

    /// A blade that crosses its triangle for the scales `(start, end)`.
    fn blade(start: f32, end: f32) -> (f32, f32) {
        let by = 2.0 / end;
        (2.0 - by * start, by)
    }

    fn none_cross(positions: &[Vec3], faces: &[[u32; 3]]) -> bool {
        (0..faces.len() as u32 / 2).all(|k| !faces_cross(positions, faces, 2 * k, 2 * k + 1))
    }

    /// Blade A crosses from s ≈ 0.556 on (at the full displacement too); blade B only for s in
    /// (0.4, 0.7), so the full displacement shows A alone. Searching on A's pair finds
    /// s ≈ 0.556, where B crosses: the check at that scale must catch it, and the scale kept is
    /// where B begins to cross, 0.4 (within the second search's 2⁻¹² of its bracket, ≈ 0.556).
    #[test]
    fn a_pair_crossing_only_midway_is_caught_by_the_check_at_the_scale_found() {
        let (before, faces, mut pending) = rising_blades(&[(1.0, 1.8), blade(0.4, 0.7)]);
        assert!(faces_cross(&pending.positions, &faces, 0, 1) && !faces_cross(&pending.positions, &faces, 2, 3));
        guard_crossings(&mut pending, &faces, &before);
        let kept = pending.report.limited_to.expect("limited");
        assert!((0.4 - 0.56 * 2f32.powi(-12) - 1e-5..=0.4 + 1e-5).contains(&kept), "kept {kept}");
        assert!(none_cross(&pending.positions, &faces));
    }

    /// A chain of blades, each crossing from a little below where the previous one starts to
    /// just past it: every check at a scale found finds the next blade, more times than the
    /// guard searches on watched pairs, so it falls back to watching every pair that could
    /// cross. The scale kept is where the last blade begins to cross.
    #[test]
    fn a_long_chain_of_midway_crossings_falls_back_to_every_pair() {
        // The first blade, of height 1 rising by 1.8, crosses from (2 − 1) / 1.8 on.
        let mut blades = vec![(1.0, 1.8)];
        let mut start = (2.0 - 1.0) / 1.8;
        for _ in 0..(MAX_VERIFIED_SEARCHES + 2) {
            let next = start - 0.04;
            blades.push(blade(next, start + 0.02));
            start = next;
        }
        let (before, faces, mut pending) = rising_blades(&blades);
        guard_crossings(&mut pending, &faces, &before);
        let kept = pending.report.limited_to.expect("limited");
        assert!((start - 2f32.powi(-12) - 1e-5..=start + 1e-5).contains(&kept), "kept {kept}, expected {start}");
        assert!(none_cross(&pending.positions, &faces));
    }

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
