//! Local refinement: crack-free longest-edge bisection of the triangles that touch a region,
//! until none of them has an edge longer than a given length.
//!
//! Each split halves one edge and every face on it at once (so no T-junction can appear, and a
//! closed mesh stays closed); which edge is split follows Rivara's longest-edge propagation
//! path, so triangles never get thinner than about half their starting angles. Refinement only
//! APPENDS: existing vertex indices keep their meaning, a split face keeps its slot for one child
//! and the other child is appended. The new vertices' provenance ([`Refinement`]) lets a caller
//! carry its own per-vertex data (UVs, skin weights, colours) along
//! ([`Refinement::interpolate`]).
//!
//! Vertices that share a position (a game mesh's hard edges and UV seams, `weld`) are one point
//! of the surface: an edge is split on every side of a seam at once, each side getting its own
//! new vertex at a bit-identical position, so the sides stay together.
//!
//! A refinement never makes faces cross that did not: where a rounded midpoint would (on a
//! surface folded flat onto itself, see `refine_crossings`), the base faces involved are left
//! unsplit ([`Refinement::held_back`]) and the refinement is run again without them.

use std::collections::{HashMap, HashSet, VecDeque};

use glam::Vec3;
use rayon::prelude::*;

use super::TriMesh;
use super::refine_crossings::{Pieces, crossings_made};
use super::weld::Weld;

/// Where a mesh is refined: a triangle is refined while it touches the region.
pub trait RefineRegion: Sync {
    /// Whether the triangle with corners `triangle` (world units) touches the region; may be
    /// conservative (say yes for a triangle just outside).
    fn touches(&self, triangle: [Vec3; 3]) -> bool;
}

/// A solid ball, world units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ball {
    /// Centre.
    pub centre: Vec3,
    /// Radius (≥ 0).
    pub radius: f32,
}

impl RefineRegion for Ball {
    fn touches(&self, triangle: [Vec3; 3]) -> bool {
        distance_sq_to_triangle(self.centre, triangle) <= self.radius * self.radius
    }
}

/// A solid box with orthonormal axes (a dent's footprint: two axes across the collision plane,
/// one along the depth), world units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrientedBox {
    /// Centre.
    pub centre: Vec3,
    /// Unit, mutually orthogonal axes.
    pub axes: [Vec3; 3],
    /// Half the side along each axis (≥ 0).
    pub half_extents: Vec3,
}

impl OrientedBox {
    /// Whether point `p` lies in the box (its boundary included).
    pub(crate) fn contains(&self, p: Vec3) -> bool {
        let r = p - self.centre;
        (0..3).all(|i| r.dot(self.axes[i]).abs() <= self.half_extents[i])
    }
}

impl RefineRegion for OrientedBox {
    /// Exact separating-axis test (the box's 3 axes, the triangle's normal, and the 9 products
    /// of a box axis with a triangle edge) in the box's coordinates.
    fn touches(&self, triangle: [Vec3; 3]) -> bool {
        // Bounding spheres first: most triangles of a large mesh are far from a small box.
        let centroid = (triangle[0] + triangle[1] + triangle[2]) / 3.0;
        let spread = triangle.iter().map(|p| p.distance_squared(centroid)).fold(0.0, f32::max).sqrt();
        if centroid.distance(self.centre) > self.half_extents.length() + spread {
            return false;
        }
        let local = triangle.map(|p| {
            let r = p - self.centre;
            Vec3::new(r.dot(self.axes[0]), r.dot(self.axes[1]), r.dot(self.axes[2]))
        });
        let h = self.half_extents;
        let separated = |axis: Vec3| {
            if axis.length_squared() <= f32::EPSILON * f32::EPSILON {
                return false; // a degenerate axis separates nothing
            }
            let [p0, p1, p2] = local.map(|p| p.dot(axis));
            let reach = h.x * axis.x.abs() + h.y * axis.y.abs() + h.z * axis.z.abs();
            p0.min(p1).min(p2) > reach || p0.max(p1).max(p2) < -reach
        };
        if [Vec3::X, Vec3::Y, Vec3::Z].into_iter().any(separated) {
            return false;
        }
        let edges = [local[1] - local[0], local[2] - local[1], local[0] - local[2]];
        if separated(edges[0].cross(edges[1])) {
            return false;
        }
        !edges.iter().any(|&e| [Vec3::X, Vec3::Y, Vec3::Z].into_iter().any(|a| separated(a.cross(e))))
    }
}

