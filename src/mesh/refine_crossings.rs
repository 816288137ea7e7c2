//! Whether a refinement made faces cross. A bisection midpoint is rounded to f32, so it lies
//! up to half an ulp off the edge it splits. On a smooth surface that is harmless; where the
//! surface is folded flat onto itself (two faces on one edge lying back to back, which touch and
//! do not cross), the pieces on either side of a rounded midpoint no longer lie in a common
//! plane, and their planes now meet inside both: the refinement made a crossing. Measured in
//! 1,000 random dents on `block-fine` (refinement on), three dents' refinement did this, and the
//! intersection guard, which compares a dent with the refined surface it starts from, rightly
//! took those crossings as already there.

use std::collections::HashMap;

use glam::Vec3;

use super::self_intersect::crossing_pairs_among;
use super::tri_tri::triangles_cross;

/// What a refinement changed, in terms of the base mesh it started from.
pub(crate) struct Pieces<'a> {
    /// Vertices before refinement: every index from here on is a new midpoint.
    pub base_vertex_count: usize,
    /// Faces before refinement.
    pub base_face_count: usize,
    /// The base face that appended face `base_face_count + k` is a piece of.
    pub face_parents: &'a [u32],
    /// The corners before refinement of every base face whose slot now holds a piece.
    pub originals: &'a HashMap<u32, [u32; 3]>,
}

impl Pieces<'_> {
    /// The base face that face `f` of the refined mesh is (a piece of).
    fn root(&self, f: u32) -> u32 {
        match (f as usize).checked_sub(self.base_face_count) {
            Some(k) => self.face_parents[k],
            None => f,
        }
    }
}

/// The base faces (ascending, no repeats) with a piece that crosses a piece of another base face
/// (or of itself) in the refined mesh (`positions`, `faces`) although the two base faces did not
/// cross before refinement. Empty when the refinement made no crossing.
pub(crate) fn crossings_made(positions: &[Vec3], faces: &[[u32; 3]], pieces: &Pieces<'_>) -> Vec<u32> {
    let first_new = pieces.base_vertex_count as u32;
    // Every changed or added face has a new midpoint as a corner.
    let changed: Vec<u32> =
        (0..faces.len() as u32).filter(|&f| faces[f as usize].iter().any(|&v| v >= first_new)).collect();
    if changed.is_empty() {
        return Vec::new();
    }
    // Base vertices keep their positions, so a base face's corners before are its original indices.
    let base_corners = |r: u32| {
        let face = pieces.originals.get(&r).copied().unwrap_or(faces[r as usize]);
        face.map(|v| positions[v as usize].as_dvec3())
    };
    let mut made: Vec<u32> = crossing_pairs_among(positions, faces, &changed)
        .into_iter()
        .map(|(f, g)| (pieces.root(f), pieces.root(g)))
        .filter(|&(r, s)| r == s || !triangles_cross(base_corners(r), base_corners(s)))
        .flat_map(|(r, s)| [r, s])
        .collect();
    made.sort_unstable();
    made.dedup();
    made
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::mesh::{Ball, TriMesh, refine};

    /// Four vertices of `block-fine` after 578 refined random dents (seed 18 of
    /// `tests/dent_no_crossings.rs`), as f32 bits: faces (0, 1, 2) and (0, 3, 1) lie back to back
    /// on the edge 0–1, folded flat onto each other (their normals' dot is −1 to 1e-9).
    fn fold() -> TriMesh {
        let bits: [[u32; 3]; 4] = [
            [3220459816, 1017034372, 3218754230],
            [3220129037, 1029664842, 3218830601],
            [3219930276, 1032894347, 3218832460],
            [3220130300, 1027380658, 3218756920],
        ];
        let positions = bits.iter().map(|b| Vec3::from_array(b.map(f32::from_bits))).collect();
        TriMesh::new(positions, vec![[0, 1, 2], [0, 3, 1]]).unwrap()
    }

    #[test]
    fn splitting_a_flat_fold_naively_makes_its_faces_cross() {
        // What plain bisection does to the fold: the edge 0–1 and then 0–2 halved at their
        // midpoints rounded to f32, every face on them split. This is what the refinement
        // must not leave behind.
        let fold = fold();
        assert_eq!(fold.self_intersections(), vec![]);
        let p = fold.positions();
        let mut positions = p.to_vec();
        positions.push(p[0] * 0.5 + p[1] * 0.5); // 4: on 0–1
        positions.push(p[0] * 0.5 + p[2] * 0.5); // 5: on 0–2
        let faces = vec![[0, 4, 5], [4, 1, 2], [4, 2, 5], [4, 3, 1], [0, 3, 4]];
        let split = TriMesh::new(positions, faces).unwrap();
        assert!(!split.self_intersections().is_empty(), "the captured fold must be able to fail");
    }

    #[test]
    fn refining_a_flat_fold_makes_no_crossing() {
        let fold = fold();
        let everywhere = Ball { centre: fold.positions()[0], radius: 1.0 };
        for max_edge in [0.04, 0.02, 0.01, 0.005] {
            let (fine, refinement) = refine(&fold, &everywhere, max_edge, 100_000).unwrap();
            assert_eq!(fine.self_intersections(), vec![], "max_edge {max_edge}");
            // Whatever was held back is so named, and the rest was refined.
            assert!(refinement.added_faces() > 0 || refinement.held_back == vec![0, 1], "max_edge {max_edge}");
            eprintln!("max_edge {max_edge}: +{} faces, held back {:?}", refinement.added_faces(), refinement.held_back);
        }
    }
}
