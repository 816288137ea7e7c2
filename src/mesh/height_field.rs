//! Height-field certificates: a cheap proof that no two faces of a patch cross, for the patch
//! a dent leaves (a crater and its rim on a surface seen from one side), in place of testing
//! its pairs one by one.
//!
//! Project the patch along the coordinate axis `e` nearest its summed area normal (dropping a
//! coordinate, so the projected corners are f32 inputs; the signs below are trusted by
//! Shewchuk's static bound, which holds for any f64 operands, the f64 centroid included, and
//! an uncertain sign refuses the patch). The patch is certified when
//!
//! 1. every face projects wound counter-clockwise seen from `+e`, and
//! 2. its boundary (the edges its faces do not pair off, counted with direction: a chain that
//!    needs no manifold mesh) is closed loops of single edges through distinct vertices (one
//!    edge leaving each vertex), each a simple polygon: one outer loop wound counter-clockwise,
//!    and any number of holes wound clockwise.
//!
//! A loop is shown simple either because every edge is wound the same way about the loop's
//! vertex centroid, going around it once (a polygon star-shaped about it), or because no two
//! of its edges meet but neighbours at their common end (tested with a sweep over the edges;
//! an uncertain sign counts as meeting); its winding is then the sign of the turn at its
//! lowest vertex. By 2 the outer loop winds once about the points inside it and never about
//! those outside; each hole winds −1 about the points inside it and 0 about the others. For a
//! point `y` off the projected edges, the faces whose projections hold `y` (each counted +1,
//! by condition 1) number the boundary's winding about `y` (the boundary of a sum of faces
//! winds about `y` as often as they cover it): the outer loop's 0 or 1 plus the holes' 0 or −1
//! each, so at most one. So the projected faces have disjoint interiors. Each face projects
//! one-to-one, its relative interior onto its projection's interior; two faces that cross
//! (their relative interiors share a point, or they overlap in an area) would have projections
//! whose interiors overlap. So two faces of a certified patch meet only where their boundaries
//! do: they touch and do not cross, which is what [`triangles_cross`] decides too.
//!
//! A patch that fails as a whole (a dent through a thin wall moves both of its sides, joined
//! around its edge; a crumpled surface faces many ways) is split and its parts tried apart:
//! the faces wound counter-clockwise along its axis, taken by connected patches and tried along
//! that axis; and the others, split the same way along their own axis, down to
//! [`MAX_SPLIT_DEPTH`]. Each part is certified by the same two conditions, so each part's
//! promise holds for it alone: pairs between parts are still the caller's to test.
//!
//! [`triangles_cross`]: super::tri_tri::triangles_cross

use glam::{DVec3, Vec3};

use super::local_vertices::LocalVertices;
use super::tri_tri::orient2d;

const NONE: u32 = u32::MAX;

/// Connected patches (faces joined through a shared vertex) with fewer faces are not tried.
const MIN_PATCH_FACES: usize = 16;
/// At most this many patches are tried, the largest first.
const MAX_PATCHES: usize = 8;
/// How many times a patch that fails is split in two along its axis (module documentation).
const MAX_SPLIT_DEPTH: u32 = 2;
/// How many times the faces around a failing boundary are left out of a part and the rest
/// tried again.
const MAX_PEELS: u32 = 3;
/// At most this many certified patches, parts of split ones included.
const MAX_LABELS: u32 = 64;

/// Certified patches: a label per face, and the patches themselves.
#[derive(Debug, Default)]
pub(crate) struct PatchLabels {
    /// Per face of the candidates, its patch's number or [`UNCERTIFIED`].
    pub(crate) moved: Vec<u32>,
    /// Per face of `around`, the number of the patch it was certified with, or [`UNCERTIFIED`].
    pub(crate) ring: Vec<u32>,
    /// Each certified patch, by number.
    pub(crate) parts: Vec<CertifiedPart>,
}

impl PatchLabels {
    /// No patch yet, for `candidates` and `around` faces: every label [`UNCERTIFIED`].
    fn none(candidates: usize, around: usize) -> Self {
        Self { moved: vec![UNCERTIFIED; candidates], ring: vec![UNCERTIFIED; around], parts: Vec::new() }
    }
}

/// A certified patch: its faces and the coordinate plane it was certified a height field over.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct CertifiedPart {
    pub(crate) faces: Vec<u32>,
    /// The projection's two coordinates, in the order that makes counter-clockwise the side
    /// the patch faces.
    plane: [usize; 2],
}

