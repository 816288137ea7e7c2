//! The convex hull of a mesh's vertices, as a closed mesh: the shape a dynamic body's convex
//! collider takes after a dent.
//!
//! Quickhull in f64: a tetrahedron of extreme vertices, then, while some face has vertices in
//! front of it, the farthest of them joins the hull: the faces it sees go, and a fan from it to
//! their horizon takes their place. Each vertex in front of a face is kept in that face's list
//! only, so a step looks at the vertices of the faces it removes, not at all of them.
//!
//! A vertex less than `RELATIVE_TOLERANCE` (10⁻¹⁰) of the vertices' box diagonal in front of a
//! face's plane counts as on it: it is left inside, and the hull misses it by at most that
//! (a grid of coplanar vertices, a box's side, comes out as its corners' triangles).

use glam::{DVec3, Vec3};

use super::{MeshError, TriMesh};

/// Distance in front of a face plane, as a fraction of the vertices' box diagonal, under which
/// a vertex counts as on the plane: far above f64's rounding of a height (10⁻¹⁶), far below
/// f32's spacing of the positions themselves (6·10⁻⁸), so only truly coplanar vertices tie.
const RELATIVE_TOLERANCE: f64 = 1e-10;

/// Attempts, each with a tolerance 16× the last, before a hull that stays ambiguous in
/// floating point (a horizon that is not one loop) is refused.
const ATTEMPTS: u32 = 3;

impl TriMesh {
    /// The convex hull of the vertices: a closed mesh (every edge shared by two faces, wound
    /// counter-clockwise seen from outside) of the hull's vertices, kept in their order here.
    /// Vertices within 10⁻¹⁰ of the vertices' box diagonal of the hull's surface are left
    /// inside.
    ///
    /// # Errors
    /// [`MeshError::InvalidParameter`] when the vertices lie in one plane (within the
    /// tolerance): they bound no volume.
    ///
    /// # Example
    /// ```
    /// use dentbend::{glam::Vec3, mesh};
    /// let ball = mesh::icosphere(0.5, 2).unwrap();
    /// let hull = ball.convex_hull().unwrap();
    /// assert_eq!(hull.vertex_count(), ball.vertex_count());
    /// assert!((hull.volume() - ball.volume()).abs() < 1e-6);
    /// ```
    pub fn convex_hull(&self) -> Result<TriMesh, MeshError> {
        let points: Vec<DVec3> = self.positions().iter().map(|p| p.as_dvec3()).collect();
        let (lo, hi) = self.bounds();
        let diagonal = f64::from((hi - lo).length());
        let mut tolerance = RELATIVE_TOLERANCE * diagonal;
        for _ in 0..ATTEMPTS {
            match Quickhull::run(&points, tolerance) {
                Ok(faces) => return Ok(self.hull_mesh(&faces)),
                Err(Failure::Flat) => {
                    return Err(MeshError::InvalidParameter(format!(
                        "the {} vertices lie in one plane (within {tolerance:e}): they have no convex hull with a \
                         volume; give a collider of a flat mesh a tri-mesh shape",
                        points.len()
                    )));
                }
                Err(Failure::Ambiguous) => tolerance *= 16.0,
            }
        }
        Err(MeshError::InvalidParameter(format!(
            "the convex hull of the {} vertices stays ambiguous in floating point up to a tolerance of {tolerance:e}",
            points.len()
        )))
    }

    /// The mesh of hull `faces` (indices into this mesh), its vertices renumbered in order.
    fn hull_mesh(&self, faces: &[[u32; 3]]) -> TriMesh {
        let mut used = vec![false; self.vertex_count()];
        faces.iter().flatten().for_each(|&v| used[v as usize] = true);
        let mut index = vec![u32::MAX; self.vertex_count()];
        let mut positions: Vec<Vec3> = Vec::new();
        for v in (0..self.vertex_count()).filter(|&v| used[v]) {
            index[v] = positions.len() as u32;
            positions.push(self.positions()[v]);
        }
        let faces = faces.iter().map(|f| f.map(|v| index[v as usize])).collect();
        TriMesh::from_valid(positions, faces)
    }
}

/// Why a hull was not made.
enum Failure {
    /// All vertices lie in one plane.
    Flat,
    /// Rounding made the faces a vertex sees into something other than one disc.
    Ambiguous,
}

