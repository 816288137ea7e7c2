//! The face pairs that a dent's displacement could make cross: what the intersection guard must
//! test exactly. Every other pair near the dent is cleared here, for every scale of the
//! displacement at once, by a bound on how far its vertices move relative to each other.
//!
//! Vertex `i` moves from `b_i` by `u_i` (zero where it did not move); the guard tries the scaled
//! displacements `b_i + s·u_i`, `0 < s ≤ 1`. A pair of faces, one of them moved, can meet at some
//! scale only if the boxes the two faces sweep from before to after overlap; those pairs are
//! found with a uniform grid. Each is then cleared when one of these holds before the dent
//! (`R` below is the relative motion bound named, plus the slack described at the end):
//!
//! * **Apart** (no shared vertex). Let `r` bound `|u_i − u_j|` over the pair's six vertices (the
//!   diagonal of their displacements' box does). A point of a face is a convex combination of its
//!   corners and moves by the same combination of their `s·u_i`, so the vector between a point of
//!   one face and a point of the other changes by a combination of the `s·(u_i − u_j)`: by at
//!   most `r`. The faces' distance shrinks by at most `r`, and boxes more than `R` apart before
//!   never let them meet.
//! * **Sharing one vertex** `a` (other corners `b, c` and `d, e`). Let `r` bound `|u_x − u_a|`.
//!   If a plane through `a` with normal `n` has `b, c` more than `|n|·R` above it and `d, e` more
//!   than `|n|·R` below, then `n·(x_s − a_s) = n·(x − a) + s·n·(u_x − u_a)` keeps its sign at
//!   every scale: the plane moved with `a` still separates the faces, which meet only at `a`.
//!   `n` is the difference of the two faces' corner directions at `a` (sums of unit arms).
//! * **Sharing an edge** `ab` (third corners `c`, `d`). Two faces with a common edge cross only
//!   folded flat onto each other, `c` and `d` on one side of the edge in a common plane; so they
//!   cannot while some plane through the moved edge has `c_s` and `d_s` strictly on opposite
//!   sides. Take `n` perpendicular to `e = b − a` (to rounding: `|n·e|` is carried), with
//!   `n·(c − a) > 0 > n·(d − a)`, and `r` bounding `|u_x − u_a|`. At scale `s` let
//!   `E = b_s − a_s` (`|E − e| ≤ R`) and `C = c_s − a_s` (`|C − (c − a)| ≤ R`); the plane through
//!   the moved edge with normal `n_s = n − (n·E/|E|²)·E` has
//!   `n_s·C ≥ n·(c − a) − |n|·R − (|n·e| + |n|·R)·(|e| + R)·(|c − a| + R) / (|e| − R)²`,
//!   and the same for `−n_s·D`; both positive clear the pair.
//!
//! Distances are computed in f64 from the f32 positions. `R` is the motion bound plus a slack of
//! four f32 ulps of the largest coordinate and displacement near the dent, which covers the f64
//! arithmetic and the rounding of the scaled positions `b + (a − b)·s` the guard writes (at most
//! half an ulp of the displacement and of the result, per coordinate and vertex).

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::mesh::cover_mask::CoverMask;
use crate::mesh::face_grid::{Aabb, overlapping_pairs, pairs_between};
use crate::mesh::face_sort::{FaceSort, MARK_A, out_code};
use crate::mesh::height_field::{CertifiedPart, PatchLabels, UNCERTIFIED, certified_again, certified_patches};
use crate::mesh::umbrella::Umbrellas;

/// The height-field patches the first check of a dent at the full displacement certified,
/// kept for its checks at other scales (the guard's bisection): those try these patches alone,
/// each checked again at its own positions, instead of searching for patches anew. Empty until
/// a check fills it.
#[derive(Debug, Default)]
pub(crate) struct KnownPatches(Option<Vec<CertifiedPart>>);

/// Which scales of the displacement the pairs are wanted for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Reach {
    /// The full displacement only: pairs whose boxes after the dent overlap (less those a
    /// height-field or umbrella certificate clears).
    Full,
    /// Every scale in `(0, 1]`: pairs whose boxes swept from before to after overlap. (A scaled
    /// position `b + (a − b)·s`, `s < 1`, rounded, stays between `b` and `a`.)
    Scaled,
}