/// Labels for the faces `candidates` and `around` (faces of `faces` at `positions`): the
/// candidates' connected patches (faces joined through a shared vertex) that are certified
/// (module documentation) are numbered, 0 for the largest, counting up as the patches shrink,
/// and their faces get that number; the others [`UNCERTIFIED`]. Only the [`MAX_PATCHES`]
/// largest patches of at least [`MIN_PATCH_FACES`] faces are tried. Each is tried first
/// together with its ring, the faces of `around` that share a vertex with it (then those get
/// its number too: no pair of the patch and its ring crosses either), then alone, then split
/// (module documentation; each certified part numbered after the whole patches).
pub(crate) fn certified_patches(
    positions: &[Vec3],
    faces: &[[u32; 3]],
    candidates: &[u32],
    around: &[u32],
) -> PatchLabels {
    let mut local = LocalVertices::new(positions.len());
    local.add_corners(faces, candidates);
    let vertex_roots = patch_roots(local.len(), |v| local.of(v), faces, candidates);
    let root_of = |f: u32| vertex_roots[local.of(faces[f as usize][0])];
    let roots: Vec<u32> = candidates.iter().map(|&f| root_of(f)).collect();
    // The patch each face of `around` touches first, if any.
    let ring_roots: Vec<u32> = around
        .iter()
        .map(|&f| {
            let touching = faces[f as usize].into_iter().find_map(|v| local.get(v));
            touching.map_or(NONE, |k| vertex_roots[k])
        })
        .collect();
    let mut sizes = vec![0usize; vertex_roots.len()];
    roots.iter().for_each(|&r| sizes[r as usize] += 1);
    let mut tried: Vec<u32> = (0..sizes.len() as u32).filter(|&r| sizes[r as usize] >= MIN_PATCH_FACES).collect();
    tried.sort_unstable_by_key(|&r| std::cmp::Reverse(sizes[r as usize]));
    tried.truncate(MAX_PATCHES);
    let mut labels = PatchLabels::none(candidates.len(), around.len());
    let mut next_label = 0;
    // Numbers the corners of one patch or part at a time.
    let mut scratch = LocalVertices::new(positions.len());
    let mut failed = Vec::new();
    for root in tried {
        let members: Vec<usize> = (0..candidates.len()).filter(|&k| roots[k] == root).collect();
        let ring_members: Vec<usize> = (0..around.len()).filter(|&k| ring_roots[k] == root).collect();
        let patch: Vec<u32> = members.iter().map(|&k| candidates[k]).collect();
        let with_ring: Vec<u32> = patch.iter().copied().chain(ring_members.iter().map(|&k| around[k])).collect();
        let mut embedded = |faces_of: &[u32]| {
            let projection = Projection::of(positions, faces, faces_of)?;
            (projection.check(faces_of, &mut scratch) == Check::Embedded).then_some(projection.plane())
        };
        let ring_plane = if ring_members.is_empty() { None } else { embedded(&with_ring) };
        let ring_too = ring_plane.is_some();
        if let Some(plane) = ring_plane.or_else(|| embedded(&patch)) {
            members.iter().for_each(|&k| labels.moved[k] = next_label);
            if ring_too {
                ring_members.iter().for_each(|&k| labels.ring[k] = next_label);
            }
            labels.parts.push(CertifiedPart { faces: if ring_too { with_ring } else { patch }, plane });
            next_label += 1;
        } else {
            failed.push(members);
        }
    }
    // The parts of the patches that failed, numbered after the whole ones.
    if failed.is_empty() {
        return labels;
    }
    let mut index_of = vec![NONE; faces.len()];
    candidates.iter().zip(0..).for_each(|(&f, k)| index_of[f as usize] = k);
    for members in failed {
        let patch: Vec<u32> = members.iter().map(|&k| candidates[k]).collect();
        for part in certified_parts(positions, faces, &patch, MAX_SPLIT_DEPTH, &mut scratch) {
            if next_label == MAX_LABELS {
                return labels;
            }
            part.faces.iter().for_each(|&f| labels.moved[index_of[f as usize] as usize] = next_label);
            labels.parts.push(part);
            next_label += 1;
        }
    }
    labels
}

/// Labels for the faces `candidates` and `around`, as [`certified_patches`] gives them, from
/// the patches `known` (certified by an earlier call for other positions of the same faces):
/// each is checked again at `positions`, alone and over its own plane, and those still
/// certified are numbered in turn (their faces among `candidates` and `around` get the
/// number). No new patch is searched for.
pub(crate) fn certified_again(
    positions: &[Vec3],
    faces: &[[u32; 3]],
    candidates: &[u32],
    around: &[u32],
    known: &[CertifiedPart],
) -> PatchLabels {
    let mut labels = PatchLabels::none(candidates.len(), around.len());
    // Where each face sits: in `candidates` (k) or in `around` (candidates.len() + k).
    let mut place = vec![NONE; faces.len()];
    candidates.iter().chain(around).zip(0..).for_each(|(&f, k)| place[f as usize] = k);
    let mut scratch = LocalVertices::new(positions.len());
    for part in known {
        let projection = Projection::along(positions, faces, part.plane);
        if projection.check(&part.faces, &mut scratch) != Check::Embedded {
            continue;
        }
        let label = labels.parts.len() as u32;
        for &f in &part.faces {
            let k = place[f as usize];
            if k == NONE {
                continue;
            }
            match (k as usize).checked_sub(candidates.len()) {
                None => labels.moved[k as usize] = label,
                Some(r) => labels.ring[r] = label,
            }
        }
        labels.parts.push(part.clone());
    }
    labels
}

/// The certified parts of `patch`, a patch that failed as a whole: its faces wound
/// counter-clockwise along its axis, by connected patches, tried along that axis; the others
/// split again along their own axis, `depth` more times.
fn certified_parts(
    positions: &[Vec3],
    faces: &[[u32; 3]],
    patch: &[u32],
    depth: u32,
    scratch: &mut LocalVertices,
) -> Vec<CertifiedPart> {
    let Some(projection) = Projection::of(positions, faces, patch) else {
        return Vec::new();
    };
    let (wound, others): (Vec<u32>, Vec<u32>) = patch.iter().partition(|&&f| projection.wound(f));
    let mut parts = Vec::new();
    if !others.is_empty() {
        for part in connected_parts(faces, &wound, scratch) {
            parts.extend(peeled_until_certified(&projection, faces, part, MAX_PEELS, scratch));
        }
    }
    if depth > 0 && others.len() >= MIN_PATCH_FACES {
        for part in connected_parts(faces, &others, scratch) {
            match Projection::of(positions, faces, &part) {
                Some(own) if own.check(&part, scratch) == Check::Embedded => {
                    parts.push(CertifiedPart { faces: part, plane: own.plane() })
                }
                _ => parts.extend(certified_parts(positions, faces, &part, depth - 1, scratch)),
            }
        }
    }
    parts
}

