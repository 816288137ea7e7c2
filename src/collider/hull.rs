//! Convex-hull colliders of dented meshes: a quickhull in f64 over the mesh's points, checked
//! before it is trusted, and parry's own hull when the check fails.
//!
//! A dynamic body's convex collider is rebuilt after every dent on it, so its hull is on the hot
//! path of a game's step. parry's general hull spends about 0.2 ms on the 162 points of a
//! two-fold subdivided icosphere; this one a small fraction of that (see the `collider_refit`
//! benchmark).
//!
//! # Algorithm and check
//!
//! Quickhull: a tetrahedron of extreme points, then, face by face, the farthest point outside
//! it replaces the faces it sees with a fan over their horizon. A point counts as outside a face
//! only when it lies more than `BUILD_TOLERANCE` of the points' box diagonal above its plane,
//! so near-coplanar points never make slivers. The result is trusted only if
//!
//! - it is a closed surface of genus 0: each edge's neighbour names it back, the triangles
//!   around each corner form one cycle, and V − E + F = 2;
//! - it is convex and faces out: across every edge the far corner lies under the triangle's
//!   plane (to f64 rounding) and the enclosed volume is positive. A closed, connected surface
//!   that is convex at every edge bounds a convex polytope, whose corners all lie under every
//!   face's plane;
//! - every input point that is not a corner lies within `INSIDE_TOLERANCE` of the diagonal
//!   under every face's plane.
//!
//! A convex polytope whose corners are input points and which holds every input point is
//! their hull. When a check fails, and for flat, collinear or non-finite input, parry's hull is
//! used unchanged.

use std::ops::Range;

use glam::{DVec3, Vec3};
use parry3d::shape::SharedShape;

/// A point counts as outside a face while building when it lies more than this fraction of the
/// points' box diagonal above the face's plane. f32 positions carry about 6e-8 of their size in
/// rounding; this is well above that, and far below any dent.
const BUILD_TOLERANCE: f64 = 1e-7;

/// The rounding of an f64 plane test through f32 points, as a fraction of their box diagonal
/// (a few f64 ulps, with room).
const ROUNDING: f64 = 1e-12;

/// The check accepts a point this fraction of the diagonal above a face's plane: points skipped
/// as coplanar while building lie within `BUILD_TOLERANCE` of a plane that later faces tilt by
/// at most as much again, with room for f64 rounding.
const INSIDE_TOLERANCE: f64 = 1e-5;

/// The convex hull of `points` (any frame, m) as a parry convex polyhedron; for points that span
/// no volume (fewer than four, flat, collinear) or that are not finite, whatever parry's own hull
/// makes of them (`None` when it makes nothing).
pub fn convex_hull(points: &[Vec3]) -> Option<SharedShape> {
    if let Some(hull) = quickhull(points)
        && let Some(shape) = SharedShape::convex_mesh(hull.points, &hull.triangles)
    {
        return Some(shape);
    }
    SharedShape::convex_hull(points)
}

/// A checked hull: its corner points and outward-facing (counter-clockwise) triangles.
#[derive(Debug)]
pub(crate) struct Hull {
    pub(crate) points: Vec<Vec3>,
    pub(crate) triangles: Vec<[u32; 3]>,
}

/// No face, no point: the end of a list.
const NONE: u32 = u32::MAX;

/// One face while building: corners (indices into the input), the faces across its edges
/// (`across[e]` shares edge `corners[e] → corners[e + 1]`), outward unit normal, the plane's
/// offset along it, and the points outside it not yet taken (a list threaded through
/// [`Outside`]) with the farthest of them.
struct Face {
    corners: [u32; 3],
    across: [u32; 3],
    normal: DVec3,
    offset: f64,
    first_outside: u32,
    farthest: (u32, f64),
    alive: bool,
}

impl Face {
    fn new(corners: [u32; 3], p: &[DVec3], min_area: f64) -> Option<Self> {
        let [a, b, c] = corners.map(|i| p[i as usize]);
        let cross = (b - a).cross(c - a);
        let length = cross.length();
        if length.is_nan() || length <= min_area {
            return None;
        }
        let normal = cross / length;
        Some(Self {
            corners,
            across: [NONE; 3],
            normal,
            offset: normal.dot(a),
            first_outside: NONE,
            farthest: (NONE, 0.0),
            alive: true,
        })
    }

    fn height(&self, q: DVec3) -> f64 {
        self.normal.dot(q) - self.offset
    }

    /// Which of this face's edges runs `a → b`.
    fn edge(&self, a: u32, b: u32) -> Option<usize> {
        (0..3).find(|&e| self.corners[e] == a && self.corners[(e + 1) % 3] == b)
    }
}