/// Pairs `(f, g)` of faces (`f` moved, or marked in `presorted`) that moving `before` to
/// `after` (with `moved` flagging the vertices that moved) could make cross at the scales
/// `reach` names: for
/// [`Reach::Scaled`], those that no bound in the module documentation clears; for
/// [`Reach::Full`], every pair whose boxes after the move overlap but those within a patch
/// certified a height field after the move (see `mesh::height_field`) and those sharing a
/// vertex whose umbrella is certified after the move (see `mesh::umbrella`). Each pair once,
/// as `(smaller, larger)` index. `presorted`, when given, is a sort of the faces made
/// beforehand (for example in the volume stage's pass) whose marked faces include every face
/// with a moved corner (they may include unmoved ones); it saves a pass over the faces when
/// every marked face's corners lie in its region before and after the move. `known`: for
/// [`Reach::Full`], the patches an earlier check of the same dent certified, tried alone
/// instead of searching anew; an empty one is filled with the patches this check certifies.
pub(crate) fn pairs_to_test(
    faces: &[[u32; 3]],
    before: &[Vec3],
    after: &[Vec3],
    moved: &[bool],
    reach: Reach,
    presorted: Option<FaceSort>,
    known: &mut KnownPatches,
) -> Vec<(u32, u32)> {
    // The near set's completeness (every face around a corner of a moved face) rests on this.
    debug_assert!(
        before.iter().zip(after).zip(moved).all(|((b, a), &m)| m || b == a),
        "a vertex not flagged as moved changed position"
    );
    let near = NearFaces::find(faces, before, after, moved, reach, presorted);
    if near.active == 0 {
        return Vec::new();
    }
    if reach == Reach::Full {
        return full_reach_pairs(faces, after, &near, known);
    }
    let candidates = overlapping_pairs(&near.reached, near.active, |_, _| true);
    let id = |(i, j): (u32, u32)| {
        let (f, g) = (near.faces[i as usize], near.faces[j as usize]);
        (f.min(g), f.max(g))
    };
    let slack = 4.0 * f64::from(f32::EPSILON) * near.scale;
    let motion = Motion { faces, before, after, reach: 1.0, slack };
    let keep = |&(i, j): &(u32, u32)| {
        let gap = || near.before[i as usize].distance(&near.before[j as usize]);
        let (f, g) = (near.faces[i as usize], near.faces[j as usize]);
        motion.may_cross(f, g, gap).then(|| id((i, j)))
    };
    if candidates.len() < PARALLEL_PAIRS {
        candidates.iter().filter_map(keep).collect()
    } else {
        candidates.par_iter().with_min_len(PARALLEL_PAIRS / 2).filter_map(keep).collect()
    }
}

/// The pairs of `pairs` (listed by [`pairs_to_test`] with [`Reach::Scaled`] for the same move)
/// that could still cross at some scale in `(0, reach]`. The positions at those scales,
/// `b + s·u` with `s ≤ reach`, are the scales `(0, 1]` of the displacement `reach·u`, so the
/// module's bounds apply to it unchanged (in f64, `reach·u` is exact for the guard's dyadic
/// scales); the rounding of the positions the guard writes is no larger than at the full
/// displacement, so the slack is the one for `u`, from the pairs' own corners. A pair cleared
/// here does not meet at any such scale, so dropping it changes no test's outcome.
pub(crate) fn pairs_within_scale(
    faces: &[[u32; 3]],
    before: &[Vec3],
    after: &[Vec3],
    pairs: &[(u32, u32)],
    reach: f32,
) -> Vec<(u32, u32)> {
    let corners = || pairs.iter().flat_map(|&(f, g)| faces[f as usize].into_iter().chain(faces[g as usize]));
    let (extent, displacement) = corners().fold((0.0f32, 0.0f32), |(e, d), v| {
        let (b, a) = (before[v as usize], after[v as usize]);
        (e.max(b.abs().max_element()).max(a.abs().max_element()), d.max((a - b).abs().max_element()))
    });
    let slack = 4.0 * f64::from(f32::EPSILON) * (f64::from(extent) + f64::from(displacement));
    let motion = Motion { faces, before, after, reach: f64::from(reach), slack };
    let box_before = |f: u32| Aabb::of(faces[f as usize].map(|v| before[v as usize]));
    let keep = |&&(f, g): &&(u32, u32)| motion.may_cross(f, g, || box_before(f).distance(&box_before(g)));
    if pairs.len() < PARALLEL_PAIRS {
        pairs.iter().filter(keep).copied().collect()
    } else {
        pairs.par_iter().with_min_len(PARALLEL_PAIRS / 2).filter(keep).copied().collect()
    }
}