/// The certified parts of `part` (faces all wound counter-clockwise in `projection`): the part
/// itself if it is certified; otherwise, where its boundary fails (it touches itself at a
/// vertex, or a loop of it is not a simple polygon of the right winding: a fold at its edge or
/// around a hole), the faces with a corner there are left out and what is left tried again,
/// `peels` more times.
fn peeled_until_certified(
    projection: &Projection,
    faces: &[[u32; 3]],
    part: Vec<u32>,
    peels: u32,
    scratch: &mut LocalVertices,
) -> Vec<CertifiedPart> {
    match projection.check(&part, scratch) {
        Check::Embedded => vec![CertifiedPart { faces: part, plane: projection.plane() }],
        Check::Boundary(mut failing) if peels > 0 => {
            failing.sort_unstable();
            let touches = |f: &u32| faces[*f as usize].iter().any(|v| failing.binary_search(v).is_ok());
            let rest: Vec<u32> = part.into_iter().filter(|f| !touches(f)).collect();
            let mut certified = Vec::new();
            for p in connected_parts(faces, &rest, scratch) {
                certified.extend(peeled_until_certified(projection, faces, p, peels - 1, scratch));
            }
            certified
        }
        _ => Vec::new(),
    }
}

/// The connected patches of `chosen` with at least [`MIN_PATCH_FACES`] faces (`scratch`
/// numbers their corners on the way, and is left cleared).
fn connected_parts(faces: &[[u32; 3]], chosen: &[u32], scratch: &mut LocalVertices) -> Vec<Vec<u32>> {
    scratch.add_corners(faces, chosen);
    let corners = &*scratch;
    let roots = patch_roots(corners.len(), |v| corners.of(v), faces, chosen);
    // Faces by root, each patch's in the order chosen.
    let mut by_root: Vec<(u32, u32)> =
        chosen.iter().zip(0..).map(|(&f, k)| (roots[corners.of(faces[f as usize][0])], k)).collect();
    scratch.clear();
    by_root.sort_unstable();
    let mut parts: Vec<Vec<u32>> = by_root
        .chunk_by(|a, b| a.0 == b.0)
        .filter(|run| run.len() >= MIN_PATCH_FACES)
        .map(|run| run.iter().map(|&(_, k)| chosen[k as usize]).collect())
        .collect();
    parts.sort_unstable_by_key(|p| (std::cmp::Reverse(p.len()), p[0]));
    parts
}

/// The label of a face in no certified patch.
pub(crate) const UNCERTIFIED: u32 = u32::MAX;

/// For each numbered vertex, one that stands for its connected patch among the faces
/// `chosen` (whose corners are all numbered).
fn patch_roots(count: usize, number: impl Fn(u32) -> usize, faces: &[[u32; 3]], chosen: &[u32]) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..count as u32).collect();
    fn root(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            let up = parent[parent[x as usize] as usize];
            parent[x as usize] = up;
            x = up;
        }
        x
    }
    for &f in chosen {
        let [a, b, c] = faces[f as usize].map(|v| number(v) as u32);
        for other in [b, c] {
            let (ra, ro) = (root(&mut parent, a), root(&mut parent, other));
            parent[ra.max(ro) as usize] = ra.min(ro);
        }
    }
    (0..parent.len() as u32).map(|x| root(&mut parent, x)).collect()
}

/// What [`Projection::check`] finds.
#[derive(Debug, PartialEq)]
enum Check {
    /// Conditions 1 and 2 hold.
    Embedded,
    /// Condition 2 fails at these boundary vertices (where two boundary edges leave a vertex,
    /// or on loops that are not simple polygons of the right winding).
    Boundary(Vec<u32>),
    /// Condition 1 fails, or the boundary is not a chain of single edges.
    Refused,
}

/// A patch's projection along the coordinate axis nearest its summed area normal, with the two
/// coordinates kept ordered so that counter-clockwise means facing the patch's side.
struct Projection<'a> {
    positions: &'a [Vec3],
    faces: &'a [[u32; 3]],
    u: usize,
    v: usize,
}

impl<'a> Projection<'a> {
    /// The projection of the faces `patch`; `None` when their summed normal has no component
    /// on any axis.
    fn of(positions: &'a [Vec3], faces: &'a [[u32; 3]], patch: &[u32]) -> Option<Self> {
        let normal: DVec3 = patch
            .iter()
            .map(|&f| {
                let [a, b, c] = faces[f as usize].map(|v| positions[v as usize].as_dvec3());
                (b - a).cross(c - a)
            })
            .sum();
        let axis = normal.abs().max_position();
        if normal[axis] == 0.0 {
            return None;
        }
        // The two other coordinates, in the order that makes (u, v, e) right-handed, swapped
        // when the patch faces −e.
        let (mut u, mut v) = ((axis + 1) % 3, (axis + 2) % 3);
        if normal[axis] < 0.0 {
            std::mem::swap(&mut u, &mut v);
        }
        Some(Self { positions, faces, u, v })
    }

    /// The projection onto `plane` (as [`plane`](Self::plane) gives it).
    fn along(positions: &'a [Vec3], faces: &'a [[u32; 3]], plane: [usize; 2]) -> Self {
        Self { positions, faces, u: plane[0], v: plane[1] }
    }

    /// The two coordinates kept, in order.
    fn plane(&self) -> [usize; 2] {
        [self.u, self.v]
    }

    fn flat(&self, x: u32) -> [f64; 2] {
        let p = self.positions[x as usize];
        [f64::from(p[self.u]), f64::from(p[self.v])]
    }

    /// Whether face `f` projects wound counter-clockwise (condition 1).
    fn wound(&self, f: u32) -> bool {
        let [a, b, c] = self.faces[f as usize].map(|x| self.flat(x));
        orient2d(a, b, c) > 0
    }