/// Where one new vertex came from: it lies at `(1 − fraction)·parents[0] + fraction·parents[1]`
/// (both parents have smaller indices; either may itself be new).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SplitVertex {
    /// The ends of the split edge.
    pub parents: [u32; 2],
    /// Where along the edge, in (0, 1) (bisection: 0.5).
    pub fraction: f32,
}

/// What a refinement appended to a mesh that had `base_vertex_count` vertices and
/// `base_face_count` faces. Empty when nothing was refined.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Refinement {
    /// Vertices before refinement.
    pub base_vertex_count: usize,
    /// Faces before refinement.
    pub base_face_count: usize,
    /// Vertex `base_vertex_count + k` came from `vertices[k]`.
    pub vertices: Vec<SplitVertex>,
    /// Face `base_face_count + k` is a piece of the base face `face_parents[k]` (copy per-face
    /// data from there); a split base face keeps its own slot for another piece.
    pub face_parents: Vec<u32>,
    /// Base faces whose slot now holds a smaller piece, ascending.
    pub split_faces: Vec<u32>,
    /// Base faces left unsplit, edges included, although too coarse: splitting them would have
    /// made faces cross (rounded midpoints on a surface folded flat onto itself), ascending.
    pub held_back: Vec<u32>,
}

impl Refinement {
    /// Whether nothing was refined (the mesh's faces are unchanged).
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty() && self.face_parents.is_empty()
    }

    /// Vertices added.
    pub fn added_vertices(&self) -> usize {
        self.vertices.len()
    }

    /// Triangles added.
    pub fn added_faces(&self) -> usize {
        self.face_parents.len()
    }

    /// `values` (one per base vertex; any entries past `base_vertex_count` are dropped) extended
    /// with a value for every new vertex, `lerp(a, b, t)` blending its parents' values.
    ///
    /// # Errors
    /// [`RefineError::AttributeCount`] when `values` has fewer than `base_vertex_count` entries.
    ///
    /// # Example
    /// ```
    /// use dentbend::{glam::{Vec2, Vec3}, mesh::{self, Ball}};
    /// let quad = dentbend::TriMesh::new(
    ///     vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
    ///     vec![[0, 1, 2], [0, 2, 3]],
    /// )?;
    /// let uvs = vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    /// let (fine, refinement) = mesh::refine(&quad, &Ball { centre: Vec3::ZERO, radius: 2.0 }, 0.5, 1000)?;
    /// let fine_uvs = refinement.interpolate(&uvs, |a, b, t| a.lerp(*b, t))?;
    /// assert_eq!(fine_uvs.len(), fine.vertex_count());
    /// // Here UV = (x, y): every interpolated UV matches its vertex.
    /// assert!(fine.positions().iter().zip(&fine_uvs).all(|(p, uv)| p.truncate().distance(*uv) < 1e-6));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn interpolate<T: Clone>(&self, values: &[T], lerp: impl Fn(&T, &T, f32) -> T) -> Result<Vec<T>, RefineError> {
        if values.len() < self.base_vertex_count {
            return Err(RefineError::AttributeCount { expected: self.base_vertex_count, actual: values.len() });
        }
        let mut out = Vec::with_capacity(self.base_vertex_count + self.vertices.len());
        out.extend_from_slice(&values[..self.base_vertex_count]);
        for s in &self.vertices {
            let value = lerp(&out[s.parents[0] as usize], &out[s.parents[1] as usize], s.fraction);
            out.push(value);
        }
        Ok(out)
    }

    /// Appends `later`, a refinement of the mesh this one produced, so that the result describes
    /// both from this one's base.
    ///
    /// # Errors
    /// [`RefineError::NotConsecutive`] when `later` did not start from this one's result.
    pub fn extend(&mut self, later: Refinement) -> Result<(), RefineError> {
        if later.is_empty() && later.held_back.is_empty() {
            return Ok(());
        }
        if self.is_empty() && self.base_vertex_count == 0 && self.base_face_count == 0 {
            *self = later;
            return Ok(());
        }
        let (vertices, faces) =
            (self.base_vertex_count + self.vertices.len(), self.base_face_count + self.face_parents.len());
        if later.base_vertex_count != vertices || later.base_face_count != faces {
            return Err(RefineError::NotConsecutive);
        }
        let root = |slot: u32| -> u32 {
            let s = slot as usize;
            if s < self.base_face_count { slot } else { self.face_parents[s - self.base_face_count] }
        };
        let parents: Vec<u32> = later.face_parents.iter().map(|&f| root(f)).collect();
        let mut held_back: Vec<u32> = later.held_back.iter().map(|&f| root(f)).collect();
        held_back.extend_from_slice(&self.held_back);
        held_back.sort_unstable();
        held_back.dedup();
        self.held_back = held_back;
        let mut split: Vec<u32> =
            later.split_faces.iter().copied().filter(|&f| (f as usize) < self.base_face_count).collect();
        self.face_parents.extend(parents);
        self.vertices.extend(later.vertices);
        split.extend_from_slice(&self.split_faces);
        split.sort_unstable();
        split.dedup();
        self.split_faces = split;
        Ok(())
    }
}