/// The faces' outside lists, threaded through one array: `next[i]` follows point `i`.
struct Outside {
    next: Vec<u32>,
}

impl Outside {
    /// Gives each of `points` to the first face of `among` it lies more than `eps` above.
    fn assign(&mut self, faces: &mut [Face], among: Range<u32>, points: &[u32], p: &[DVec3], eps: f64) {
        for &i in points {
            let q = p[i as usize];
            for f in among.clone() {
                let face = &mut faces[f as usize];
                let height = face.height(q);
                if height > eps {
                    self.next[i as usize] = face.first_outside;
                    face.first_outside = i;
                    if height > face.farthest.1 {
                        face.farthest = (i, height);
                    }
                    break;
                }
            }
        }
    }

    /// Empties face `face`'s list into `into`, leaving out `skip`.
    fn take(&mut self, face: &mut Face, skip: u32, into: &mut Vec<u32>) {
        let mut i = std::mem::replace(&mut face.first_outside, NONE);
        while i != NONE {
            if i != skip {
                into.push(i);
            }
            i = self.next[i as usize];
        }
    }
}

/// One edge of the horizon: its corners (as the visible face ran it), the face beyond it that
/// stays, and that face's slot for the edge.
struct HorizonEdge {
    from: u32,
    to: u32,
    beyond: u32,
    slot: usize,
}

/// The hull of `points`, checked; `None` when the quickhull cannot build one it can vouch for.
pub(crate) fn quickhull(points: &[Vec3]) -> Option<Hull> {
    if points.len() < 4 || points.len() >= NONE as usize || !points.iter().all(|p| p.is_finite()) {
        return None;
    }
    let p: Vec<DVec3> = points.iter().map(|q| q.as_dvec3()).collect();
    let (lo, hi) = p.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), &q| (l.min(q), h.max(q)));
    let diagonal = (hi - lo).length();
    if diagonal.is_nan() || diagonal <= 0.0 {
        return None;
    }
    let eps = BUILD_TOLERANCE * diagonal;
    let mut faces = Vec::with_capacity(6 * p.len().min(4096));
    faces.extend(first_tetrahedron(&p, eps)?);
    let mut outside = Outside { next: vec![NONE; p.len()] };
    let used: Vec<u32> = faces.iter().flat_map(|f| f.corners).collect();
    let rest: Vec<u32> = (0..p.len() as u32).filter(|i| !used.contains(i)).collect();
    outside.assign(&mut faces, 0..4, &rest, &p, eps);

    let mut pending: Vec<u32> = (0..4).collect();
    let mut visible: Vec<u32> = Vec::new();
    let mut horizon: Vec<HorizonEdge> = Vec::new();
    let mut orphans: Vec<u32> = Vec::new();
    while let Some(f) = pending.pop() {
        let face = &faces[f as usize];
        if !face.alive || face.first_outside == NONE {
            continue;
        }
        let apex = face.farthest.0;
        let q = p[apex as usize];
        // The faces the apex sees, connected through shared edges, and their horizon.
        visible.clear();
        horizon.clear();
        visible.push(f);
        faces[f as usize].alive = false;
        let mut k = 0;
        while k < visible.len() {
            let face = &faces[visible[k] as usize];
            let (corners, across) = (face.corners, face.across);
            for e in 0..3 {
                let other = &mut faces[across[e] as usize];
                if !other.alive {
                    continue;
                }
                if other.height(q) > eps {
                    other.alive = false;
                    visible.push(across[e]);
                } else {
                    let (from, to) = (corners[e], corners[(e + 1) % 3]);
                    let slot = other.edge(to, from)?;
                    horizon.push(HorizonEdge { from, to, beyond: across[e], slot });
                }
            }
            k += 1;
        }
        orphans.clear();
        for &v in &visible {
            outside.take(&mut faces[v as usize], apex, &mut orphans);
        }
        // A fan over the horizon, which must be one loop through distinct corners (a visible
        // set that is not a disk, from near-coplanar faces, leaves it to parry).
        let first = faces.len() as u32;
        for (n, h) in horizon.iter().enumerate() {
            let mut face = Face::new([h.from, h.to, apex], &p, eps * eps)?;
            face.across[0] = h.beyond;
            faces[h.beyond as usize].across[h.slot] = first + n as u32;
            faces.push(face);
        }
        for (n, h) in horizon.iter().enumerate() {
            // Edge `to → apex` meets the new face starting at `to`; `apex → from`, the one ending
            // at `from`.
            let mut starts = horizon.iter().enumerate().filter(|(_, o)| o.from == h.to);
            let (Some((next, _)), None) = (starts.next(), starts.next()) else { return None };
            let mut ends = horizon.iter().enumerate().filter(|(_, o)| o.to == h.from);
            let (Some((previous, _)), None) = (ends.next(), ends.next()) else { return None };
            faces[first as usize + n].across[1] = first + next as u32;
            faces[first as usize + n].across[2] = first + previous as u32;
        }
        let last = faces.len() as u32;
        outside.assign(&mut faces, first..last, &orphans, &p, eps);
        pending.extend(first..last);
    }
    let (hull, across, corner_of) = collect(&faces, points);
    let checked = is_closed_sphere(&hull, &across)
        && is_convex(&hull, &across, ROUNDING * diagonal)
        && holds_the_rest(&hull, &p, &corner_of, INSIDE_TOLERANCE * diagonal);
    checked.then_some(hull)
}