    /// Whether the faces `patch` are certified embedded in this projection (conditions 1 and 2
    /// of the module documentation), and if not, where (`scratch` numbers their corners on
    /// the way, and is left cleared).
    fn check(&self, patch: &[u32], scratch: &mut LocalVertices) -> Check {
        if !patch.iter().all(|&f| self.wound(f)) {
            return Check::Refused;
        }
        scratch.add_corners(self.faces, patch);
        let found = self.check_boundary(patch, scratch);
        scratch.clear();
        found
    }

    /// Condition 2 for the faces `patch`, wound counter-clockwise, whose corners `corners`
    /// numbers.
    fn check_boundary(&self, patch: &[u32], corners: &LocalVertices) -> Check {
        let Some(boundary) = boundary_edges(self.faces, patch, corners) else {
            return Check::Refused;
        };
        let loops = match closed_loops(&boundary, corners) {
            Ok(loops) => loops,
            Err(pinches) => return Check::Boundary(pinches),
        };
        let mut outer = Vec::new();
        let mut failing = Vec::new();
        for walk in &loops {
            match self.star_turns(walk).or_else(|| self.simple_turns(walk)) {
                Some(1) => outer.push(walk),
                Some(-1) => {}
                _ => failing.extend_from_slice(walk),
            }
        }
        match (failing.is_empty(), outer.len()) {
            (true, 1) => Check::Embedded,
            (true, 0) => Check::Refused,
            // More than one outer loop: all but the longest are folds to peel.
            (true, _) => {
                outer.sort_unstable_by_key(|walk| std::cmp::Reverse(walk.len()));
                Check::Boundary(outer[1..].iter().flat_map(|walk| walk.iter().copied()).collect())
            }
            (false, _) => Check::Boundary(failing),
        }
    }

    /// For a loop through the vertices `walk` (in order, closing back to the first): `1` when
    /// every edge is wound counter-clockwise about the vertex centroid and the loop goes around
    /// it once, `-1` for clockwise and once, `None` otherwise.
    fn star_turns(&self, walk: &[u32]) -> Option<i8> {
        let centre = walk.iter().map(|&x| self.flat(x)).fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]]);
        let centre = centre.map(|s| s / walk.len() as f64);
        let edges = walk.iter().zip(walk.iter().cycle().skip(1));
        let (mut turned, mut sign) = (0.0, 0);
        for (&a, &b) in edges {
            let (pa, pb) = (self.flat(a), self.flat(b));
            let here = orient2d(centre, pa, pb).signum();
            if here == 0 || (sign != 0 && here != sign) {
                return None;
            }
            sign = here;
            let (ra, rb) = ([pa[0] - centre[0], pa[1] - centre[1]], [pb[0] - centre[0], pb[1] - centre[1]]);
            turned += (ra[0] * rb[1] - ra[1] * rb[0]).atan2(ra[0] * rb[0] + ra[1] * rb[1]);
        }
        // Each edge turns by an angle in (0, π) of one sign, so the total is a whole number of
        // turns.
        ((turned - f64::from(sign) * std::f64::consts::TAU).abs() < std::f64::consts::PI).then_some(sign)
    }

    /// For a loop through the distinct vertices `walk` (in order, closing back to the first):
    /// its winding, `1` counter-clockwise or `-1` clockwise, when it is a simple polygon (no two
    /// edges meet but neighbours at their common end, where they do not fold back); `None`
    /// otherwise, or when a sign it needs is uncertain.
    fn simple_turns(&self, walk: &[u32]) -> Option<i8> {
        let n = walk.len();
        let points: Vec<[f64; 2]> = walk.iter().map(|&x| self.flat(x)).collect();
        let edge = |i: usize| (points[i], points[(i + 1) % n]);
        // Neighbours meet only at their common end: a straight run goes on forward.
        for i in 0..n {
            let (a, b, c) = (points[i], points[(i + 1) % n], points[(i + 2) % n]);
            let forward = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]) > 0.0;
            if orient2d(a, b, c) == 0 && !forward {
                return None;
            }
        }
        // Other pairs: a sweep along u over the edges' spans.
        let span = |i: usize| {
            let (a, b) = edge(i);
            (a[0].min(b[0]), a[0].max(b[0]), a[1].min(b[1]), a[1].max(b[1]))
        };
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_unstable_by(|&i, &j| span(i).0.total_cmp(&span(j).0));
        let mut open: Vec<usize> = Vec::new();
        for &i in &order {
            let (low, _, bottom, top) = span(i);
            open.retain(|&j| span(j).1 >= low);
            let (a, b) = edge(i);
            for &j in &open {
                let neighbours = (i + 1) % n == j || (j + 1) % n == i;
                let (_, _, jb, jt) = span(j);
                if neighbours || jt < bottom || jb > top {
                    continue;
                }
                let (c, d) = edge(j);
                let apart = orient2d(a, b, c) * orient2d(a, b, d) > 0 || orient2d(c, d, a) * orient2d(c, d, b) > 0;
                if !apart {
                    return None;
                }
            }
            open.push(i);
        }
        // The turn at the lowest vertex (least u, then v) has the polygon's winding.
        let lowest = (0..n)
            .min_by(|&i, &j| points[i][0].total_cmp(&points[j][0]).then(points[i][1].total_cmp(&points[j][1])))?;
        let turn = orient2d(points[(lowest + n - 1) % n], points[lowest], points[(lowest + 1) % n]);
        (turn != 0).then_some(turn)
    }
}