/// Why a refinement was refused; the mesh is unchanged then.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RefineError {
    /// The longest edge allowed is not a positive finite length.
    #[error("refine: max_edge = {0} must be finite and > 0")]
    InvalidMaxEdge(f32),
    /// Refining would add more triangles than allowed.
    #[error("refine: more than {limit} new triangles would be needed (max_edge {max_edge})")]
    TooManyTriangles {
        /// The cap on new triangles.
        limit: usize,
        /// The edge length asked for, world units.
        max_edge: f32,
    },
    /// An attribute array has fewer values than the base mesh has vertices.
    #[error("refine: {actual} attribute values for {expected} base vertices")]
    AttributeCount {
        /// Base vertices.
        expected: usize,
        /// Values given.
        actual: usize,
    },
    /// Two refinements joined by [`Refinement::extend`] do not follow each other.
    #[error("refine: the later refinement does not start from the earlier one's result")]
    NotConsecutive,
    /// Every way tried to split the region made faces cross (the surface there is folded flat
    /// onto itself in many places); nothing was split.
    #[error("refine: splitting here would make faces cross (a surface folded flat onto itself)")]
    WouldCross,
}

/// Refinements tried, each holding back more base faces, before [`RefineError::WouldCross`].
const CROSSING_RETRIES: usize = 8;

/// Refines `mesh` where it touches `region` until no touching triangle has an edge longer than
/// `max_edge` (world units), adding at most `max_new_triangles` triangles. Returns the refined
/// mesh and what was added (a copy of `mesh` and an empty [`Refinement`] when nothing was too
/// long). Deterministic: the same input gives a bit-identical output.
///
/// Faces with a repeated vertex index (zero area) are never split themselves; an edge they share
/// is split in the other faces only.
///
/// # Errors
/// [`RefineError::InvalidMaxEdge`]; [`RefineError::TooManyTriangles`] when the cap would be passed
/// (nothing is returned then: refine with a longer `max_edge` or a higher cap);
/// [`RefineError::WouldCross`] when every refinement tried made faces cross.
pub fn refine(
    mesh: &TriMesh,
    region: &dyn RefineRegion,
    max_edge: f32,
    max_new_triangles: usize,
) -> Result<(TriMesh, Refinement), RefineError> {
    let mut positions = mesh.positions().to_vec();
    let mut faces = mesh.faces().to_vec();
    let refinement = refine_parts(&mut positions, &mut faces, region, max_edge, max_new_triangles)?;
    if refinement.is_empty() {
        return Ok((mesh.clone(), refinement));
    }
    Ok((TriMesh::from_valid(positions, faces), refinement))
}