/// Four extreme points spanning a tetrahedron, as four outward faces; `None` when the points
/// are collinear or flat within `eps`.
fn first_tetrahedron(p: &[DVec3], eps: f64) -> Option<Vec<Face>> {
    let mut extremes = [0usize; 6];
    for (i, q) in p.iter().enumerate() {
        for axis in 0..3 {
            if q[axis] < p[extremes[2 * axis]][axis] {
                extremes[2 * axis] = i;
            }
            if q[axis] > p[extremes[2 * axis + 1]][axis] {
                extremes[2 * axis + 1] = i;
            }
        }
    }
    let mut best = (0.0, 0, 0);
    for &i in &extremes {
        for &j in &extremes {
            let d = p[i].distance_squared(p[j]);
            if d > best.0 {
                best = (d, i, j);
            }
        }
    }
    let (_, a, b) = best;
    let axis = (p[b] - p[a]).try_normalize()?;
    let off_line = |q: DVec3| (q - p[a]).reject_from_normalized(axis).length_squared();
    let c = farthest(p, off_line)?;
    if off_line(p[c]) <= eps * eps {
        return None;
    }
    let normal = (p[b] - p[a]).cross(p[c] - p[a]).try_normalize()?;
    let d = farthest(p, |q| normal.dot(q - p[a]).abs())?;
    if normal.dot(p[d] - p[a]).abs() <= eps {
        return None;
    }
    let [a, b, c, d] = [a, b, c, d].map(|i| i as u32);
    // Outward: the fourth corner lies below each face.
    let (b, c) = if normal.dot(p[d as usize] - p[a as usize]) > 0.0 { (c, b) } else { (b, c) };
    let mut faces: Vec<Face> = [[a, b, c], [a, d, b], [b, d, c], [c, d, a]]
        .into_iter()
        .map(|t| Face::new(t, p, eps * eps))
        .collect::<Option<_>>()?;
    // Each directed edge's twin runs the other way on another face.
    for f in 0..4 {
        for e in 0..3 {
            let (from, to) = (faces[f].corners[e], faces[f].corners[(e + 1) % 3]);
            faces[f].across[e] = (0..4).find(|&g| g != f && faces[g].edge(to, from).is_some())? as u32;
        }
    }
    Some(faces)
}

/// Index of the point with the largest `key`.
fn farthest(p: &[DVec3], key: impl Fn(DVec3) -> f64) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (i, &q) in p.iter().enumerate() {
        let k = key(q);
        if best.is_none_or(|(_, b)| k > b) {
            best = Some((i, k));
        }
    }
    best.map(|(i, _)| i)
}

/// The live faces over their own corners (renumbered in order of first use), each triangle's
/// neighbours across its edges (as triangle indices; `NONE` for a dead face), and each input
/// point's corner index (`NONE` for the points inside).
fn collect(faces: &[Face], points: &[Vec3]) -> (Hull, Vec<[u32; 3]>, Vec<u32>) {
    let mut corner_of = vec![NONE; points.len()];
    let mut triangle_of = vec![NONE; faces.len()];
    let mut hull = Hull { points: Vec::new(), triangles: Vec::new() };
    for (f, face) in faces.iter().enumerate().filter(|(_, f)| f.alive) {
        triangle_of[f] = hull.triangles.len() as u32;
        let triangle = face.corners.map(|v| {
            let slot = &mut corner_of[v as usize];
            if *slot == NONE {
                *slot = hull.points.len() as u32;
                hull.points.push(points[v as usize]);
            }
            *slot
        });
        hull.triangles.push(triangle);
    }
    let across = faces.iter().filter(|f| f.alive).map(|f| f.across.map(|g| triangle_of[g as usize])).collect();
    (hull, across, corner_of)
}