/// The pairs for [`Reach::Full`]: those whose boxes after the move overlap, less the pairs
/// within a patch of moved faces certified a height field after the move, with its ring of
/// unmoved faces where that is certified too (`mesh::height_field`: none of its faces cross;
/// its pairs are not even enumerated), and those sharing a vertex whose umbrella is certified
/// after the move (`mesh::umbrella`: they only touch).
fn full_reach_pairs(faces: &[[u32; 3]], after: &[Vec3], near: &NearFaces, known: &mut KnownPatches) -> Vec<(u32, u32)> {
    let (moved, ring) = (&near.faces[..near.active], &near.faces[near.active..]);
    let PatchLabels { moved: moved_labels, ring: ring_labels, parts } = match &known.0 {
        Some(patches) => certified_again(after, faces, moved, ring, patches),
        None => certified_patches(after, faces, moved, ring),
    };
    known.0.get_or_insert(parts);
    let label = |k: u32| match (k as usize).checked_sub(near.active) {
        None => moved_labels[k as usize],
        Some(unmoved) => ring_labels[unmoved],
    };
    // Indices into `near`: the certified patches' moved faces, and the rest (moved ones first).
    let (patches, mut rest): (Vec<u32>, Vec<u32>) = (0..near.active as u32).partition(|&k| label(k) != UNCERTIFIED);
    let rest_active = rest.len();
    rest.extend(near.active as u32..near.faces.len() as u32);
    let boxes = |indices: &[u32]| indices.iter().map(|&k| near.reached[k as usize]).collect::<Vec<_>>();
    let rest_boxes = boxes(&rest);
    // Pairs sharing a vertex whose umbrella is certified only touch: they are dropped as they
    // are found. Every such vertex is a corner of a moved face, whose faces are all near.
    let face = |k: u32| near.faces[k as usize];
    let umbrellas = Umbrellas::new(after, faces, moved, &near.faces);
    let may_cross = |i: u32, j: u32| !umbrellas.only_touch(face(i), face(j));
    let mut candidates: Vec<(u32, u32)> =
        overlapping_pairs(&rest_boxes, rest_active, |i, j| may_cross(rest[i as usize], rest[j as usize]))
            .into_iter()
            .map(|(i, j)| (rest[i as usize], rest[j as usize]))
            .collect();
    // Every patch face against the rest but its own ring; and against the moved faces of the
    // other patches, each such pair found once from its face in the patch numbered higher.
    // A face is queried against a patch only if its box meets the box of the patch's faces.
    let mut patch_boxes: Vec<Aabb> = Vec::new();
    for &k in &patches {
        let l = label(k) as usize;
        if l >= patch_boxes.len() {
            patch_boxes.resize(l + 1, Aabb::EMPTY);
        }
        patch_boxes[l] = patch_boxes[l].union(near.reached[k as usize]);
    }
    // Whether face `q`'s pairs with patch `l`'s faces are wanted from this side: an uncertified
    // face's all are; a ring face's but with its own patch; a patch's moved face's with the
    // patches numbered lower only (the others find it).
    let wanted = |q: u32, l: u32| match label(q) {
        UNCERTIFIED => true,
        own if (q as usize) < near.active => l < own,
        ring => l != ring,
    };
    // Patch by patch, its faces against the faces that want pairs with it and whose boxes meet
    // the patch's (no pair within a patch is ever listed).
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); patch_boxes.len()];
    patches.iter().for_each(|&k| members[label(k) as usize].push(k));
    let meeting = |q: u32| -> Vec<(u32, u32)> {
        let b = near.reached[q as usize];
        patch_boxes.iter().zip(0..).filter(|(p, l)| wanted(q, *l) && p.overlaps(&b)).map(|(_, l)| (l, q)).collect()
    };
    let askers: Vec<u32> = rest.iter().chain(&patches).copied().collect();
    let mut asked: Vec<(u32, u32)> = if askers.len() < PARALLEL_PAIRS {
        askers.iter().flat_map(|&q| meeting(q)).collect()
    } else {
        askers.par_iter().with_min_len(PARALLEL_PAIRS / 2).flat_map_iter(|&q| meeting(q)).collect()
    };
    asked.sort_unstable();
    for run in asked.chunk_by(|a, b| a.0 == b.0) {
        let own = &members[run[0].0 as usize];
        let queries: Vec<u32> = run.iter().map(|&(_, q)| q).collect();
        let keep = |i: u32, j: u32| may_cross(own[i as usize], queries[j as usize]);
        candidates.extend(
            pairs_between(&boxes(own), &boxes(&queries), keep)
                .into_iter()
                .map(|(i, j)| (own[i as usize], queries[j as usize])),
        );
    }
    candidates
        .into_iter()
        .map(|(i, j)| {
            let (f, g) = (face(i), face(j));
            (f.min(g), f.max(g))
        })
        .collect()
}