/// The patch's boundary chain as directed edges, each once; `None` when an edge is left over
/// more than once in one direction (the chain is not a set of single edges).
fn boundary_edges(faces: &[[u32; 3]], patch: &[u32], corners: &LocalVertices) -> Option<Vec<(u32, u32)>> {
    // Every directed edge filed under its smaller end (compressed rows), with +1 when it runs
    // from the smaller end and −1 otherwise.
    let mut starts = vec![0u32; corners.len() + 1];
    let edges = |f: u32| {
        let [a, b, c] = faces[f as usize];
        [(a, b), (b, c), (c, a)]
    };
    for &f in patch {
        for (a, b) in edges(f) {
            starts[corners.of(a.min(b)) + 1] += 1;
        }
    }
    for k in 0..corners.len() {
        starts[k + 1] += starts[k];
    }
    let mut fill = starts.clone();
    let mut filed = vec![(0u32, 0i32); 3 * patch.len()];
    for &f in patch {
        for (a, b) in edges(f) {
            let row = corners.of(a.min(b));
            filed[fill[row] as usize] = (a.max(b), if a < b { 1 } else { -1 });
            fill[row] += 1;
        }
    }
    let mut boundary = Vec::new();
    for (row, &low) in corners.vertices.iter().enumerate() {
        let edges = &mut filed[starts[row] as usize..starts[row + 1] as usize];
        edges.sort_unstable_by_key(|e| e.0);
        for run in edges.chunk_by(|x, y| x.0 == y.0) {
            let high = run[0].0;
            match run.iter().map(|e| e.1).sum::<i32>() {
                0 => {}
                1 => boundary.push((low, high)),
                -1 => boundary.push((high, low)),
                _ => return None,
            }
        }
    }
    Some(boundary)
}