/// A hull face: corners counter-clockwise from outside, plane `normal·x = offset`.
struct Face {
    corners: [u32; 3],
    normal: DVec3,
    offset: f64,
    /// The face across the edge from corner `i` to corner `i + 1`.
    neighbours: [u32; 3],
    /// First of the vertices in front of this face (and of no face before it in their
    /// search), linked through `Quickhull::next`; `NONE` for none.
    outside: u32,
    alive: bool,
    /// The last step that found the face visible.
    seen: u32,
}

/// The working state of one hull.
struct Quickhull<'a> {
    points: &'a [DVec3],
    tolerance: f64,
    faces: Vec<Face>,
    /// The vertex after each in its face's outside list (`NONE` at the end).
    next: Vec<u32>,
    /// Vertices added after the tetrahedron, the step count marking visible faces.
    step: u32,
    /// Buffers each step reuses.
    scratch: Scratch,
}

/// The buffers of a step, kept between steps so that a step allocates nothing.
#[derive(Default)]
struct Scratch {
    visible: Vec<u32>,
    stack: Vec<u32>,
    horizon: Vec<HorizonEdge>,
    orphans: Vec<u32>,
}

/// No vertex, or no face.
const NONE: u32 = u32::MAX;

impl<'a> Quickhull<'a> {
    /// The hull's faces, or why there is none.
    fn run(points: &'a [DVec3], tolerance: f64) -> Result<Vec<[u32; 3]>, Failure> {
        let faces = Vec::with_capacity(8 * points.len().min(1 << 20));
        let next = vec![NONE; points.len()];
        let mut hull = Quickhull { points, tolerance, faces, next, step: 0, scratch: Scratch::default() };
        let simplex = hull.simplex()?;
        hull.start(simplex)?;
        let mut next = 0;
        while next < hull.faces.len() {
            if hull.faces[next].alive && hull.faces[next].outside != NONE {
                hull.add_farthest_of(next)?;
            } else {
                next += 1;
            }
        }
        hull.check_convex()?;
        Ok(hull.faces.iter().filter(|f| f.alive).map(|f| f.corners).collect())
    }

    /// Checks that every edge is convex: each face's neighbours' far corners lie behind its
    /// plane (within twice the tolerance the steps decided with). A closed surface convex at
    /// every edge bounds a convex solid; rounding that made a step decide inconsistently shows
    /// here as a fold.
    fn check_convex(&self) -> Result<(), Failure> {
        for (f, face) in self.faces.iter().enumerate().filter(|(_, face)| face.alive) {
            for &n in &face.neighbours {
                let far = self.faces[n as usize].corners.iter().find(|v| !face.corners.contains(v));
                if far.is_some_and(|&v| self.height(f, v) > 2.0 * self.tolerance) {
                    return Err(Failure::Ambiguous);
                }
            }
        }
        Ok(())
    }

    /// Four vertices spanning the largest tetrahedron found greedily: the farthest pair of the
    /// axis extremes, the vertex farthest from their line, the one farthest from their plane
    /// (ties: [`farthest`]).
    fn simplex(&self) -> Result<[u32; 4], Failure> {
        let p = self.points;
        let centre = p.iter().sum::<DVec3>() / p.len() as f64;
        let mut extremes = Vec::with_capacity(6);
        for axis in 0..3 {
            extremes.push(farthest(p, |q| -q[axis], centre, self.tolerance));
            extremes.push(farthest(p, |q| q[axis], centre, self.tolerance));
        }
        let mut pair = (extremes[0], extremes[1]);
        for &a in &extremes {
            for &b in &extremes {
                if p[a].distance_squared(p[b]) > p[pair.0].distance_squared(p[pair.1]) {
                    pair = (a, b);
                }
            }
        }
        let (a, b) = pair;
        if p[a].distance(p[b]) <= self.tolerance {
            return Err(Failure::Flat);
        }
        let line = (p[b] - p[a]).normalize();
        let from_line = |q: DVec3| (q - p[a]).cross(line).length();
        let c = farthest(p, from_line, 0.5 * (p[a] + p[b]), self.tolerance);
        if from_line(p[c]) <= self.tolerance {
            return Err(Failure::Flat);
        }
        let normal = (p[b] - p[a]).cross(p[c] - p[a]).normalize();
        let from_plane = |q: DVec3| (q - p[a]).dot(normal).abs();
        let d = farthest(p, from_plane, (p[a] + p[b] + p[c]) / 3.0, self.tolerance);
        if from_plane(p[d]) <= self.tolerance {
            return Err(Failure::Flat);
        }
        Ok([a as u32, b as u32, c as u32, d as u32])
    }