/// Below this many candidate pairs the clearing runs on one thread (waking the pool costs more).
const PARALLEL_PAIRS: usize = 4096;

/// The faces near a dent, moved ones first, with their boxes.
struct NearFaces {
    /// Face indices: the `active` moved faces (with a presort: its marked faces, which may
    /// include unmoved ones), then unmoved faces whose box meets theirs.
    faces: Vec<u32>,
    active: usize,
    /// Boxes after the dent, or swept from before to after (see [`Reach`]); equal to `before`
    /// for unmoved faces.
    reached: Vec<Aabb>,
    /// Boxes before the dent ([`Reach::Scaled`] only; empty for [`Reach::Full`]).
    before: Vec<Aabb>,
    /// Largest absolute coordinate or displacement component among these faces, world units
    /// ([`Reach::Scaled`] only; zero for [`Reach::Full`]).
    scale: f64,
}

impl NearFaces {
    fn find(
        faces: &[[u32; 3]],
        before: &[Vec3],
        after: &[Vec3],
        moved: &[bool],
        reach: Reach,
        presorted: Option<FaceSort>,
    ) -> Self {
        // A sort made beforehand serves when its marked faces' corners lie in its region after
        // the move too (before, its `inside` says), and then needs no second pass.
        let mut presorted = presorted.filter(|sort| {
            let corners = sort.marked.iter().flat_map(|&f| faces[f as usize]);
            sort.inside && corners.into_iter().all(|v| out_code(after[v as usize], &sort.region) == 0)
        });
        debug_assert!(
            presorted.as_ref().is_none_or(|sort| {
                let mut marked = vec![false; faces.len()];
                sort.marked.iter().for_each(|&f| marked[f as usize] = true);
                faces.iter().zip(&marked).all(|(face, &m)| m || face.iter().all(|&v| !moved[v as usize]))
            }),
            "a presort left out a face with a moved corner"
        );
        // Otherwise where the moved faces lie is guessed first as the moved vertices' box
        // (before and after) widened by a twentieth of its size, so that one pass over the faces
        // finds them and the unmoved faces that may meet them: when the guess holds every moved
        // face's corners before, it holds the moved faces' boxes. Otherwise the pass is repeated
        // with the box of the moved faces themselves.
        let first_guess = || {
            let moved_box = before
                .iter()
                .zip(after)
                .zip(moved)
                .filter(|(_, m)| **m)
                .fold(Aabb::EMPTY, |b, ((&p, &q), _)| b.union(Aabb::of([p, q])));
            let widen = Vec3::splat(0.05 * (moved_box.max - moved_box.min).max_element().max(0.0));
            Aabb { min: moved_box.min - widen, max: moved_box.max + widen }
        };
        let mut guess = None;
        let box_before = |f: u32| Aabb::of(faces[f as usize].map(|v| before[v as usize]));
        let box_after = |f: u32| Aabb::of(faces[f as usize].map(|v| after[v as usize]));
        loop {
            let sort = match presorted.take() {
                Some(sort) => sort,
                None => sort_faces(faces, before, moved, *guess.get_or_insert_with(first_guess)),
            };
            let (mut list, maybe, inside) = (sort.marked, sort.maybe, sort.inside);
            let active = list.len();
            // Boxes before are needed for the swept boxes, the bounds and a second pass only.
            let scaled = reach == Reach::Scaled;
            let mut boxes_before: Vec<Aabb> =
                if scaled || !inside { list.iter().map(|&f| box_before(f)).collect() } else { Vec::new() };
            let mut reached: Vec<Aabb> = list.iter().map(|&f| box_after(f)).collect();
            if scaled {
                reached.iter_mut().zip(&boxes_before).for_each(|(r, b)| *r = r.union(*b));
            }
            if !inside {
                // Holds every moved face before and after: the next pass finds all inside.
                guess = Some(reached.iter().chain(&boxes_before).fold(Aabb::EMPTY, |r, b| r.union(*b)));
                continue;
            }
            let mask = CoverMask::new(&reached);
            for f in maybe {
                let b = box_before(f);
                if mask.may_overlap(&b) {
                    list.push(f);
                    reached.push(b);
                    if scaled {
                        boxes_before.push(b);
                    }
                }
            }
            if !scaled {
                return Self { faces: list, active, reached, before: boxes_before, scale: 0.0 };
            }
            let extent = reached
                .iter()
                .chain(&boxes_before)
                .fold(0.0f32, |m, b| m.max(b.min.abs().max_element()).max(b.max.abs().max_element()));
            let displacement = list[..active]
                .iter()
                .flat_map(|&f| faces[f as usize])
                .map(|v| (after[v as usize] - before[v as usize]).abs().max_element())
                .fold(0.0f32, f32::max);
            let scale = f64::from(extent) + f64::from(displacement);
            return Self { faces: list, active, reached, before: boxes_before, scale };
        }
    }
}

