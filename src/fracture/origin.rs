//! Where the vertices of a fracture's rest and pieces came from on the mesh that broke, and
//! the output meshes built from the cut's indexed faces.
//!
//! The cut runs on the welded mesh. A mesh that has no coincident vertices (one built for
//! simulation) gives welded output, as it came in. A mesh with split vertices (a game asset:
//! hard edges, UV seams) gives output split the same way: a point of the surface is one vertex
//! per side of each of the input's seams, and every cap (a cut face) has vertices of its own, so
//! its rim is a hard edge and its attributes can differ from the surface's (unless welded output
//! is asked for: `FractureRecord::weld_output`, how version-1 damage files broke). Surface vertices
//! take their normals from the input's (interpolated in the face they lie in); cap vertices the
//! cap's plane. [`VertexOrigin`] tells the caller where each vertex lies, so that UVs and other
//! attributes can be carried over.

use glam::{DVec3, Vec3};

use super::FractureError;
use super::outgoing::Outgoing;
use crate::mesh::TriMesh;

/// A point of the broken mesh's surface: one of its faces and the point's barycentric weights
/// of that face's three corners (non-negative, summing to 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// Index into the broken mesh's faces.
    pub face: u32,
    /// Weights of `faces()[face]`'s corners, in order.
    pub weights: [f32; 3],
}

/// Where a vertex of a fracture's rest or piece lies on the mesh that broke, for carrying
/// vertex attributes (UVs, colours, tangents, joint weights) over from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VertexOrigin {
    /// On the broken mesh's surface, at this point: interpolate the attributes of its face's
    /// corners with its weights.
    Surface(SurfacePoint),
    /// On a cut (inside the broken body).
    Cut {
        /// The cut's plane's unit normal, out of this mesh (mesh coordinates): the same for
        /// every vertex of one cut, so a projection on it (UVs) is seamless across the cut.
        normal: Vec3,
        /// The surface point nearest to it on the same mesh, whose attributes it can take
        /// where a cut has none of its own (colours, joint weights); `None` for a piece that is
        /// all cut.
        nearest: Option<SurfacePoint>,
    },
}

/// Where a cut's vertex lies on the welded input, as far as its splits can tell: at a welded
/// vertex, on the edge between two (lower id first), or elsewhere (inside a face, on a cap).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Location {
    Vertex(u32),
    Edge(u32, u32),
    Elsewhere,
}

impl Location {
    /// Where the point made on the segment between points at `a` and `b` lies: on an input
    /// edge when both ends are on it (its end vertices or points of it), elsewhere otherwise.
    /// Edges between two input vertices are always input edges: cuts join new points only.
    pub(crate) fn between(a: Self, b: Self) -> Self {
        use Location::{Edge, Elsewhere, Vertex};
        let edge = |p: u32, q: u32| Edge(p.min(q), p.max(q));
        match (a, b) {
            (Vertex(p), Vertex(q)) => edge(p, q),
            (Vertex(v), Edge(p, q)) | (Edge(p, q), Vertex(v)) if v == p || v == q => Edge(p, q),
            (Edge(p, q), Edge(r, s)) if (p, q) == (r, s) => Edge(p, q),
            _ => Elsewhere,
        }
    }
}

/// Marks a face origin as a cap: `CAP | k` is the part's cap `k`; other origins are faces of
/// the welded input.
pub(crate) const CAP: u32 = 1 << 31;

/// The input as the output builder needs it: the mesh that broke, which input face each welded
/// face is, which welded vertex each input vertex is, and whether the output keeps the input's
/// seams (some input vertices were welded, and welded output was not asked for).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Source<'a> {
    pub mesh: &'a TriMesh,
    pub input_face: &'a [u32],
    pub welded: &'a [u32],
    pub seams: bool,
}

/// Which output vertex a corner of the cut's faces becomes, besides its position: in welded
/// output every corner at a position is one vertex; with seams, corners share a vertex only
/// when they are on the same side of every input seam (the same input vertex, the same pair
/// of input vertices along an edge, or inside the same input face), or on the same cap.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    Vertex(u32),
    Edge(u32, u32),
    Face(u32),
    Cap(u32),
}

