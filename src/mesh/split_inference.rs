//! Which edge each vertex a refinement appended bisected, told from the meshes before and
//! after an edit (a damage file's mesh edit keeps positions, not parents): an engine replaying
//! saved damage carries its vertex attributes over to the new vertices with it.
//!
//! Refinement appends a vertex at the midpoint of an edge of the mesh as it is then, in order,
//! so the edits can be followed forward: the edges of `before`, each appended vertex replacing
//! the edge it bisected by its two halves (and joining the faces' opposite corners). Its
//! parents are the current edge whose ends it can reach through vertices appended after it
//! (later splits of its halves) and whose midpoint lies nearest to it.

use std::collections::{HashSet, VecDeque};

use super::{SplitVertex, TriMesh};

/// Most vertices one search for a new vertex's parents visits.
const SEARCH_LIMIT: usize = 512;

/// The edge each vertex of `after` past `before`'s vertices bisected, in order (both parents
/// have smaller indices), for `after` made from `before` by refinement and moves (a dent),
/// indices of `before` keeping their meaning. A new vertex whose edge cannot be found (an edit
/// no refinement made) is given its first older neighbour as both parents.
pub(crate) fn infer_splits(before: &TriMesh, after: &TriMesh) -> Vec<SplitVertex> {
    let (base, count) = (before.vertex_count(), after.vertex_count());
    if count <= base {
        return Vec::new();
    }
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); count];
    for face in after.faces() {
        for k in 0..3 {
            let (a, b) = (face[k], face[(k + 1) % 3]);
            neighbours[a as usize].push(b);
            neighbours[b as usize].push(a);
        }
    }
    // The current edges, as each vertex's list of neighbours (both ways).
    let mut edges: Vec<Vec<u32>> = vec![Vec::new(); count];
    let join = |edges: &mut Vec<Vec<u32>>, a: u32, b: u32| {
        if !edges[a as usize].contains(&b) {
            edges[a as usize].push(b);
            edges[b as usize].push(a);
        }
    };
    for face in before.faces() {
        for k in 0..3 {
            join(&mut edges, face[k], face[(k + 1) % 3]);
        }
    }
    let positions = after.positions();
    // `reached[v] == m + 1`: `v` is among the vertices new vertex `m` reaches.
    let mut reached = vec![0u32; count];
    let mut splits = Vec::with_capacity(count - base);
    for m in base as u32..count as u32 {
        let older = reachable_older(&neighbours, m);
        for &v in &older {
            reached[v as usize] = m + 1;
        }
        let at = positions[m as usize];
        let mut best: Option<(f32, u32, u32)> = None;
        for &p in &older {
            for &q in edges[p as usize].iter().filter(|&&q| q > p && reached[q as usize] == m + 1) {
                let (a, b) = (positions[p as usize], positions[q as usize]);
                let length = a.distance(b);
                if length <= 0.0 {
                    continue;
                }
                let off = at.distance((a + b) * 0.5) / length;
                if best.is_none_or(|(score, x, y)| off < score || (off == score && (p, q) < (x, y))) {
                    best = Some((off, p, q));
                }
            }
        }
        let Some((_, p, q)) = best else {
            let parent = older.first().copied().unwrap_or(0);
            splits.push(SplitVertex { parents: [parent, parent], fraction: 0.0 });
            continue;
        };
        splits.push(SplitVertex { parents: [p, q], fraction: 0.5 });
        // The faces' opposite corners: older vertices joined to both ends.
        let corners: Vec<u32> = edges[p as usize]
            .iter()
            .copied()
            .filter(|&c| c != q && reached[c as usize] == m + 1 && edges[q as usize].contains(&c))
            .collect();
        edges[p as usize].retain(|&x| x != q);
        edges[q as usize].retain(|&x| x != p);
        join(&mut edges, p, m);
        join(&mut edges, m, q);
        for c in corners {
            join(&mut edges, m, c);
        }
    }
    splits
}

/// The vertices older than `m` (smaller indices) that `m` reaches through vertices newer than
/// it, nearest (fewest steps) first: at most [`SEARCH_LIMIT`] visited, enough for the chains
/// of halves a refinement makes between a vertex and its parents.
fn reachable_older(neighbours: &[Vec<u32>], m: u32) -> Vec<u32> {
    let mut seen: HashSet<u32> = HashSet::from([m]);
    let (mut queue, mut older) = (VecDeque::from([m]), Vec::new());
    while let Some(x) = queue.pop_front() {
        for &y in &neighbours[x as usize] {
            if seen.len() >= SEARCH_LIMIT || !seen.insert(y) {
                continue;
            }
            if y < m {
                older.push(y);
            } else {
                queue.push_back(y);
            }
        }
    }
    older
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::mesh::{Ball, refine, subdivided_box};

    /// A refinement several levels deep (halves of halves split again), then every vertex moved
    /// a little as a dent would: the inferred parents are the refinement's own, every one.
    #[test]
    fn a_dented_refinement_is_told_back_exactly() {
        let panel = subdivided_box(Vec3::new(1.0, 1.0, 0.1), [4, 4, 1]).unwrap();
        let region = Ball { centre: Vec3::new(0.1, 0.05, 0.05), radius: 0.3 };
        let (refined, refinement) = refine(&panel, &region, 0.04, 1 << 20).unwrap();
        assert!(refinement.vertices.len() > 100, "{} new vertices", refinement.vertices.len());
        let dented: Vec<Vec3> = refined
            .positions()
            .iter()
            .map(|&p| {
                let depth = 0.02 * (1.0 - (p - region.centre).length() / region.radius).max(0.0);
                p - Vec3::Z * depth
            })
            .collect();
        let after = TriMesh::new(dented, refined.faces().to_vec()).unwrap();
        let inferred = infer_splits(&panel, &after);
        assert_eq!(inferred.len(), refinement.vertices.len());
        for (k, (found, made)) in inferred.iter().zip(&refinement.vertices).enumerate() {
            let sorted = |s: &SplitVertex| {
                let [a, b] = s.parents;
                (a.min(b), a.max(b))
            };
            assert_eq!(sorted(found), sorted(made), "new vertex {k}");
        }
    }

    /// The same on a sphere refined five levels deep under a smooth dent as deep as the new
    /// edges are long (5 cm).
    #[test]
    fn a_deeply_refined_sphere_is_told_back_exactly() {
        let ball = crate::mesh::icosphere(1.0, 2).unwrap();
        let region = Ball { centre: Vec3::Z, radius: 0.5 };
        let (refined, refinement) = refine(&ball, &region, 0.05, 1 << 20).unwrap();
        assert!(refinement.vertices.len() > 300, "{} new vertices", refinement.vertices.len());
        let dented: Vec<Vec3> = refined
            .positions()
            .iter()
            .map(|&p| p * (1.0 - 0.05 * (1.0 - (p - Vec3::Z).length() / 0.5).max(0.0).powi(2)))
            .collect();
        let after = TriMesh::new(dented, refined.faces().to_vec()).unwrap();
        let inferred = infer_splits(&ball, &after);
        let sorted = |s: &SplitVertex| (s.parents[0].min(s.parents[1]), s.parents[0].max(s.parents[1]));
        let wrong = inferred.iter().zip(&refinement.vertices).filter(|(a, b)| sorted(a) != sorted(b)).count();
        assert_eq!(wrong, 0, "{wrong} of {} new vertices given other parents", inferred.len());
    }
}