/// One pass over the faces: those with a moved corner (marked), the unmoved ones that may reach
/// into `guess`, and whether every moved face's corners lie inside it.
fn sort_faces(faces: &[[u32; 3]], before: &[Vec3], moved: &[bool], guess: Aabb) -> FaceSort {
    let codes: Vec<u8> =
        before.iter().zip(moved).map(|(&p, &m)| out_code(p, &guess) | if m { MARK_A } else { 0 }).collect();
    FaceSort::new(faces, &codes, Some(guess))
}

/// Euclidean distance between boxes.
trait BoxGap {
    fn distance(&self, other: &Self) -> f64;
}

impl BoxGap for Aabb {
    fn distance(&self, other: &Self) -> f64 {
        let gap = (other.min - self.max).max(self.min - other.max).max(Vec3::ZERO).as_dvec3();
        gap.length()
    }
}

/// One displacement: positions before and after, the scale `reach` of `after − before` taken
/// as the displacement (1: all of it), and the slack added to every motion bound.
struct Motion<'a> {
    faces: &'a [[u32; 3]],
    before: &'a [Vec3],
    after: &'a [Vec3],
    reach: f64,
    slack: f64,
}

impl Motion<'_> {
    fn position(&self, v: u32) -> DVec3 {
        self.before[v as usize].as_dvec3()
    }

    fn displacement(&self, v: u32) -> DVec3 {
        (self.after[v as usize].as_dvec3() - self.before[v as usize].as_dvec3()) * self.reach
    }

    /// Whether faces `f` and `g`, whose boxes before lie `gap()` apart, are not cleared.
    fn may_cross(&self, f: u32, g: u32, gap: impl FnOnce() -> f64) -> bool {
        let (p, q) = (self.faces[f as usize], self.faces[g as usize]);
        let collapsed = |t: [u32; 3]| t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
        if collapsed(p) || collapsed(q) {
            // A face with a repeated corner has no area at any scale and crosses nothing.
            return false;
        }
        let mut shared = [(0, 0); 2];
        let mut count = 0;
        for (i, &corner) in p.iter().enumerate() {
            for (j, &other) in q.iter().enumerate() {
                if corner == other {
                    if count < 2 {
                        shared[count] = (i, j);
                    }
                    count += 1;
                }
            }
        }
        match count {
            0 => gap() <= self.apart_motion(p, q) + self.slack,
            1 => !self.wedges_stay_apart(p, q, shared[0].0, shared[0].1),
            2 => {
                let [(i, j), (k, l)] = shared;
                !self.hinge_stays_open(p[i], p[k], p[3 - i - k], q[3 - j - l])
            }
            _ => true,
        }
    }

    /// Diagonal of the box of the six corners' displacements: bounds every `|u_i − u_j|`.
    fn apart_motion(&self, p: [u32; 3], q: [u32; 3]) -> f64 {
        let mut lo = DVec3::INFINITY;
        let mut hi = DVec3::NEG_INFINITY;
        for v in p.into_iter().chain(q) {
            let u = self.displacement(v);
            lo = lo.min(u);
            hi = hi.max(u);
        }
        (hi - lo).length()
    }

    /// The largest `|u_x − u_a|` over `others`, plus the slack.
    fn motion_about(&self, a: u32, others: &[u32]) -> f64 {
        let ua = self.displacement(a);
        others.iter().map(|&x| (self.displacement(x) - ua).length_squared()).fold(0.0, f64::max).sqrt() + self.slack
    }

    /// Faces `p` and `q` sharing only corner `p[i] = q[j]`: whether a plane through it keeps
    /// them apart at every scale (see the module documentation).
    fn wedges_stay_apart(&self, p: [u32; 3], q: [u32; 3], i: usize, j: usize) -> bool {
        let a = p[i];
        let (b, c) = (p[(i + 1) % 3], p[(i + 2) % 3]);
        let (d, e) = (q[(j + 1) % 3], q[(j + 2) % 3]);
        let origin = self.position(a);
        let arms = [b, c, d, e].map(|x| self.position(x) - origin);
        let [Some(ub), Some(uc), Some(ud), Some(ue)] = arms.map(DVec3::try_normalize) else {
            return false;
        };
        let n = ub + uc - ud - ue;
        let clear = n.dot(arms[0]).min(n.dot(arms[1])).min(-n.dot(arms[2])).min(-n.dot(arms[3]));
        clear > 0.0 && clear > n.length() * self.motion_about(a, &[b, c, d, e])
    }

    /// Faces `(a, b, c)` and `(·, ·, d)` sharing the edge `ab`: whether `c` and `d` stay strictly
    /// on opposite sides of a plane through the moved edge at every scale (module documentation).
    fn hinge_stays_open(&self, a: u32, b: u32, c: u32, d: u32) -> bool {
        let origin = self.position(a);
        let edge = self.position(b) - origin;
        let (to_c, to_d) = (self.position(c) - origin, self.position(d) - origin);
        let length_sq = edge.length_squared();
        if length_sq == 0.0 {
            return false;
        }
        let across = |x: DVec3| (x - edge * (x.dot(edge) / length_sq)).try_normalize();
        let (Some(wc), Some(wd)) = (across(to_c), across(to_d)) else {
            return false;
        };
        let n = wc - wd;
        let norm = n.length();
        let r = self.motion_about(a, &[b, c, d]);
        let length = length_sq.sqrt();
        if length <= r {
            return false;
        }
        let tilt = (n.dot(edge).abs() + norm * r) * (length + r) / ((length - r) * (length - r));
        let clear_c = n.dot(to_c) - norm * r - tilt * (to_c.length() + r);
        let clear_d = -n.dot(to_d) - norm * r - tilt * (to_d.length() + r);
        clear_c > 0.0 && clear_d > 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn motion<'a>(faces: &'a [[u32; 3]], before: &'a [Vec3], after: &'a [Vec3]) -> Motion<'a> {
        Motion { faces, before, after, reach: 1.0, slack: 1e-9 }
    }

    #[test]
    fn flat_neighbours_moving_together_are_cleared_and_a_fold_is_not() {
        // A fan of four faces around the origin in the xy-plane.
        // Face 4 shares the edge 1–2 with face 0; face 5 lies apart.
        let far = [Vec3::new(3.0, 3.0, 0.0), Vec3::new(4.0, 3.0, 0.0), Vec3::new(3.0, 4.0, 0.0)];
        let mut before = vec![Vec3::ZERO, Vec3::X, Vec3::Y, -Vec3::X, -Vec3::Y, Vec3::new(1.0, 1.0, 0.0)];
        before.extend(far);
        let faces = [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1], [1, 5, 2], [6, 7, 8]];
        let shifted: Vec<Vec3> = before.iter().map(|&p| p + Vec3::new(0.3, -0.2, 0.5)).collect();
        let m = motion(&faces, &before, &shifted);
        // Sharing a vertex, an edge, nothing: all cleared under a common translation.
        assert!(!m.may_cross(0, 2, || 0.0));
        assert!(!m.may_cross(0, 1, || 0.0));
        assert!(!m.may_cross(0, 4, || 0.0));
        // Vertex 4 lifted and swung over face 0 (a fold of face 2 onto face 0): not cleared.
        let mut folded = before.clone();
        folded[4] = Vec3::new(0.4, 0.4, 0.01);
        let m = motion(&faces, &before, &folded);
        assert!(m.may_cross(0, 2, || 0.0));
        assert!(m.may_cross(3, 2, || 0.0));
        // A far vertex of the apart pair moving further than the gap: not cleared.
        let mut pushed = before.clone();
        pushed[6] = Vec3::new(0.2, 0.2, 0.0);
        // (the gap passed stands for the boxes' distance before, 1 here)
        assert!(motion(&faces, &before, &pushed).may_cross(0, 5, || 1.0));
        assert!(!motion(&faces, &before, &before).may_cross(0, 5, || 1.0));
    }

    #[test]
    fn a_hinge_closing_by_less_than_its_clearance_is_cleared() {
        // Two faces on the edge (0,0,0)–(1,0,0), opened flat; d rises by 0.1 (a small fold).
        let before = vec![Vec3::ZERO, Vec3::X, Vec3::new(0.5, 1.0, 0.0), Vec3::new(0.5, -1.0, 0.0)];
        let faces = [[0, 1, 2], [1, 0, 3]];
        let mut after = before.clone();
        after[3].z = 0.1;
        assert!(!motion(&faces, &before, &after).may_cross(0, 1, || 0.0));
        // Folded over onto the other face: d moves across the edge, further than its clearance.
        after[3] = Vec3::new(0.5, 0.5, 0.0);
        assert!(motion(&faces, &before, &after).may_cross(0, 1, || 0.0));
    }

    #[test]
    fn a_moved_face_reaching_past_the_moved_vertices_is_found_and_kept() {
        // A large face at z = 0 and a small one above it whose first corner is pushed through it:
        // the moved face's other corners lie well outside the moved vertex's box.
        let before = vec![
            Vec3::ZERO,
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(0.0, 10.0, 0.0),
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(2.0, 1.0, 1.0),
            Vec3::new(1.0, 2.0, 1.0),
        ];
        let faces = [[0, 1, 2], [3, 4, 5]];
        let mut after = before.clone();
        after[3].z = -1.0;
        let moved = [false, false, false, true, false, false];
        for reach in [Reach::Full, Reach::Scaled] {
            assert_eq!(
                pairs_to_test(&faces, &before, &after, &moved, reach, None, &mut KnownPatches::default()),
                vec![(0, 1)],
                "{reach:?}"
            );
        }
        // With a repeated corner the moved face has no area and crosses nothing.
        let collapsed = [[0, 1, 2], [3, 3, 5]];
        after[3].z = -1.0;
        assert_eq!(
            pairs_to_test(&collapsed, &before, &after, &moved, Reach::Scaled, None, &mut KnownPatches::default()),
            vec![]
        );
        // A sort made beforehand around where the moved vertex was (say, before a rim rose) does
        // not hold where it went: it is not used, and the pair is still found.
        let stale = sort_faces(&faces, &before, &moved, Aabb { min: Vec3::splat(0.9), max: Vec3::splat(2.1) });
        assert_eq!((&stale.marked[..], &stale.maybe[..]), (&[1][..], &[][..]), "face 0 lies outside");
        assert_eq!(
            pairs_to_test(&faces, &before, &after, &moved, Reach::Full, Some(stale), &mut KnownPatches::default()),
            vec![(0, 1)]
        );
        // Pushed only halfway down to the large face: cleared by the gap.
        after[3].z = 0.6;
        assert_eq!(
            pairs_to_test(&faces, &before, &after, &moved, Reach::Scaled, None, &mut KnownPatches::default()),
            vec![]
        );
    }

    /// Two parallel sheets 0.1 apart, the upper one's middle pushed down through the lower one
    /// by a smooth bump; second, the lower one's pushed up as much; third, the upper one
    /// dented a little and the lower one raised in a wider bump through the upper one's dent
    /// and the ring around it. The moved faces of each sheet form a certified height field
    /// (with their ring of unmoved faces), so their pairs are skipped, and every crossing is
    /// found between them and the other sheet's faces.
    #[test]
    fn certified_patches_pushed_through_a_sheet_or_each_other_are_caught() {
        use crate::mesh::face_sort::MARK_B;
        use crate::mesh::self_intersect::{crossing_pairs_among, faces_cross};
        use crate::mesh::test_support::sheet;
        // (upper bump depth and squared radius, lower bump height and squared radius)
        for (down, upper_r2, up, lower_r2) in [(0.3, 0.09, 0.0, 1.0), (0.3, 0.09, 0.3, 0.09), (0.05, 0.04, 0.3, 0.2)] {
            let (upper, mut faces) = sheet(12, |_, _| 0.0);
            let (lower, lower_faces) = sheet(12, |_, _| -0.1);
            let (offset, upper_faces) = (upper.len() as u32, faces.len());
            faces.extend(lower_faces.iter().map(|f| f.map(|v| v + offset)));
            let before: Vec<Vec3> = upper.iter().chain(&lower).copied().collect();
            let bump = |p: Vec3, r2: f32| (1.0 - ((p.x - 0.5).powi(2) + (p.z - 0.5).powi(2)) / r2).max(0.0).powi(2);
            let after: Vec<Vec3> = before
                .iter()
                .enumerate()
                .map(|(v, &p)| match v < upper.len() {
                    true => p - Vec3::Y * down * bump(p, upper_r2),
                    false => p + Vec3::Y * up * bump(p, lower_r2),
                })
                .collect();
            let moved: Vec<bool> = before.iter().zip(&after).map(|(b, a)| b != a).collect();
            let active: Vec<u32> =
                (0..faces.len() as u32).filter(|&f| faces[f as usize].iter().any(|&v| moved[v as usize])).collect();
            let unmoved: Vec<u32> = (0..faces.len() as u32).filter(|f| !active.contains(f)).collect();
            let PatchLabels { moved: labels, ring, .. } = certified_patches(&after, &faces, &active, &unmoved);
            assert!(labels.iter().all(|&l| l != UNCERTIFIED), "the height-field path is taken");
            assert!(ring.iter().filter(|&&l| l != UNCERTIFIED).count() >= 40, "with the rings");
            let pairs = pairs_to_test(&faces, &before, &after, &moved, Reach::Full, None, &mut KnownPatches::default());
            let crossing: Vec<(u32, u32)> =
                pairs.iter().copied().filter(|&(f, g)| faces_cross(&after, &faces, f, g)).collect();
            assert!(crossing.iter().all(|&(f, g)| (f as usize) < upper_faces && g as usize >= upper_faces));
            // Every crossing pair is among those listed (the all-pairs check agrees).
            let every = crossing_pairs_among(&after, &faces, &active);
            assert!(!every.is_empty() && every.iter().all(|&(f, g)| crossing.contains(&(f.min(g), f.max(g)))));
            // A presort whose marks take in more than moved (a rim-like ring of unmoved upper
            // vertices, as the volume stage marks them) is accepted and lists the same crossings.
            let region = Aabb::of(before.iter().chain(&after).map(|&p| p * 1.01));
            let codes: Vec<u8> = before
                .iter()
                .enumerate()
                .map(|(v, &p)| {
                    let rim = v < upper.len() && bump(p, upper_r2 * 1.5) > 0.0;
                    out_code(p, &region)
                        | if moved[v] {
                            MARK_A
                        } else if rim {
                            MARK_B
                        } else {
                            0
                        }
                })
                .collect();
            let sort = FaceSort::new(&faces, &codes, Some(region));
            assert!(sort.marked.len() > active.len());
            let presorted =
                pairs_to_test(&faces, &before, &after, &moved, Reach::Full, Some(sort), &mut KnownPatches::default());
            let mut found: Vec<(u32, u32)> =
                presorted.into_iter().filter(|&(f, g)| faces_cross(&after, &faces, f, g)).collect();
            let mut expected = crossing.clone();
            found.sort_unstable();
            expected.sort_unstable();
            assert_eq!(found, expected);
        }
    }
}
