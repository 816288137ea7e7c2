//! Self-intersection checks of a [`TriMesh`]: which pairs of its faces cross, over the whole
//! mesh or around some vertices. "Cross" is decided by an f64 triangle–triangle test that treats
//! touching (along a shared edge, at a shared vertex, or a vertex resting on a face) as not
//! crossing; see [`TriMesh::self_intersections`].

use glam::Vec3;
use rayon::prelude::*;

use super::TriMesh;
use super::face_grid::{Aabb, overlapping_pairs};
use super::tri_tri::triangles_cross;

impl TriMesh {
    /// Pairs of faces `(i, j)`, `i < j`, sorted, that cross: their interiors meet transversally
    /// or, coplanar, overlap with positive area. Faces that share a vertex or an edge are
    /// reported only when they overlap beyond it (a fold flattened onto its neighbour, a fan
    /// pinched through itself); faces that merely touch are not; zero-area faces never cross.
    /// A closed, well-formed mesh has none.
    ///
    /// Decisions are made in f64 on the f32 positions: a configuration is classified as touching
    /// when it lies within the arithmetic's rounding error of touching, so a crossing deeper than
    /// about 10⁻⁹ of the faces' size is always found and a mere touch is never reported. A
    /// uniform grid over the face bounding boxes keeps the work near linear; the pair tests run
    /// on all cores.
    ///
    /// # Example
    /// ```
    /// let sphere = dentbend::mesh::builtin("sphere").unwrap();
    /// assert!(sphere.self_intersections().is_empty());
    /// ```
    pub fn self_intersections(&self) -> Vec<(u32, u32)> {
        let all: Vec<u32> = (0..self.face_count() as u32).collect();
        let mut pairs = self.crossing_pairs(&all);
        pairs.sort_unstable();
        pairs
    }

    /// Whether any two faces cross (as [`self_intersections`](Self::self_intersections)).
    pub fn has_self_intersections(&self) -> bool {
        !self.self_intersections().is_empty()
    }

    /// Pairs of crossing faces `(i, j)`, `i < j`, sorted, where `i` or `j` uses one of
    /// `vertices` (indices past the vertex count are ignored), tested against the whole mesh:
    /// the check after moving a few vertices, costing one pass over the faces plus the tests
    /// around them.
    pub fn self_intersections_near(&self, vertices: &[u32]) -> Vec<(u32, u32)> {
        let mut flags = vec![false; self.vertex_count()];
        for &v in vertices {
            if let Some(flag) = flags.get_mut(v as usize) {
                *flag = true;
            }
        }
        let active: Vec<u32> = (0..self.face_count() as u32)
            .filter(|&f| self.faces()[f as usize].iter().any(|&v| flags[v as usize]))
            .collect();
        let mut pairs = self.crossing_pairs(&active);
        pairs.iter_mut().for_each(|p| *p = (p.0.min(p.1), p.0.max(p.1)));
        pairs.sort_unstable();
        pairs
    }

    /// Crossing pairs with at least one face of `active` (no duplicates, unordered).
    fn crossing_pairs(&self, active: &[u32]) -> Vec<(u32, u32)> {
        crossing_pairs_among(self.positions(), self.faces(), active)
    }
}

/// Pairs of crossing faces of a mesh with `positions` and `faces` with at least one face of
/// `active` (no duplicates, unordered): one pass over the faces for those whose boxes reach the
/// active faces' region, a grid over those, and the exact test of the pairs whose boxes overlap.
pub(crate) fn crossing_pairs_among(positions: &[Vec3], faces: &[[u32; 3]], active: &[u32]) -> Vec<(u32, u32)> {
    let face_box = |f: u32| Aabb::of(faces[f as usize].map(|v| positions[v as usize]));
    let mut is_active = vec![false; faces.len()];
    active.iter().for_each(|&f| is_active[f as usize] = true);
    // Local numbering: the active faces first, then the others whose boxes meet their region.
    let mut local: Vec<u32> = active.to_vec();
    local.sort_unstable();
    local.dedup();
    let active_count = local.len();
    let mut boxes: Vec<Aabb> = local.iter().map(|&f| face_box(f)).collect();
    let region = boxes.iter().fold(Aabb::EMPTY, |r, b| r.union(*b));
    for f in 0..faces.len() as u32 {
        if !is_active[f as usize] {
            let b = face_box(f);
            if b.overlaps(&region) {
                local.push(f);
                boxes.push(b);
            }
        }
    }
    let candidates = overlapping_pairs(&boxes, active_count, |_, _| true);
    candidates
        .into_par_iter()
        .with_min_len(1024)
        .map(|(a, b)| (local[a as usize], local[b as usize]))
        .filter(|&(a, b)| faces_cross(positions, faces, a, b))
        .collect()
}

/// Whether faces `a` and `b` of a mesh with `positions` cross.
pub(crate) fn faces_cross(positions: &[Vec3], faces: &[[u32; 3]], a: u32, b: u32) -> bool {
    let corners = |f: u32| faces[f as usize].map(|v| positions[v as usize].as_dvec3());
    triangles_cross(corners(a), corners(b))
}