/// An output mesh of `faces` over the pool's `positions` (f64, m) and `locations`, `from`
/// giving each face's origin (a welded input face, or `CAP | k` for the cap whose outward
/// normal is `cap_normals[k]`), with the origin of each of its vertices. Vertices are numbered
/// in order of first use; deterministic.
///
/// # Errors
/// [`FractureError::Mesh`] when there is no face (or a coordinate leaves the mesh range).
pub(crate) fn build(
    source: &Source,
    (positions, locations): (&[DVec3], &[Location]),
    (faces, from): (&[[u32; 3]], &[u32]),
    cap_normals: &[DVec3],
) -> Result<(TriMesh, Vec<VertexOrigin>), FractureError> {
    let cut = |origin: u32| {
        let normal = cap_normals.get((origin & !CAP) as usize).map_or(Vec3::ZERO, |n| n.as_vec3());
        VertexOrigin::Cut { normal, nearest: None }
    };
    // Per pool vertex: its newest output vertex (`u32::MAX`: none); per output vertex, the one
    // before it at the same pool vertex, so that a lookup walks that short chain (welded
    // output has one output vertex per pool vertex: no chain, no sides).
    let mut newest = vec![u32::MAX; positions.len()];
    let mut before: Vec<u32> = Vec::with_capacity(positions.len());
    let mut sides: Vec<Side> = Vec::new();
    let mut pool_of: Vec<u32> = Vec::new();
    let mut origins: Vec<VertexOrigin> = Vec::new();
    let mut out_faces = Vec::with_capacity(faces.len());
    let surface = |origin: u32, v: u32| {
        VertexOrigin::Surface(surface_point(source, origin, (locations[v as usize], positions[v as usize])))
    };
    for (face, &origin) in faces.iter().zip(from) {
        let on_surface = origin & CAP == 0;
        out_faces.push(face.map(|v| {
            let mut id = newest[v as usize];
            let side = source.seams.then(|| side_of(source, locations[v as usize], origin));
            if let Some(side) = side {
                while id != u32::MAX && sides[id as usize] != side {
                    id = before[id as usize];
                }
            }
            if id == u32::MAX {
                id = origins.len() as u32;
                // Welded output makes one vertex per pool vertex: its chain is empty.
                before.push(newest[v as usize]);
                sides.extend(side);
                newest[v as usize] = id;
                pool_of.push(v);
                origins.push(if on_surface { surface(origin, v) } else { cut(origin) });
            } else if on_surface && matches!(origins[id as usize], VertexOrigin::Cut { .. }) {
                // Welded output: a rim vertex is on the surface too.
                origins[id as usize] = surface(origin, v);
            }
            id
        }));
    }
    let out_positions: Vec<Vec3> = pool_of.iter().map(|&v| positions[v as usize].as_vec3()).collect();
    fill_nearest(&mut origins, &out_faces, (&pool_of, &newest, &before));
    let mesh = if source.seams {
        let normals = normals(source, &origins);
        TriMesh::with_normals(out_positions, out_faces, normals)?
    } else {
        TriMesh::new(out_positions, out_faces)?
    };
    Ok((mesh, origins))
}

/// The side a corner at a point at `location` of a face of `origin` is on (output with seams).
fn side_of(source: &Source, location: Location, origin: u32) -> Side {
    if origin & CAP != 0 {
        return Side::Cap(origin & !CAP);
    }
    let face = source.input_face[origin as usize];
    let corners = source.mesh.faces()[face as usize];
    let corner_at = |w: u32| corners.iter().copied().find(|&c| source.welded[c as usize] == w);
    match location {
        Location::Vertex(w) => corner_at(w).map_or(Side::Face(face), Side::Vertex),
        Location::Edge(p, q) => match (corner_at(p), corner_at(q)) {
            (Some(a), Some(b)) => Side::Edge(a.min(b), a.max(b)),
            _ => Side::Face(face),
        },
        Location::Elsewhere => Side::Face(face),
    }
}

/// The point at `location`, `p`, as a point of the input face that welded face `origin` is:
/// its barycentric weights, clamped to the face and summing to 1 (the first corner's for a
/// degenerate face). A point at an input vertex (most of them) is that corner's alone, and one
/// on an input edge is weighed along that edge only.
fn surface_point(source: &Source, origin: u32, (location, p): (Location, DVec3)) -> SurfacePoint {
    let face = source.input_face[origin as usize];
    let corners = source.mesh.faces()[face as usize];
    let corner_of = |w: u32| corners.iter().position(|&c| source.welded[c as usize] == w);
    let at = |k: usize| source.mesh.positions()[corners[k] as usize].as_dvec3();
    let mut weights = [0.0f32; 3];
    match location {
        Location::Vertex(w) => {
            if let Some(k) = corner_of(w) {
                weights[k] = 1.0;
                return SurfacePoint { face, weights };
            }
        }
        Location::Edge(a, b) => {
            if let (Some(i), Some(j)) = (corner_of(a), corner_of(b)) {
                let (pa, pb) = (at(i), at(j));
                let t = ((p - pa).dot(pb - pa) / (pb - pa).length_squared()).clamp(0.0, 1.0);
                if t.is_finite() {
                    weights[i] = (1.0 - t) as f32;
                    weights[j] = t as f32;
                    return SurfacePoint { face, weights };
                }
            }
        }
        Location::Elsewhere => {}
    }
    let (a, b, c) = (at(0), at(1), at(2));
    let (e0, e1, d) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (e0.dot(e0), e0.dot(e1), e1.dot(e1));
    let (d20, d21) = (d.dot(e0), d.dot(e1));
    let denominator = d00 * d11 - d01 * d01;
    let weights = if denominator > f64::MIN_POSITIVE * 1e6 {
        let v = (d11 * d20 - d01 * d21) / denominator;
        let w = (d00 * d21 - d01 * d20) / denominator;
        let clamped = [1.0 - v - w, v, w].map(|x| x.max(0.0));
        let sum: f64 = clamped.iter().sum();
        if sum > 0.0 { clamped.map(|x| (x / sum) as f32) } else { [1.0, 0.0, 0.0] }
    } else {
        [1.0, 0.0, 0.0]
    };
    SurfacePoint { face, weights }
}