/// [`refine`] on a mesh's parts, in place; `positions` and `faces` are unchanged on error (and
/// untouched when nothing needs refining: one pass over the faces).
pub(crate) fn refine_parts(
    positions: &mut Vec<Vec3>,
    faces: &mut Vec<[u32; 3]>,
    region: &dyn RefineRegion,
    max_edge: f32,
    max_new_triangles: usize,
) -> Result<Refinement, RefineError> {
    if !(max_edge.is_finite() && max_edge > 0.0) {
        return Err(RefineError::InvalidMaxEdge(max_edge));
    }
    let mut held_back = HashSet::new();
    // The positions are the same for every try (a try that fails rolls back).
    let weld = Weld::of(positions);
    for _ in 0..CROSSING_RETRIES {
        match refine_once(positions, faces, weld.clone(), region, max_edge, max_new_triangles, &held_back)? {
            Ok(mut log) => {
                log.held_back = held_back.into_iter().collect();
                log.held_back.sort_unstable();
                return Ok(log);
            }
            Err(crossing) => held_back.extend(crossing),
        }
    }
    Err(RefineError::WouldCross)
}

/// One refinement that splits no edge of the base faces `held_back`: `Ok(Ok(log))`, or
/// `Ok(Err(faces))` (and the parts as they were) when it made faces cross, naming the base
/// faces whose pieces did.
fn refine_once(
    positions: &mut Vec<Vec3>,
    faces: &mut Vec<[u32; 3]>,
    weld: Option<Weld>,
    region: &dyn RefineRegion,
    max_edge: f32,
    max_new_triangles: usize,
    held_back: &HashSet<u32>,
) -> Result<Result<Refinement, Vec<u32>>, RefineError> {
    let base = Refinement { base_vertex_count: positions.len(), base_face_count: faces.len(), ..Default::default() };
    let mut refiner = Refiner {
        weld,
        positions,
        faces,
        max_edge_sq: max_edge * max_edge,
        region,
        adjacency: None,
        log: base,
        undo: Vec::new(),
        held_back,
    };
    let candidates: VecDeque<u32> =
        (0..refiner.faces.len() as u32).filter(|&f| !held_back.contains(&f) && refiner.needs(f)).collect();
    if candidates.is_empty() {
        return Ok(Ok(refiner.log));
    }
    let welded: Vec<[u32; 3]> = refiner.faces.iter().map(|f| refiner.welded(*f)).collect();
    refiner.adjacency = Some(Adjacency::new(refiner.positions.len(), &welded));
    if refiner.run(candidates, max_new_triangles).is_err() {
        refiner.roll_back();
        return Err(RefineError::TooManyTriangles { limit: max_new_triangles, max_edge });
    }
    let crossing = refiner.crossings_made();
    if !crossing.is_empty() {
        refiner.roll_back();
        return Ok(Err(crossing));
    }
    let mut log = std::mem::take(&mut refiner.log);
    log.split_faces.sort_unstable();
    log.split_faces.dedup();
    Ok(Ok(log))
}

/// Whether any non-degenerate face of `positions`/`faces` that touches `region` has an edge
/// longer than `max_edge` (what [`refine`] would split); one pass on all cores, nothing
/// allocated.
pub(crate) fn any_too_long(positions: &[Vec3], faces: &[[u32; 3]], region: &dyn RefineRegion, max_edge: f32) -> bool {
    let max_sq = max_edge * max_edge;
    faces.par_iter().any(|&f| {
        let [a, b, c] = f.map(|v| positions[v as usize]);
        let too_long =
            a.distance_squared(b) > max_sq || b.distance_squared(c) > max_sq || c.distance_squared(a) > max_sq;
        too_long && !Refiner::degenerate(f) && region.touches([a, b, c])
    })
}

/// Vertex → faces, for the base mesh in one packed array, and for vertices a split touched in a
/// list of their own. Keyed by a group of vertices that share a position (its first vertex):
/// the other vertices of a group have no list.
struct Adjacency {
    offsets: Vec<u32>,
    packed: Vec<u32>,
    edited: Vec<Option<Vec<u32>>>,
}