    /// The tetrahedron's four faces, outward, and every other vertex in front of one of them.
    fn start(&mut self, [a, b, c, d]: [u32; 4]) -> Result<(), Failure> {
        let p = self.points;
        // Wind (a, b, c) so that d is behind it; the other faces follow from it.
        let (b, c) =
            if (p[b as usize] - p[a as usize]).cross(p[c as usize] - p[a as usize]).dot(p[d as usize] - p[a as usize])
                > 0.0
            {
                (c, b)
            } else {
                (b, c)
            };
        // Faces 0..4 with their neighbours across edges (corner i → corner i + 1).
        let tetrahedron =
            [([a, b, c], [1, 2, 3]), ([b, a, d], [0, 3, 2]), ([c, b, d], [0, 1, 3]), ([a, c, d], [0, 2, 1])];
        for (corners, neighbours) in tetrahedron {
            self.push_face(corners, neighbours)?;
        }
        let all: Vec<u32> = (0..p.len() as u32).filter(|v| ![a, b, c, d].contains(v)).collect();
        self.assign(&all, 0..4);
        Ok(())
    }

    /// A new live face; its plane from its corners.
    fn push_face(&mut self, corners: [u32; 3], neighbours: [u32; 3]) -> Result<u32, Failure> {
        let [a, b, c] = corners.map(|v| self.points[v as usize]);
        let normal = (b - a).cross(c - a).normalize_or_zero();
        if normal == DVec3::ZERO {
            return Err(Failure::Ambiguous);
        }
        let offset = normal.dot(a);
        self.faces.push(Face { corners, normal, offset, neighbours, outside: NONE, alive: true, seen: 0 });
        Ok(self.faces.len() as u32 - 1)
    }

    /// How far vertex `v` lies in front of face `f` (negative behind).
    fn height(&self, f: usize, v: u32) -> f64 {
        let face = &self.faces[f];
        face.normal.dot(self.points[v as usize]) - face.offset
    }

    /// Gives each of `vertices` to the first face of `candidates` it is in front of; the
    /// others are inside the hull so far, and stay inside.
    fn assign(&mut self, vertices: &[u32], candidates: std::ops::Range<usize>) {
        for &v in vertices {
            if let Some(f) = candidates.clone().find(|&f| self.height(f, v) > self.tolerance) {
                self.next[v as usize] = self.faces[f].outside;
                self.faces[f].outside = v;
            }
        }
    }

    /// Adds the vertex farthest in front of face `start` to the hull.
    fn add_farthest_of(&mut self, start: usize) -> Result<(), Failure> {
        let apex = self.farthest_outside(start);
        self.find_visible(start, apex);
        let mut s = std::mem::take(&mut self.scratch);
        s.orphans.clear();
        for &f in &s.visible {
            let face = &mut self.faces[f as usize];
            face.alive = false;
            let mut v = std::mem::replace(&mut face.outside, NONE);
            while v != NONE {
                if v != apex {
                    s.orphans.push(v);
                }
                v = self.next[v as usize];
            }
        }
        let first = self.faces.len();
        let result = self.build_fan(&s.horizon, apex, first as u32);
        if result.is_ok() {
            self.assign(&s.orphans, first..self.faces.len());
        }
        self.scratch = s;
        result
    }

    /// The vertex farthest in front of face `f` (which has some), in one pass over its list:
    /// a vertex clearly higher than the best so far replaces it, and one as high within the
    /// tolerance replaces it when it lies farther from the face's centre (so that, as in
    /// [`farthest`], a tie among coplanar vertices goes to a corner of theirs).
    fn farthest_outside(&self, f: usize) -> u32 {
        let face = &self.faces[f];
        let centre = face.corners.iter().map(|&v| self.points[v as usize]).sum::<DVec3>() / 3.0;
        let (mut best, mut best_height, mut best_spread) = (NONE, f64::NEG_INFINITY, f64::NEG_INFINITY);
        let mut v = face.outside;
        while v != NONE {
            let (height, spread) = (self.height(f, v), self.points[v as usize].distance_squared(centre));
            // Clearly higher, or as high within the tolerance and farther out.
            if height > best_height + self.tolerance || (height >= best_height - self.tolerance && spread > best_spread)
            {
                (best, best_height, best_spread) = (v, height.max(best_height), spread);
            }
            v = self.next[v as usize];
        }
        best
    }

