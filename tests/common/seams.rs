//! Welding a mesh by position: the closed surface a game mesh's split vertices stand for.

use std::collections::HashMap;

use dentbend::TriMesh;
use dentbend::glam::Vec3;

/// The position key of a vertex (bits, −0 as +0).
pub fn key(p: Vec3) -> [u32; 3] {
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}

/// `mesh`'s faces with bit-equal positions welded (each vertex named by the first vertex at its
/// position), the faces that then have a corner twice (degenerate) left out.
pub fn welded_faces(mesh: &TriMesh) -> Vec<[u32; 3]> {
    let mut first: HashMap<[u32; 3], u32> = HashMap::new();
    let group: Vec<u32> =
        mesh.positions().iter().enumerate().map(|(v, &p)| *first.entry(key(p)).or_insert(v as u32)).collect();
    mesh.faces()
        .iter()
        .map(|f| f.map(|v| group[v as usize]))
        .filter(|w| w[0] != w[1] && w[1] != w[2] && w[2] != w[0])
        .collect()
}

/// Edges of `mesh`, welded by position, that do not lie between exactly two faces (degenerate
/// faces, which have a corner twice once welded, left out).
pub fn unpaired_edges(mesh: &TriMesh) -> usize {
    let mut counts: HashMap<(u32, u32), u32> = HashMap::new();
    for w in welded_faces(mesh) {
        for k in 0..3 {
            let (a, b) = (w[k], w[(k + 1) % 3]);
            *counts.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    counts.values().filter(|&&n| n != 2).count()
}