impl Adjacency {
    fn new(vertex_count: usize, faces: &[[u32; 3]]) -> Self {
        let mut offsets = vec![0u32; vertex_count + 1];
        for f in faces {
            for (k, &v) in f.iter().enumerate() {
                if !f[..k].contains(&v) {
                    offsets[v as usize + 1] += 1;
                }
            }
        }
        for v in 0..vertex_count {
            offsets[v + 1] += offsets[v];
        }
        let mut fill = offsets.clone();
        let mut packed = vec![0u32; offsets[vertex_count] as usize];
        for (face, f) in faces.iter().enumerate() {
            for (k, &v) in f.iter().enumerate() {
                if !f[..k].contains(&v) {
                    packed[fill[v as usize] as usize] = face as u32;
                    fill[v as usize] += 1;
                }
            }
        }
        Self { offsets, packed, edited: (0..vertex_count).map(|_| None).collect() }
    }

    fn faces_of(&self, v: u32) -> &[u32] {
        match self.edited.get(v as usize) {
            Some(Some(list)) => list,
            _ => {
                let v = v as usize;
                &self.packed[self.offsets[v] as usize..self.offsets[v + 1] as usize]
            }
        }
    }

    fn edit(&mut self, v: u32) -> &mut Vec<u32> {
        let v = v as usize;
        if self.edited.len() <= v {
            self.edited.resize_with(v + 1, || Some(Vec::new()));
        }
        if self.edited[v].is_none() {
            let base = self.packed[self.offsets[v] as usize..self.offsets[v + 1] as usize].to_vec();
            self.edited[v] = Some(base);
        }
        self.edited[v].get_or_insert_with(Vec::new)
    }
}

struct Refiner<'a> {
    /// The groups of vertices that share a position (`None`: every vertex is its own), new
    /// vertices included.
    weld: Option<Weld>,
    positions: &'a mut Vec<Vec3>,
    faces: &'a mut Vec<[u32; 3]>,
    max_edge_sq: f32,
    region: &'a dyn RefineRegion,
    adjacency: Option<Adjacency>,
    log: Refinement,
    /// Face slots overwritten, with their earlier value, in order.
    undo: Vec<(u32, [u32; 3])>,
    /// Base faces none of whose edges may be split.
    held_back: &'a HashSet<u32>,
}

/// An undirected edge between two groups of vertices (each named by its first vertex), ordered by
/// (squared length, low index, high index): a strict total order, so ties between equal lengths
/// break the same way every run.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
struct EdgeKey {
    length_sq: f32,
    lo: u32,
    hi: u32,
}

