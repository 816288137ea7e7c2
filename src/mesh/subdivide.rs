//! Subdivision: the 1→4 midpoint split and Loop smoothing, both welding the new edge vertices so
//! that a closed mesh stays closed.

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use super::TriMesh;

/// The connectivity of one 1→4 split: the edges that received a new vertex, in creation order (the
/// vertex of `edges[i]` has index `vertex_count + i`), and the four children of every face.
pub(crate) struct Split {
    /// Undirected edges `[lo, hi]` (`lo <= hi`), one per new vertex.
    pub edges: Vec<[u32; 2]>,
    /// The split faces, four per input face, wound like their parent.
    pub faces: Vec<[u32; 3]>,
}

/// Splits every face of a mesh with `vertex_count` vertices into four, creating one vertex per
/// undirected edge (shared by both faces on that edge).
///
/// # Panics
/// If the result would need more than `u32::MAX` vertices (tens of gigabytes of input).
pub(crate) fn split_faces(vertex_count: usize, faces: &[[u32; 3]]) -> Split {
    let mut ids: HashMap<u64, u32> = HashMap::with_capacity(faces.len() * 3 / 2 + 3);
    let mut edges: Vec<[u32; 2]> = Vec::with_capacity(faces.len() * 3 / 2 + 3);
    let mut out = Vec::with_capacity(faces.len() * 4);
    for &[a, b, c] in faces {
        let mut mid = |u: u32, v: u32| -> u32 {
            let (lo, hi) = (u.min(v), u.max(v));
            *ids.entry((u64::from(lo) << 32) | u64::from(hi)).or_insert_with(|| {
                edges.push([lo, hi]);
                u32::try_from(vertex_count + edges.len() - 1).expect("subdivision needs more than u32::MAX vertices")
            })
        };
        let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
        out.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    Split { edges, faces: out }
}

/// Splits every triangle into four at its edge midpoints (4× the faces; vertices + edges vertices).
///
/// The shape is unchanged, only refined; vertices on a shared edge are welded, so a closed mesh
/// stays closed and the winding is preserved.
///
/// # Panics
/// If the result would need more than `u32::MAX` vertices.
///
/// # Example
/// ```
/// let sphere = dentbend::mesh::icosphere(1.0, 0).unwrap();
/// let fine = dentbend::mesh::subdivide_midpoint(&sphere);
/// assert_eq!(fine.face_count(), 4 * sphere.face_count());
/// ```
pub fn subdivide_midpoint(mesh: &TriMesh) -> TriMesh {
    let positions = mesh.positions();
    let split = split_faces(positions.len(), mesh.faces());
    let mut out = Vec::with_capacity(positions.len() + split.edges.len());
    out.extend_from_slice(positions);
    // Halving first cannot overflow, so finite inputs give finite midpoints.
    out.extend(split.edges.iter().map(|&[a, b]| positions[a as usize] * 0.5 + positions[b as usize] * 0.5));
    TriMesh::from_valid(out, split.faces)
}

/// One step of Loop subdivision: the 1→4 split, then every vertex moved to Loop's smoothing
/// weights (Warren's β), so repeated steps converge to a smooth surface that shrinks slightly.
///
/// An edge shared by exactly two faces is interior; any other edge (open boundary or
/// non-manifold) is a crease: new vertices on it sit at its midpoint, an old vertex with exactly
/// two crease edges follows the boundary rule (¾ itself + ⅛ each crease neighbour), and one with
/// any other number stays put. Positions are blended in f64 as convex combinations, so finite
/// inputs give finite outputs.
///
/// # Panics
/// If the result would need more than `u32::MAX` vertices.
pub fn subdivide_loop(mesh: &TriMesh) -> TriMesh {
    let positions = mesh.positions();
    let faces = mesh.faces();
    let p = |v: u32| positions[v as usize].as_dvec3();

    // Opposite vertices of every undirected edge: (number of faces, first two opposites).
    let mut opposite: HashMap<u64, (u32, [u32; 2])> = HashMap::with_capacity(faces.len() * 3 / 2 + 3);
    for &[a, b, c] in faces {
        for (u, v, w) in [(a, b, c), (b, c, a), (c, a, b)] {
            let key = (u64::from(u.min(v)) << 32) | u64::from(u.max(v));
            let entry = opposite.entry(key).or_insert((0, [w, w]));
            if entry.0 == 1 {
                entry.1[1] = w;
            }
            entry.0 += 1;
        }
    }
    let key = |[a, b]: [u32; 2]| (u64::from(a) << 32) | u64::from(b);

    let split = split_faces(positions.len(), faces);
    // Per old vertex: interior neighbour sum and count, crease neighbour sum and count.
    let mut ring = vec![(DVec3::ZERO, 0u32, DVec3::ZERO, 0u32); positions.len()];
    let mut odd = Vec::with_capacity(split.edges.len());
    for &edge in &split.edges {
        let [a, b] = edge;
        let (count, [w1, w2]) = opposite.get(&key(edge)).copied().unwrap_or((0, [a, b]));
        let interior = count == 2;
        if a != b {
            for (v, other) in [(a, b), (b, a)] {
                let r = &mut ring[v as usize];
                if interior {
                    r.0 += p(other);
                    r.1 += 1;
                } else {
                    r.2 += p(other);
                    r.3 += 1;
                }
            }
        }
        odd.push(if interior { (p(a) + p(b)) * 0.375 + (p(w1) + p(w2)) * 0.125 } else { (p(a) + p(b)) * 0.5 });
    }

    let mut out = Vec::with_capacity(positions.len() + odd.len());
    for (v, &(sum, n, crease_sum, creases)) in ring.iter().enumerate() {
        let old = positions[v].as_dvec3();
        let moved = match (creases, n) {
            (0, 0) => old,
            (0, n) => {
                let n = f64::from(n);
                let beta = if n == 3.0 { 3.0 / 16.0 } else { 3.0 / (8.0 * n) };
                old * (1.0 - n * beta) + sum * beta
            }
            (2, _) => old * 0.75 + crease_sum * 0.125,
            _ => old,
        };
        out.push(moved.as_vec3());
    }
    out.extend(odd.iter().map(|q| q.as_vec3()));
    TriMesh::from_valid(out, split.faces)
}

/// Applies [`subdivide_midpoint`] `levels` times.
pub fn subdivide_midpoint_n(mesh: &TriMesh, levels: u32) -> TriMesh {
    (0..levels).fold(mesh.clone(), |m, _| subdivide_midpoint(&m))
}

/// Positions of the new edge vertices of `split` projected onto the unit sphere (icosphere
/// refinement); mirror-symmetric inputs give exactly mirror-symmetric outputs.
pub(crate) fn unit_midpoints(positions: &[Vec3], split: &Split) -> Vec<Vec3> {
    split.edges.iter().map(|&[a, b]| (positions[a as usize] + positions[b as usize]).normalize()).collect()
}