/// Gives every cut vertex its nearest surface point: a surface vertex at the same point when
/// there is one (a cap's rim, nearly every cut vertex), otherwise the surface vertex fewest
/// edges away over the mesh's `faces` (a cut vertex inside the body, where cuts meet; each
/// face's edges lead on round it, so every vertex of a connected mesh is reached).
fn fill_nearest(origins: &mut [VertexOrigin], faces: &[[u32; 3]], (pool_of, newest, before): (&[u32], &[u32], &[u32])) {
    let mut inside = Vec::new();
    for k in 0..origins.len() {
        if !matches!(origins[k], VertexOrigin::Cut { .. }) {
            continue;
        }
        let mut id = newest[pool_of[k] as usize];
        let mut rim = None;
        while id != u32::MAX {
            if let VertexOrigin::Surface(point) = origins[id as usize] {
                rim = Some(point);
                break;
            }
            id = before[id as usize];
        }
        match rim {
            Some(point) => set_nearest(&mut origins[k], point),
            None => inside.push(k),
        }
    }
    if inside.is_empty() {
        return;
    }
    let graph = Graph { edges: Outgoing::of(faces, origins.len()), pool_of, newest, before };
    // Each search marks what it saw with its own number: one array for all of them.
    let mut seen = vec![0u32; origins.len()];
    for (search, k) in inside.into_iter().enumerate() {
        if let Some(point) = nearest_surface(origins, &graph, (k, search as u32 + 1), &mut seen) {
            set_nearest(&mut origins[k], point);
        }
    }
}

/// How a search walks an output mesh: along its faces' edges, and between the copies of one
/// pool vertex (a seam's sides, caps that meet inside the body).
struct Graph<'a> {
    edges: Outgoing,
    pool_of: &'a [u32],
    newest: &'a [u32],
    before: &'a [u32],
}

impl Graph<'_> {
    /// The vertices one step from `v`: its edges' ends, then its copies.
    fn steps(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        let first = self.newest[self.pool_of[v as usize] as usize];
        let copies = std::iter::successors((first != u32::MAX).then_some(first), |&c| {
            let next = self.before[c as usize];
            (next != u32::MAX).then_some(next)
        });
        self.edges.from(v).iter().copied().chain(copies)
    }
}

/// Records `point` as a cut vertex's nearest surface point.
fn set_nearest(origin: &mut VertexOrigin, point: SurfacePoint) {
    if let VertexOrigin::Cut { nearest, .. } = origin {
        *nearest = Some(point);
    }
}

/// The surface point of the surface vertex fewest edges from vertex `from`, or of the cut
/// vertex nearest it that has one already (a rim's copy: with seams, a cap shares no vertex
/// with the surface), breadth first over the faces' edges and between copies of one point
/// (deterministic), marking what it sees in `seen` with `mark`; `None` when its part of the
/// mesh has none.
fn nearest_surface(
    origins: &[VertexOrigin],
    graph: &Graph,
    (from, mark): (usize, u32),
    seen: &mut [u32],
) -> Option<SurfacePoint> {
    seen[from] = mark;
    let mut queue = std::collections::VecDeque::from([from as u32]);
    while let Some(v) = queue.pop_front() {
        for w in graph.steps(v) {
            if std::mem::replace(&mut seen[w as usize], mark) == mark {
                continue;
            }
            match origins[w as usize] {
                VertexOrigin::Surface(point) | VertexOrigin::Cut { nearest: Some(point), .. } => return Some(point),
                VertexOrigin::Cut { nearest: None, .. } => queue.push_back(w),
            }
        }
    }
    None
}

/// Normals of output with seams: a surface vertex's interpolated from the input's in its face,
/// a cut vertex's its cap's plane's.
fn normals(source: &Source, origins: &[VertexOrigin]) -> Vec<Vec3> {
    let input = source.mesh.normals();
    let normal = |origin: &VertexOrigin| match origin {
        VertexOrigin::Surface(point) => {
            let corners = source.mesh.faces()[point.face as usize];
            (0..3).map(|k| input[corners[k] as usize] * point.weights[k]).sum::<Vec3>().normalize_or_zero()
        }
        VertexOrigin::Cut { normal, .. } => *normal,
    };
    origins.iter().map(normal).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on one input edge stay on it, whatever order they were made in; anything else
    /// leaves it.
    #[test]
    fn locations_follow_input_edges() {
        use Location::{Edge, Elsewhere, Vertex};
        let on = Location::between(Vertex(7), Vertex(3));
        assert_eq!(on, Edge(3, 7));
        assert_eq!(Location::between(Vertex(3), on), Edge(3, 7));
        assert_eq!(Location::between(on, Edge(3, 7)), Edge(3, 7));
        assert_eq!(Location::between(Vertex(4), on), Elsewhere);
        assert_eq!(Location::between(on, Edge(3, 8)), Elsewhere);
        assert_eq!(Location::between(Elsewhere, Vertex(3)), Elsewhere);
    }
}