impl Refiner<'_> {
    fn corners(&self, f: u32) -> [Vec3; 3] {
        self.faces[f as usize].map(|v| self.positions[v as usize])
    }

    fn degenerate(face: [u32; 3]) -> bool {
        face[0] == face[1] || face[1] == face[2] || face[2] == face[0]
    }

    /// The group of vertex `v`: the first vertex at its position.
    fn group(&self, v: u32) -> u32 {
        self.weld.as_ref().map_or(v, |w| w.canonical(v))
    }

    /// `face` with each corner replaced by its group.
    fn welded(&self, face: [u32; 3]) -> [u32; 3] {
        face.map(|v| self.group(v))
    }

    fn edge(&self, a: u32, b: u32) -> EdgeKey {
        let (a, b) = (self.group(a), self.group(b));
        let length_sq = self.positions[a as usize].distance_squared(self.positions[b as usize]);
        EdgeKey { length_sq, lo: a.min(b), hi: a.max(b) }
    }

    fn longest(&self, f: u32) -> EdgeKey {
        let [a, b, c] = self.faces[f as usize];
        let edges = [self.edge(a, b), self.edge(b, c), self.edge(c, a)];
        let mut best = edges[0];
        for e in &edges[1..] {
            if e.partial_cmp(&best) == Some(std::cmp::Ordering::Greater) {
                best = *e;
            }
        }
        best
    }

    /// Whether face `f` touches the region with an edge longer than allowed.
    fn needs(&self, f: u32) -> bool {
        let face = self.faces[f as usize];
        !Self::degenerate(self.welded(face))
            && self.longest(f).length_sq > self.max_edge_sq
            && self.region.touches(self.corners(f))
    }

    /// Refines until no face in the queue needs it; `Err` when the cap is passed.
    fn run(&mut self, mut queue: VecDeque<u32>, max_new_triangles: usize) -> Result<(), ()> {
        let base_faces = self.log.base_face_count;
        while let Some(f) = queue.pop_front() {
            if !self.needs(f) {
                continue;
            }
            let edge = self.terminal_edge(f);
            if self.holds_back(edge) {
                continue; // f stays as it is
            }
            let changed = self.split(edge);
            if self.faces.len() - base_faces > max_new_triangles || self.positions.len() >= u32::MAX as usize {
                return Err(());
            }
            queue.push_back(f);
            queue.extend(changed);
        }
        Ok(())
    }

    /// The faces (non-degenerate) on the edge between groups `lo` and `hi`, on every side of a
    /// seam, ascending.
    fn faces_on(&self, lo: u32, hi: u32) -> Vec<u32> {
        let adjacency = self.adjacency.as_ref().expect("adjacency is built before splitting");
        let mut on: Vec<u32> = adjacency
            .faces_of(lo)
            .iter()
            .copied()
            .filter(|&f| {
                let face = self.welded(self.faces[f as usize]);
                face.contains(&hi) && !Self::degenerate(face)
            })
            .collect();
        on.sort_unstable();
        on
    }

    /// The base face that face slot `f` is (a piece of).
    fn root(&self, f: u32) -> u32 {
        match (f as usize).checked_sub(self.log.base_face_count) {
            Some(k) => self.log.face_parents[k],
            None => f,
        }
    }

    /// Whether `edge` lies on a piece of a held-back base face.
    fn holds_back(&self, edge: EdgeKey) -> bool {
        !self.held_back.is_empty()
            && self.faces_on(edge.lo, edge.hi).into_iter().any(|f| self.held_back.contains(&self.root(f)))
    }

    /// The base faces whose pieces cross although they did not (see `refine_crossings`).
    fn crossings_made(&self) -> Vec<u32> {
        let mut originals = HashMap::new();
        for &(slot, face) in &self.undo {
            if (slot as usize) < self.log.base_face_count {
                originals.entry(slot).or_insert(face);
            }
        }
        let pieces = Pieces {
            base_vertex_count: self.log.base_vertex_count,
            base_face_count: self.log.base_face_count,
            face_parents: &self.log.face_parents,
            originals: &originals,
        };
        crossings_made(self.positions, self.faces, &pieces)
    }

    /// The end of face `f`'s longest-edge propagation path: an edge that is the longest of every
    /// face on it.
    fn terminal_edge(&self, f: u32) -> EdgeKey {
        let mut edge = self.longest(f);
        loop {
            let longer = self
                .faces_on(edge.lo, edge.hi)
                .into_iter()
                .map(|n| self.longest(n))
                .find(|e| e.partial_cmp(&edge) == Some(std::cmp::Ordering::Greater));
            match longer {
                Some(next) => edge = next,
                None => return edge,
            }
        }
    }

    /// Bisects `edge` and every face on it, with one new vertex for each side of a seam (all at
    /// one position); returns the faces changed or added.
    fn split(&mut self, edge: EdgeKey) -> Vec<u32> {
        let (lo, hi) = (edge.lo, edge.hi);
        let on = self.faces_on(lo, hi);
        // Halving first cannot overflow, so finite ends give a finite midpoint; every side's
        // new vertex is computed from the groups' own positions, so all are bit-identical.
        let midpoint = self.positions[lo as usize] * 0.5 + self.positions[hi as usize] * 0.5;
        let mut sides: Vec<([u32; 2], u32)> = Vec::with_capacity(2);
        let mut changed = Vec::with_capacity(2 * on.len());
        let mut middle = Vec::with_capacity(2 * on.len());
        for slot in on {
            let face = self.faces[slot as usize];
            let welded = self.welded(face);
            // k: the corner where the edge starts in this face's winding.
            let k = (0..3).find(|&k| {
                let (a, b) = (welded[k], welded[(k + 1) % 3]);
                (a == lo && b == hi) || (a == hi && b == lo)
            });
            let Some(k) = k else { continue };
            let m = self.side_vertex(&mut sides, [face[k], face[(k + 1) % 3]], lo, midpoint);
            let (b, c) = (face[(k + 1) % 3], face[(k + 2) % 3]);
            let mut kept = face;
            kept[(k + 1) % 3] = m;
            let mut added = face;
            added[k] = m;
            let new = self.faces.len() as u32;
            self.undo.push((slot, face));
            self.faces[slot as usize] = kept;
            self.faces.push(added);
            let s = slot as usize;
            let root = if s < self.log.base_face_count {
                self.log.split_faces.push(slot);
                slot
            } else {
                self.log.face_parents[s - self.log.base_face_count]
            };
            self.log.face_parents.push(root);
            let (b, c) = (self.group(b), self.group(c));
            let adjacency = self.adjacency.as_mut().expect("adjacency is built before splitting");
            let list = adjacency.edit(b);
            if let Some(at) = list.iter().position(|&x| x == slot) {
                list.remove(at);
            }
            list.push(new);
            adjacency.edit(c).push(new);
            middle.extend([slot, new]);
            changed.extend([slot, new]);
        }
        if let Some(&(_, first)) = sides.first() {
            *self.adjacency.as_mut().expect("adjacency is built before splitting").edit(first) = middle;
        }
        changed
    }

    /// The new vertex at `midpoint` on the side of the edge whose ends are the vertices `ends`
    /// (`lo` the group of one of them): the one made for these ends already, or a new one
    /// (recorded with its parents, in the group of the split's first new vertex).
    fn side_vertex(&mut self, sides: &mut Vec<([u32; 2], u32)>, ends: [u32; 2], lo: u32, midpoint: Vec3) -> u32 {
        let key = [ends[0].min(ends[1]), ends[0].max(ends[1])];
        if let Some(&(_, m)) = sides.iter().find(|(k, _)| *k == key) {
            return m;
        }
        let m = self.positions.len() as u32;
        self.positions.push(midpoint);
        let parents = if self.group(ends[0]) == lo { ends } else { [ends[1], ends[0]] };
        self.log.vertices.push(SplitVertex { parents, fraction: 0.5 });
        let group = sides.first().map_or(m, |&(_, first)| first);
        if let Some(weld) = self.weld.as_mut() {
            weld.push(group);
        }
        sides.push((key, m));
        m
    }

    /// Undoes every split: the parts are as they were given.
    fn roll_back(&mut self) {
        for &(slot, face) in self.undo.iter().rev() {
            self.faces[slot as usize] = face;
        }
        self.faces.truncate(self.log.base_face_count);
        self.positions.truncate(self.log.base_vertex_count);
        if let Some(weld) = self.weld.as_mut() {
            weld.truncate(self.log.base_vertex_count);
        }
    }
}

/// Squared distance from `p` to the solid triangle `t`: to its plane when `p` projects inside
/// it, else to the nearest of its three sides.
fn distance_sq_to_triangle(p: Vec3, t: [Vec3; 3]) -> f32 {
    let normal = (t[1] - t[0]).cross(t[2] - t[0]);
    let area_sq = normal.length_squared();
    if area_sq > 0.0 {
        // p projects inside when it lies on the inner side of every edge's plane.
        let inside = (0..3).all(|k| (t[(k + 1) % 3] - t[k]).cross(p - t[k]).dot(normal) >= 0.0);
        if inside {
            let height = (p - t[0]).dot(normal);
            return height * height / area_sq;
        }
    }
    (0..3).map(|k| distance_sq_to_segment(p, t[k], t[(k + 1) % 3])).fold(f32::INFINITY, f32::min)
}

/// Squared distance from `p` to the segment `a`–`b`.
fn distance_sq_to_segment(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let ab = b - a;
    let length_sq = ab.length_squared();
    let t = if length_sq > 0.0 { ((p - a).dot(ab) / length_sq).clamp(0.0, 1.0) } else { 0.0 };
    p.distance_squared(a + ab * t)
}