/// Whether `hull` is a closed surface of genus 0: each triangle's neighbour across each edge
/// runs that edge the other way and names it back, the triangles around each corner form one
/// cycle, and V − E + F = 2.
fn is_closed_sphere(hull: &Hull, across: &[[u32; 3]]) -> bool {
    let tris = &hull.triangles;
    let mut around = vec![0u32; hull.points.len()];
    let mut start = vec![(NONE, 0usize); hull.points.len()];
    for (t, tri) in tris.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (tri[e], tri[(e + 1) % 3]);
            let Some(other) = tris.get(across[t][e] as usize) else { return false };
            let Some(back) = (0..3).find(|&k| other[k] == b && other[(k + 1) % 3] == a) else { return false };
            if across[across[t][e] as usize][back] != t as u32 {
                return false;
            }
            around[a as usize] += 1;
            start[a as usize] = (t as u32, e);
        }
    }
    // Around corner `v` of triangle `t` (at slot `e`): the next triangle is across edge `e`
    // (from `v`), where `v` is the corner after that edge's other end.
    for (v, &(first, slot)) in start.iter().enumerate() {
        if first == NONE {
            return false;
        }
        let (mut t, mut e, mut steps) = (first, slot, 0u32);
        loop {
            let next = across[t as usize][e];
            let Some(k) = (0..3).find(|&k| tris[next as usize][k] == v as u32) else { return false };
            (t, e, steps) = (next, k, steps + 1);
            if t == first || steps > around[v] {
                break;
            }
        }
        if t != first || steps != around[v] {
            return false;
        }
    }
    let (v, f) = (hull.points.len() as i64, tris.len() as i64);
    v - 3 * f / 2 + f == 2
}

/// Whether `hull` (a closed surface of genus 0, with neighbours `across`) is convex and faces
/// out: the far corner of the triangle across each edge lies under the triangle's plane (within
/// `rounding`, m, the f64 rounding of the test), and the enclosed volume is positive. Such a
/// surface bounds a convex polytope: each corner then lies under every face's plane.
fn is_convex(hull: &Hull, across: &[[u32; 3]], rounding: f64) -> bool {
    let corner = |i: u32| hull.points[i as usize].as_dvec3();
    let mut volume = 0.0;
    for (t, tri) in hull.triangles.iter().enumerate() {
        let [a, b, c] = tri.map(corner);
        let Some(n) = (b - a).cross(c - a).try_normalize() else { return false };
        volume += a.dot(b.cross(c));
        for &neighbour in &across[t] {
            let other = hull.triangles[neighbour as usize];
            let Some(far) = other.into_iter().find(|v| !tri.contains(v)) else { return false };
            if n.dot(corner(far) - a) > rounding {
                return false;
            }
        }
    }
    volume > 0.0
}