    /// The faces from `apex` to each edge of `horizon`, face `first + k` on edge k, linked to
    /// their neighbours: across (to → apex) the fan face on the edge starting at `to`, across
    /// (apex → from) the one on the edge ending at `from`.
    fn build_fan(&mut self, horizon: &[HorizonEdge], apex: u32, first: u32) -> Result<(), Failure> {
        // Small horizons (the usual) are searched, large ones sorted.
        let sorted = |key: fn(&HorizonEdge) -> u32| {
            let mut by: Vec<(u32, u32)> = horizon.iter().enumerate().map(|(k, e)| (key(e), k as u32)).collect();
            by.sort_unstable();
            by
        };
        let (by_from, by_to) =
            if horizon.len() > 16 { (sorted(|e| e.from), sorted(|e| e.to)) } else { Default::default() };
        let find = |by: &[(u32, u32)], key: fn(&HorizonEdge) -> u32, v: u32| {
            let k = if by.is_empty() {
                horizon.iter().position(|e| key(e) == v)
            } else {
                by.binary_search_by_key(&v, |p| p.0).ok().map(|i| by[i].1 as usize)
            };
            k.map(|k| first + k as u32).ok_or(Failure::Ambiguous)
        };
        for edge in horizon {
            let after = find(&by_from, |e| e.from, edge.to)?;
            let before = find(&by_to, |e| e.to, edge.from)?;
            let made = self.push_face([edge.from, edge.to, apex], [edge.beyond, after, before])?;
            let beyond = &mut self.faces[edge.beyond as usize];
            let slot = (0..3)
                .find(|&i| beyond.corners[i] == edge.to && beyond.corners[(i + 1) % 3] == edge.from)
                .ok_or(Failure::Ambiguous)?;
            beyond.neighbours[slot] = made;
        }
        // Each horizon vertex starts one edge: else the visible faces were not one disc.
        let starts_once = if by_from.is_empty() {
            horizon.iter().enumerate().all(|(k, e)| horizon[k + 1..].iter().all(|o| o.from != e.from))
        } else {
            by_from.windows(2).all(|w| w[0].0 != w[1].0)
        };
        if starts_once { Ok(()) } else { Err(Failure::Ambiguous) }
    }

    /// The faces `apex` is in front of, reached from `start` across faces it is in front of
    /// (into `scratch.visible`), and the edges between them and the faces it is not in front
    /// of (into `scratch.horizon`, each with the face that stays behind it).
    fn find_visible(&mut self, start: usize, apex: u32) {
        self.step += 1;
        let step = self.step;
        let s = &mut self.scratch;
        s.visible.clear();
        s.horizon.clear();
        s.stack.clear();
        self.faces[start].seen = step;
        s.visible.push(start as u32);
        s.stack.push(start as u32);
        while let Some(f) = s.stack.pop() {
            let (corners, neighbours) = (self.faces[f as usize].corners, self.faces[f as usize].neighbours);
            for i in 0..3 {
                let n = neighbours[i];
                let face = &self.faces[n as usize];
                if face.seen == step {
                    continue;
                }
                if face.normal.dot(self.points[apex as usize]) - face.offset > self.tolerance {
                    self.faces[n as usize].seen = step;
                    s.visible.push(n);
                    s.stack.push(n);
                } else {
                    s.horizon.push(HorizonEdge { from: corners[i], to: corners[(i + 1) % 3], beyond: n });
                }
            }
        }
    }
}

/// An edge of the region a new vertex sees, with the face behind it that stays.
struct HorizonEdge {
    from: u32,
    to: u32,
    beyond: u32,
}

/// The index of the point with the largest `measure`; of those within `tolerance` of it, the
/// one farthest from `centre`, so that a tie among coplanar points goes to a corner of theirs
/// (the point of a set farthest from any point is a vertex of the set's hull), not to one that
/// would stay on the hull as a needless vertex.
fn farthest(points: &[DVec3], measure: impl Fn(DVec3) -> f64, centre: DVec3, tolerance: f64) -> usize {
    let top = points.iter().map(|&p| measure(p)).fold(f64::NEG_INFINITY, f64::max);
    (0..points.len())
        .filter(|&k| measure(points[k]) >= top - tolerance)
        .max_by(|&i, &j| points[i].distance_squared(centre).total_cmp(&points[j].distance_squared(centre)))
        .unwrap_or(0)
}