/// `edges` as closed loops through distinct vertices, each as its vertices in order; otherwise
/// the vertices that more than one edge leaves (empty when the edges do not close up).
fn closed_loops(edges: &[(u32, u32)], corners: &LocalVertices) -> Result<Vec<Vec<u32>>, Vec<u32>> {
    let mut next = vec![NONE; corners.len()];
    let mut pinches = Vec::new();
    for &(a, b) in edges {
        let slot = &mut next[corners.of(a)];
        if *slot != NONE {
            pinches.push(a);
        }
        *slot = b;
    }
    if !pinches.is_empty() {
        return Err(pinches);
    }
    let mut walked = vec![false; corners.len()];
    let mut loops = Vec::new();
    for &(start, _) in edges {
        if walked[corners.of(start)] {
            continue;
        }
        let mut walk = Vec::new();
        let mut at = start;
        loop {
            let k = corners.of(at);
            if walked[k] {
                return Err(Vec::new());
            }
            walked[k] = true;
            walk.push(at);
            at = next[k];
            if at == NONE || corners.get(at).is_none() {
                return Err(Vec::new());
            }
            if at == start {
                break;
            }
        }
        if walk.len() < 3 {
            return Err(Vec::new());
        }
        loops.push(walk);
    }
    Ok(loops)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::test_support::sheet;
    use crate::mesh::tri_tri::triangles_cross;

    fn all(faces: &[[u32; 3]]) -> Vec<u32> {
        (0..faces.len() as u32).collect()
    }

    /// Whether each of `chosen` lies in a certified patch.
    fn certified_patch(positions: &[Vec3], faces: &[[u32; 3]], chosen: &[u32]) -> Vec<bool> {
        certified_patches(positions, faces, chosen, &[]).moved.into_iter().map(|l| l != UNCERTIFIED).collect()
    }

    #[test]
    fn a_dented_sheet_is_certified_and_has_no_crossing_pair() {
        let (positions, faces) = sheet(12, |x, z| 0.3 * (-((x - 0.5).powi(2) + (z - 0.4).powi(2)) * 20.0).exp());
        assert!(faces.iter().all(|f| {
            let [a, b, c] = f.map(|v| positions[v as usize]);
            (b - a).cross(c - a).y > 0.0
        }));
        assert!(certified_patch(&positions, &faces, &all(&faces)).iter().all(|&f| f));
        // Upside down (facing −y) it is certified just the same.
        let flipped: Vec<[u32; 3]> = faces.iter().map(|&[a, b, c]| [a, c, b]).collect();
        assert!(certified_patch(&positions, &flipped, &all(&flipped)).iter().all(|&f| f));
    }

    #[test]
    fn a_fold_is_refused_whole_and_its_parts_do_not_cross() {
        // A vertex pushed across its neighbours: faces turn over, and some cross.
        let (mut positions, faces) = sheet(6, |_, _| 0.0);
        positions[3 * 7 + 3].x += 0.4;
        let corners = |f: usize| faces[f].map(|v| positions[v as usize].as_dvec3());
        assert!((0..faces.len()).any(|f| (0..faces.len()).any(|g| triangles_cross(corners(f), corners(g)))));
        let PatchLabels { moved: labels, .. } = certified_patches(&positions, &faces, &all(&faces), &[]);
        assert!(labels.iter().any(|&l| l != 0), "not certified whole");
        for f in (0..faces.len()).filter(|&f| labels[f] != UNCERTIFIED) {
            for g in (f + 1..faces.len()).filter(|&g| labels[g] == labels[f]) {
                assert!(!triangles_cross(corners(f), corners(g)), "faces {f} and {g} of part {} cross", labels[f]);
            }
        }
    }

    /// A sheet less two middle quads: its boundary is two loops, the outer one counter-clockwise
    /// and the hole clockwise, both simple. Certified; and refused once a face beside the hole
    /// is pushed over it (its corner moved into the hole: it turns over).
    #[test]
    fn a_patch_with_a_hole_is_certified_and_refused_when_folded_into_it() {
        let (mut positions, faces) = sheet(6, |_, _| 0.0);
        let holed: Vec<u32> = (0..faces.len() as u32).filter(|&f| !(28..=31).contains(&f)).collect();
        assert!(certified_patch(&positions, &faces, &holed).iter().all(|&f| f));
        positions[2 * 7 + 2] = Vec3::new(0.55, 0.0, 0.55);
        assert!(certified_patch(&positions, &faces, &holed).iter().all(|&f| !f));
    }

    /// A sheet whose outline is an L (not star-shaped about its centroid) is certified by the
    /// simple-polygon test; a sheet folded so that its outline crosses itself is not.
    #[test]
    fn an_outline_that_is_simple_but_not_star_shaped_is_certified() {
        let (positions, faces) = sheet(8, |_, _| 0.0);
        // Quad (i, j) is faces 16i + 2j and 16i + 2j + 1: an L of the first two rows and the
        // first two columns, and a U that also takes the last two columns.
        let quads = |keep: &dyn Fn(u32, u32) -> bool| -> Vec<u32> {
            (0..8u32)
                .flat_map(|i| (0..8u32).map(move |j| (i, j)))
                .filter(|&(i, j)| keep(i, j))
                .flat_map(|(i, j)| [16 * i + 2 * j, 16 * i + 2 * j + 1])
                .collect()
        };
        let l_shape = quads(&|i, j| i < 2 || j < 2);
        assert!(certified_patch(&positions, &faces, &l_shape).iter().all(|&f| f));
        let u_shape = quads(&|i, j| i < 2 || !(2..6).contains(&j));
        assert!(certified_patch(&positions, &faces, &u_shape).iter().all(|&f| f));
    }

    /// A closed box dented through: its top, bottom and sides all move, so the patch faces
    /// every way and fails whole. Split, the top and the bottom are certified each (and the
    /// sides as their own parts), and no certified part has a crossing pair.
    #[test]
    fn a_patch_around_a_thin_wall_is_certified_in_parts() {
        let plate = crate::mesh::primitives::subdivided_box(Vec3::new(1.0, 0.1, 1.0), [12, 2, 12]).expect("box");
        let positions: Vec<Vec3> =
            plate.positions().iter().map(|&p| p - Vec3::Y * 0.05 * (-(p.x * p.x + p.z * p.z) * 8.0).exp()).collect();
        let faces = plate.faces();
        let PatchLabels { moved: labels, .. } = certified_patches(&positions, faces, &all(faces), &[]);
        let certified = labels.iter().filter(|&&l| l != UNCERTIFIED).count();
        assert!(certified * 10 >= faces.len() * 9, "{certified} of {} faces certified", faces.len());
        let top = labels
            [(0..faces.len()).find(|&f| faces[f].iter().all(|&v| plate.positions()[v as usize].y > 0.04)).unwrap()];
        let bottom = labels
            [(0..faces.len()).find(|&f| faces[f].iter().all(|&v| plate.positions()[v as usize].y < -0.04)).unwrap()];
        assert!(top != UNCERTIFIED && bottom != UNCERTIFIED && top != bottom);
        let corners = |f: usize| faces[f].map(|v| positions[v as usize].as_dvec3());
        for f in 0..faces.len() {
            for g in f + 1..faces.len() {
                if labels[f] != UNCERTIFIED && labels[f] == labels[g] {
                    assert!(!triangles_cross(corners(f), corners(g)), "faces {f} and {g} of part {} cross", labels[f]);
                }
            }
        }
    }

    /// The parts certified at one dent depth, checked again: at the same positions all of them,
    /// in order, each with its faces' labels (ring faces too); at half the depth, only parts
    /// with no crossing pair; with a vertex pushed across its neighbours, the parts holding it
    /// are refused (their faces left uncertified) and the others keep theirs.
    #[test]
    fn known_parts_are_checked_again_and_a_folded_one_is_refused() {
        let plate = crate::mesh::primitives::subdivided_box(Vec3::new(1.0, 0.1, 1.0), [12, 2, 12]).expect("box");
        let dented = |depth: f32| -> Vec<Vec3> {
            plate.positions().iter().map(|&p| p - Vec3::Y * depth * (-(p.x * p.x + p.z * p.z) * 8.0).exp()).collect()
        };
        let faces = plate.faces();
        let (candidates, around): (Vec<u32>, Vec<u32>) = (0..faces.len() as u32).partition(|f| f % 7 != 0);
        let first = certified_patches(&dented(0.05), faces, &candidates, &around);
        assert!(first.parts.len() >= 2, "{} parts", first.parts.len());
        let same = certified_again(&dented(0.05), faces, &candidates, &around, &first.parts);
        assert_eq!(same.parts, first.parts);
        let label_of = |labels: &PatchLabels, f: u32| match candidates.iter().position(|&c| c == f) {
            Some(k) => labels.moved[k],
            None => labels.ring[around.iter().position(|&a| a == f).unwrap()],
        };
        for (l, part) in same.parts.iter().enumerate() {
            assert!(part.faces.iter().all(|&f| label_of(&same, f) == l as u32), "part {l}");
        }
        let no_crossing = |positions: &[Vec3], labels: &PatchLabels| {
            let corners = |f: u32| faces[f as usize].map(|v| positions[v as usize].as_dvec3());
            labels.parts.iter().map(|part| &part.faces).all(|part| {
                part.iter()
                    .enumerate()
                    .all(|(i, &f)| part[i + 1..].iter().all(|&g| !triangles_cross(corners(f), corners(g))))
            })
        };
        let half = dented(0.025);
        assert!(no_crossing(&half, &certified_again(&half, faces, &candidates, &around, &first.parts)));
        // One top vertex pushed far across its neighbours: the parts around it fold.
        let mut folded = dented(0.05);
        let top = (0..folded.len()).filter(|&v| plate.positions()[v].y > 0.04).nth(40).unwrap();
        folded[top] += Vec3::new(0.3, 0.0, 0.3);
        let again = certified_again(&folded, faces, &candidates, &around, &first.parts);
        let holding = |part: &CertifiedPart| part.faces.iter().any(|&f| faces[f as usize].contains(&(top as u32)));
        let (broken, kept): (Vec<&CertifiedPart>, Vec<&CertifiedPart>) = first.parts.iter().partition(|p| holding(p));
        assert!(!broken.is_empty() && !kept.is_empty());
        assert!(broken.iter().flat_map(|p| p.faces.iter()).all(|&f| label_of(&again, f) == UNCERTIFIED));
        assert_eq!(again.parts, kept.into_iter().cloned().collect::<Vec<_>>());
        assert!(no_crossing(&folded, &again));
    }

    /// Soundness against the exact test: dented sheets jittered enough to fold now and then,
    /// cut to random patches; no certified patch has a crossing pair, and both verdicts occur.
    #[test]
    fn no_certified_patch_has_a_crossing_pair() {
        let mut next = crate::mesh::test_support::unit_floats(11);
        let (mut certified, mut refused) = (0, 0);
        for round in 0..1000 {
            let (mut positions, faces) = sheet(7, |x, z| 0.2 * (-((x - 0.5).powi(2) + (z - 0.5).powi(2)) * 12.0).exp());
            // Up to 1.5 grid spacings of sideways jitter, and some of height.
            let amplitude = 0.2 * next() * (round % 4) as f32 / 3.0;
            for p in positions.iter_mut() {
                *p += Vec3::new(next() - 0.5, 0.5 * (next() - 0.5), next() - 0.5) * amplitude;
            }
            // The faces whose first corner lies in a random ellipse (a ragged outline).
            let (cx, cz, rx, rz) = (0.3 + 0.4 * next(), 0.3 + 0.4 * next(), 0.15 + 0.3 * next(), 0.15 + 0.3 * next());
            let inside = |p: Vec3| ((p.x - cx) / rx).powi(2) + ((p.z - cz) / rz).powi(2) < 1.0;
            let chosen: Vec<u32> =
                (0..faces.len() as u32).filter(|&f| inside(positions[faces[f as usize][0] as usize])).collect();
            // Every certified patch or part (each one's promise is its own).
            let PatchLabels { moved: labels, .. } = certified_patches(&positions, &faces, &chosen, &[]);
            // Certified whole (one patch holds every face), or refused or split.
            if labels.iter().all(|&l| l == 0) {
                certified += 1;
            } else {
                refused += 1;
            }
            let corners = |f: u32| faces[f as usize].map(|v| positions[v as usize].as_dvec3());
            for (i, (&f, &l)) in chosen.iter().zip(&labels).enumerate().filter(|(_, (_, l))| **l != UNCERTIFIED) {
                for (&g, _) in chosen[i + 1..].iter().zip(&labels[i + 1..]).filter(|(_, m)| **m == l) {
                    assert!(!triangles_cross(corners(f), corners(g)), "round {round}: faces {f} and {g} cross");
                }
            }
        }
        assert!(certified >= 100 && refused >= 100, "certified {certified}, refused {refused}");
    }

    /// Soundness of the split and the peeling against the exact test: crumpled sheets (1 to
    /// 2.4 grid spacings of jitter, so they fold over here and there) are often certified only
    /// in parts, and no part has a crossing pair.
    #[test]
    fn no_certified_part_of_a_crumpled_sheet_has_a_crossing_pair() {
        let mut next = crate::mesh::test_support::unit_floats(23);
        let mut rounds_with_parts = 0;
        for round in 0..600 {
            let (mut positions, faces) =
                sheet(12, |x, z| 0.3 * (-((x - 0.5).powi(2) + (z - 0.5).powi(2)) * 10.0).exp());
            let amplitude = 0.08 + 0.12 * next();
            for p in positions.iter_mut() {
                *p += Vec3::new(next() - 0.5, 0.6 * (next() - 0.5), next() - 0.5) * amplitude;
            }
            let PatchLabels { moved: labels, .. } = certified_patches(&positions, &faces, &all(&faces), &[]);
            let parts: std::collections::HashSet<u32> = labels.iter().copied().filter(|&l| l != UNCERTIFIED).collect();
            rounds_with_parts += usize::from(parts.len() > 1 || labels.contains(&UNCERTIFIED) && !parts.is_empty());
            let corners = |f: usize| faces[f].map(|v| positions[v as usize].as_dvec3());
            for f in (0..faces.len()).filter(|&f| labels[f] != UNCERTIFIED) {
                for g in (f + 1..faces.len()).filter(|&g| labels[g] == labels[f]) {
                    assert!(!triangles_cross(corners(f), corners(g)), "round {round}: faces {f} and {g} cross");
                }
            }
        }
        assert!(rounds_with_parts >= 80, "only {rounds_with_parts} rounds certified in parts");
    }

    #[test]
    fn a_sheet_folded_over_itself_is_certified_only_in_parts_apart() {
        // A strip whose far half is folded back over its near half (upside down, so it faces
        // −y there): the fold's faces are wound clockwise. The whole is refused; split, the
        // flat half and the folded half may each be certified, but never in one part.
        let (mut positions, faces) = sheet(8, |_, _| 0.0);
        let folded: Vec<bool> = faces.iter().map(|f| f.iter().any(|&v| positions[v as usize].x > 0.5)).collect();
        for p in positions.iter_mut().filter(|p| p.x > 0.5) {
            *p = Vec3::new(1.0 - p.x, 0.2, p.z);
        }
        let PatchLabels { moved: labels, .. } = certified_patches(&positions, &faces, &all(&faces), &[]);
        assert!(labels.contains(&UNCERTIFIED) || labels.iter().any(|&l| l != labels[0]), "not one patch");
        for (f, &l) in labels.iter().enumerate().filter(|(_, l)| **l != UNCERTIFIED) {
            for (g, _) in labels.iter().enumerate().filter(|(_, m)| **m == l) {
                assert_eq!(folded[f], folded[g], "faces {f} and {g} of part {l}: one folded, one not");
            }
        }
    }

    /// A ramp that climbs around two turns: every face is wound counter-clockwise seen from
    /// above, but its projection covers the plane twice. It does not cross itself in space, yet
    /// the certificate must refuse it: its proof would not hold. (Its boundary turns clockwise
    /// about the centre along the inner edge; the fan below is the case the turn count alone
    /// refuses.)
    #[test]
    fn a_sheet_wound_twice_is_refused() {
        // An annulus of `k` sectors over two turns, rising with the angle.
        let k = 48;
        let mut positions = Vec::new();
        for i in 0..=k {
            let t = i as f32 / k as f32 * std::f32::consts::TAU * 2.0;
            for r in [1.0f32, 2.0] {
                positions.push(Vec3::new(r * t.cos(), 0.1 * t, r * -t.sin()));
            }
        }
        let mut faces = Vec::new();
        for i in 0..k as u32 {
            let (a, b, c, d) = (2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3);
            faces.push([a, b, c]);
            faces.push([b, d, c]);
        }
        let upward = |f: &[u32; 3]| {
            let [a, b, c] = f.map(|v| positions[v as usize]);
            (b - a).cross(c - a).y > 0.0
        };
        assert!(faces.iter().all(upward), "the spiral's faces all face +y");
        assert!(certified_patch(&positions, &faces, &all(&faces)).iter().all(|&f| !f));
    }

    /// A fan of 17 faces around a raised centre, each spanning two 17ths of a turn (a star
    /// polygon's points in turn): every face is wound counter-clockwise and the boundary is one
    /// loop turning counter-clockwise at every edge, but it goes around twice. Faces a turn
    /// apart cross; the certificate must refuse it.
    #[test]
    fn a_fan_that_winds_twice_is_refused() {
        let mut positions = vec![Vec3::Y];
        for k in 0..17 {
            let t = (2 * k) as f32 * std::f32::consts::TAU / 17.0;
            positions.push(Vec3::new(t.cos(), (k % 2) as f32, -t.sin()));
        }
        let faces: Vec<[u32; 3]> = (0..17).map(|k| [0, 1 + k, 1 + (k + 1) % 17]).collect();
        let corners = |f: usize| faces[f].map(|v| positions[v as usize].as_dvec3());
        assert!((0..17).any(|f| (0..17).any(|g| triangles_cross(corners(f), corners(g)))));
        assert!(certified_patch(&positions, &faces, &all(&faces)).iter().all(|&f| !f));
    }

    /// A dented middle of a sheet is certified with the flat faces around it; with one of those
    /// turned over it is certified alone.
    #[test]
    fn a_patch_takes_its_ring_when_the_ring_is_certified_too() {
        let (mut positions, faces) =
            sheet(8, |x, z| 0.2 * (1.0 - ((x - 0.5).powi(2) + (z - 0.5).powi(2)) / 0.04).max(0.0));
        let raised = |f: &[u32; 3]| f.iter().any(|&v| positions[v as usize].y > 0.0);
        let patch: Vec<u32> = (0..faces.len() as u32).filter(|&f| raised(&faces[f as usize])).collect();
        let others: Vec<u32> = (0..faces.len() as u32).filter(|f| !patch.contains(f)).collect();
        let touches = |f: u32| faces[f as usize].iter().any(|v| patch.iter().any(|&g| faces[g as usize].contains(v)));
        let PatchLabels { moved: labels, ring, .. } = certified_patches(&positions, &faces, &patch, &others);
        assert!(labels.iter().all(|&l| l == 0));
        assert!(others.iter().zip(&ring).all(|(&f, &l)| (l == 0) == touches(f)), "the ring is the faces touching");
        // A vertex of the ring, away from the patch, pushed across its neighbours.
        let far = (0..positions.len()).find(|&v| {
            let p = positions[v];
            (p.x - 0.5).abs() < 0.3
                && (p.z - 0.5).abs() < 0.3
                && p.y == 0.0
                && !patch.iter().any(|&g| faces[g as usize].contains(&(v as u32)))
        });
        positions[far.expect("a ring vertex off the patch")].x += 0.3;
        let PatchLabels { moved: labels, ring, .. } = certified_patches(&positions, &faces, &patch, &others);
        assert!(labels.iter().all(|&l| l == 0) && ring.iter().all(|&l| l == UNCERTIFIED));
    }

    #[test]
    fn patches_are_numbered_largest_first_and_small_ones_left_out() {
        let (positions, faces) = sheet(8, |_, _| 0.0);
        // Quad (i, j) is faces 16i + 2j and 16i + 2j + 1. The corner quad (2 faces), a block
        // of 2 × 6 quads and one of 3 × 8, each apart from the others.
        let quads = |rows: std::ops::Range<u32>, columns: std::ops::Range<u32>| {
            rows.flat_map(move |i| columns.clone().flat_map(move |j| [16 * i + 2 * j, 16 * i + 2 * j + 1]))
        };
        let chosen: Vec<u32> = quads(0..1, 0..1).chain(quads(2..4, 0..6)).chain(quads(5..8, 0..8)).collect();
        let PatchLabels { moved: labels, .. } = certified_patches(&positions, &faces, &chosen, &[]);
        assert_eq!(labels[..2], [UNCERTIFIED; 2]);
        assert!(labels[2..26].iter().all(|&l| l == 1));
        assert!(labels[26..].iter().all(|&l| l == 0));
    }
}