/// Whether each of `p` that is not a corner of `hull` (`corner_of[i] == NONE`) lies at most
/// `tolerance` (m) above every face's plane (the corners do, `hull` being convex).
fn holds_the_rest(hull: &Hull, p: &[DVec3], corner_of: &[u32], tolerance: f64) -> bool {
    let rest: Vec<DVec3> = p.iter().zip(corner_of).filter(|&(_, &c)| c == NONE).map(|(&q, _)| q).collect();
    if rest.is_empty() {
        return true;
    }
    hull.triangles.iter().all(|t| {
        let [a, b, c] = t.map(|i| hull.points[i as usize].as_dvec3());
        let Some(n) = (b - a).cross(c - a).try_normalize() else { return false };
        let limit = n.dot(a) + tolerance;
        // Counted without an early exit: the comparisons vectorize.
        rest.iter().map(|&q| u32::from(n.dot(q) > limit)).sum::<u32>() == 0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether every point lies at most `tolerance` (m) above every face plane, in f64
    /// throughout (the test's own check, independent of the f32 one).
    fn inside_every_plane(hull: &Hull, points: &[Vec3], tolerance: f64) -> bool {
        hull.triangles.iter().all(|t| {
            let [a, b, c] = t.map(|i| hull.points[i as usize].as_dvec3());
            let n = (b - a).cross(c - a).normalize();
            points.iter().all(|q| n.dot(q.as_dvec3() - a) <= tolerance)
        })
    }

    fn volume(hull: &Hull) -> f64 {
        hull.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| hull.points[i as usize].as_dvec3());
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn a_cube_with_inner_and_face_points_gives_its_eight_corners() {
        let mut points: Vec<Vec3> =
            (0..8).map(|i| Vec3::new((i & 1) as f32, (i >> 1 & 1) as f32, (i >> 2 & 1) as f32)).collect();
        // Points inside, on faces, on edges, and repeated corners: none become hull corners.
        points.extend([Vec3::splat(0.5), Vec3::new(0.5, 0.5, 0.0), Vec3::new(1.0, 0.5, 1.0), Vec3::ONE, Vec3::ZERO]);
        let hull = quickhull(&points).expect("a cube has a hull");
        assert_eq!(hull.points.len(), 8);
        assert_eq!(hull.triangles.len(), 12);
        assert!((volume(&hull) - 1.0).abs() < 1e-6, "volume {}", volume(&hull));
    }

    #[test]
    fn flat_collinear_and_non_finite_points_get_no_quickhull() {
        let square = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE.with_z(0.0), Vec3::new(0.5, 0.5, 0.0)];
        assert!(quickhull(&square).is_none());
        assert!(quickhull(&[Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::X * 3.0]).is_none());
        assert!(quickhull(&[Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.0, 0.0, f32::NAN)]).is_none());
        assert!(quickhull(&[Vec3::ZERO, Vec3::X, Vec3::Y]).is_none());
    }

    /// The volume of the hull of `points` by brute force: every triple whose plane has all
    /// points on one side is a hull face (coplanar points make fans; each triangle of the fan
    /// over the face's points is counted with the face's area weight, so the sum is exact for
    /// points in general position, which random f32 clouds are).
    fn brute_force_volume(points: &[Vec3]) -> f64 {
        let p: Vec<DVec3> = points.iter().map(|q| q.as_dvec3()).collect();
        let mut total = 0.0;
        for i in 0..p.len() {
            for j in i + 1..p.len() {
                for k in j + 1..p.len() {
                    let n = (p[j] - p[i]).cross(p[k] - p[i]);
                    let side = |q: DVec3| n.dot(q - p[i]);
                    let above = p.iter().filter(|&&q| side(q) > 1e-12).count();
                    let below = p.iter().filter(|&&q| side(q) < -1e-12).count();
                    if above == 0 || below == 0 {
                        let signed = p[i].dot(p[j].cross(p[k])) / 6.0;
                        total += if above == 0 { signed } else { -signed };
                    }
                }
            }
        }
        total
    }

    /// A deterministic cloud (xorshift): `n` points in a box of sides 4 × 1 × 2, or on a sphere
    /// of radius 0.3.
    fn cloud(n: usize, on_sphere: bool, seed: u64) -> Vec<Vec3> {
        let mut state = seed;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
        };
        (0..n)
            .map(|_| {
                let q = Vec3::new(next(), next(), next());
                if on_sphere { q.normalize_or(Vec3::X) * 0.3 } else { q * Vec3::new(2.0, 0.5, 1.0) }
            })
            .collect()
    }

    #[test]
    fn random_clouds_get_their_hull() {
        for (n, on_sphere) in [(10, false), (40, false), (60, true), (500, true), (2000, false)] {
            let points = cloud(n, on_sphere, 0x2545_f491_4f6c_dd1d + n as u64);
            let hull = quickhull(&points).expect("a cloud has a hull");
            // Closed, genus 0, every point within 1e-9 m of inside every face: the hull (its
            // corners are input points, so it holds no more than their hull). Random f32 points
            // lie in general position, far above 1e-9 m from any plane of three others.
            assert!(inside_every_plane(&hull, &points, 1e-9), "n {n}");
            if n <= 60 {
                // And the same volume as the brute-force hull, to f64 rounding of the sums.
                let (ours, exact) = (volume(&hull), brute_force_volume(&points));
                assert!((ours - exact).abs() <= 1e-9 * exact, "n {n}: {ours} vs {exact}");
            }
        }
    }

    #[test]
    fn a_dented_icosphere_hull_holds_every_point() {
        let sphere = crate::mesh::icosphere(0.15, 2).expect("icosphere");
        let mut points = sphere.positions().to_vec();
        // A dent: a cap of points pushed in (they leave the hull; their neighbours stay).
        for q in points.iter_mut().filter(|q| q.y > 0.12) {
            q.y = 0.1 + (q.y - 0.12) * 0.1;
        }
        let hull = quickhull(&points).expect("hull");
        assert!(inside_every_plane(&hull, &points, 1e-9), "every point within 1e-9 m of inside");
        assert!(hull.points.len() < points.len(), "the pushed-in points left the hull");
    }
}
