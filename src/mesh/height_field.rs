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
//!    needs no manifold mesh) is one closed loop of single edges, each wound counter-clockwise
//!    about the loop's vertex centroid `c`, going around `c` once.
//!
//! By 2 the loop is a polygon star-shaped about `c`: simple, winding once about the points
//! inside it and never about those outside. For a point `y` off the projected edges, the
//! faces whose projections hold `y` (each counted +1 by 1) number the loop's winding about `y`
//! (the boundary of a sum of faces winds about `y` as often as they cover it): 0 or 1. So the
//! projected faces have disjoint interiors. Each face projects one-to-one, its relative
//! interior onto its projection's interior; two faces that cross (their relative interiors
//! share a point, or they overlap in an area) would have projections whose interiors overlap.
//! So two faces of a certified patch meet only where their boundaries do: they touch and do
//! not cross, which is what [`triangles_cross`] decides too.
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

/// Labels for the faces `candidates` and `around` (faces of `faces` at `positions`): the
/// candidates' connected patches (faces joined through a shared vertex) that are certified
/// (module documentation) are numbered, 0 for the largest, counting up as the patches shrink,
/// and their faces get that number; the others [`UNCERTIFIED`]. Only the [`MAX_PATCHES`]
/// largest patches of at least [`MIN_PATCH_FACES`] faces are tried. Each is tried first
/// together with its ring, the faces of `around` that share a vertex with it (then those get
/// its number too: no pair of the patch and its ring crosses either), and alone if that fails.
pub(crate) fn certified_patches(
    positions: &[Vec3],
    faces: &[[u32; 3]],
    candidates: &[u32],
    around: &[u32],
) -> (Vec<u32>, Vec<u32>) {
    let mut local = LocalVertices::new(positions.len());
    local.add_corners(faces, candidates);
    let vertex_roots = patch_roots(&local, faces, candidates);
    let root_of = |f: u32| vertex_roots[local.of(faces[f as usize][0])];
    let roots: Vec<u32> = candidates.iter().map(|&f| root_of(f)).collect();
    // The patch each face of `around` touches first, if any; then their other corners numbered.
    let ring_roots: Vec<u32> = around
        .iter()
        .map(|&f| {
            let touching = faces[f as usize].into_iter().find_map(|v| local.get(v));
            touching.map_or(NONE, |k| vertex_roots[k])
        })
        .collect();
    let ring: Vec<u32> = around.iter().zip(&ring_roots).filter(|(_, r)| **r != NONE).map(|(&f, _)| f).collect();
    local.add_corners(faces, &ring);
    let mut sizes = vec![0usize; vertex_roots.len()];
    roots.iter().for_each(|&r| sizes[r as usize] += 1);
    let mut tried: Vec<u32> = (0..sizes.len() as u32).filter(|&r| sizes[r as usize] >= MIN_PATCH_FACES).collect();
    tried.sort_unstable_by_key(|&r| std::cmp::Reverse(sizes[r as usize]));
    tried.truncate(MAX_PATCHES);
    let mut labels = (vec![UNCERTIFIED; candidates.len()], vec![UNCERTIFIED; around.len()]);
    let mut next_label = 0;
    for root in tried {
        let members: Vec<usize> = (0..candidates.len()).filter(|&k| roots[k] == root).collect();
        let ring_members: Vec<usize> = (0..around.len()).filter(|&k| ring_roots[k] == root).collect();
        let patch: Vec<u32> = members.iter().map(|&k| candidates[k]).collect();
        let with_ring: Vec<u32> = patch.iter().copied().chain(ring_members.iter().map(|&k| around[k])).collect();
        let ring_too = !ring_members.is_empty() && is_embedded(positions, faces, &with_ring, &local);
        if ring_too || is_embedded(positions, faces, &patch, &local) {
            members.iter().for_each(|&k| labels.0[k] = next_label);
            if ring_too {
                ring_members.iter().for_each(|&k| labels.1[k] = next_label);
            }
            next_label += 1;
        }
    }
    labels
}

/// The label of a face in no certified patch.
pub(crate) const UNCERTIFIED: u32 = u32::MAX;

/// For each numbered vertex, one that stands for its connected patch among the faces
/// `chosen` (whose corners are all numbered).
fn patch_roots(local: &LocalVertices, faces: &[[u32; 3]], chosen: &[u32]) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..local.len() as u32).collect();
    fn root(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            let up = parent[parent[x as usize] as usize];
            parent[x as usize] = up;
            x = up;
        }
        x
    }
    for &f in chosen {
        let [a, b, c] = faces[f as usize].map(|v| local.of(v) as u32);
        for other in [b, c] {
            let (ra, ro) = (root(&mut parent, a), root(&mut parent, other));
            parent[ra.max(ro) as usize] = ra.min(ro);
        }
    }
    (0..parent.len() as u32).map(|x| root(&mut parent, x)).collect()
}

/// Whether the faces `patch` are certified embedded (conditions 1 and 2 of the module
/// documentation); `local` numbers (at least) their vertices.
fn is_embedded(positions: &[Vec3], faces: &[[u32; 3]], patch: &[u32], local: &LocalVertices) -> bool {
    let normal: DVec3 = patch
        .iter()
        .map(|&f| {
            let [a, b, c] = faces[f as usize].map(|v| positions[v as usize].as_dvec3());
            (b - a).cross(c - a)
        })
        .sum();
    let axis = normal.abs().max_position();
    if normal[axis] == 0.0 {
        return false;
    }
    // The two other coordinates, in the order that makes (u, v, e) right-handed, swapped when
    // the patch faces −e: counter-clockwise then means facing the patch's side.
    let (mut u, mut v) = ((axis + 1) % 3, (axis + 2) % 3);
    if normal[axis] < 0.0 {
        std::mem::swap(&mut u, &mut v);
    }
    let flat = |x: u32| {
        let p = positions[x as usize];
        [f64::from(p[u]), f64::from(p[v])]
    };
    let wound = patch.iter().all(|&f| {
        let [a, b, c] = faces[f as usize].map(flat);
        orient2d(a, b, c) > 0
    });
    if !wound {
        return false;
    }
    let Some(boundary) = boundary_edges(faces, patch, local) else {
        return false;
    };
    let Some(loop_vertices) = single_loop(&boundary, local) else {
        return false;
    };
    let centre = loop_vertices.iter().map(|&x| flat(x)).fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]]);
    let centre = centre.map(|s| s / loop_vertices.len() as f64);
    let mut turned = 0.0;
    for &(a, b) in &boundary {
        let (pa, pb) = (flat(a), flat(b));
        if orient2d(centre, pa, pb) <= 0 {
            return false;
        }
        let (ra, rb) = ([pa[0] - centre[0], pa[1] - centre[1]], [pb[0] - centre[0], pb[1] - centre[1]]);
        turned += (ra[0] * rb[1] - ra[1] * rb[0]).atan2(ra[0] * rb[0] + ra[1] * rb[1]);
    }
    // Each edge turns by an angle in (0, π), so the total is a whole number of turns.
    (turned - std::f64::consts::TAU).abs() < std::f64::consts::PI
}

/// The patch's boundary chain as directed edges, each once; `None` when an edge is left over
/// more than once in one direction (the chain is not a set of single edges).
fn boundary_edges(faces: &[[u32; 3]], patch: &[u32], local: &LocalVertices) -> Option<Vec<(u32, u32)>> {
    // Every directed edge filed under its smaller end (compressed rows), with +1 when it runs
    // from the smaller end and −1 otherwise.
    let mut starts = vec![0u32; local.len() + 1];
    let edges = |f: u32| {
        let [a, b, c] = faces[f as usize];
        [(a, b), (b, c), (c, a)]
    };
    for &f in patch {
        for (a, b) in edges(f) {
            starts[local.of(a.min(b)) + 1] += 1;
        }
    }
    for k in 0..local.len() {
        starts[k + 1] += starts[k];
    }
    let mut fill = starts.clone();
    let mut filed = vec![(0u32, 0i32); 3 * patch.len()];
    for &f in patch {
        for (a, b) in edges(f) {
            let row = local.of(a.min(b));
            filed[fill[row] as usize] = (a.max(b), if a < b { 1 } else { -1 });
            fill[row] += 1;
        }
    }
    let mut boundary = Vec::new();
    for (row, &low) in local.vertices.iter().enumerate() {
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

/// The vertices of `edges` when they form one closed loop through distinct vertices (each
/// vertex leaving by one edge, the walk from the first edge coming back after all of them).
fn single_loop(edges: &[(u32, u32)], local: &LocalVertices) -> Option<Vec<u32>> {
    if edges.len() < 3 {
        return None;
    }
    let mut next = vec![NONE; local.len()];
    for &(a, b) in edges {
        let slot = &mut next[local.of(a)];
        if *slot != NONE {
            return None;
        }
        *slot = b;
    }
    let start = edges[0].0;
    let mut walk = Vec::with_capacity(edges.len());
    let mut at = start;
    for step in 0..edges.len() {
        walk.push(at);
        at = next[local.of(at)];
        // (With one edge out of each vertex, a walk that is back at its start after all the
        // edges, and not before, visited distinct vertices.)
        if at == NONE || (at == start) != (step + 1 == edges.len()) {
            return None;
        }
    }
    Some(walk)
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
        certified_patches(positions, faces, chosen, &[]).0.into_iter().map(|l| l != UNCERTIFIED).collect()
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
    fn a_fold_and_a_patch_with_a_hole_are_refused() {
        // A vertex pushed across its neighbours: faces turn over.
        let (mut positions, faces) = sheet(6, |_, _| 0.0);
        positions[3 * 7 + 3].x += 0.4;
        assert!(certified_patch(&positions, &faces, &all(&faces)).iter().all(|&f| !f));
        // A sheet less two middle quads: its boundary is two loops.
        let (positions, faces) = sheet(6, |_, _| 0.0);
        let holed: Vec<u32> = (0..faces.len() as u32).filter(|&f| !(28..=31).contains(&f)).collect();
        assert!(certified_patch(&positions, &faces, &holed).iter().all(|&f| !f));
    }

    /// Soundness against the exact test: dented sheets jittered enough to fold now and then,
    /// cut to random patches; no certified patch has a crossing pair, and both verdicts occur.
    #[test]
    fn no_certified_patch_has_a_crossing_pair() {
        let mut next = crate::mesh::test_support::unit_floats(11);
        let (mut certified, mut refused) = (0, 0);
        for round in 0..400 {
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
            // The faces of the largest patch, if it is certified (each patch's promise is its own).
            let (labels, _) = certified_patches(&positions, &faces, &chosen, &[]);
            let patch: Vec<u32> = chosen.iter().zip(&labels).filter(|(_, l)| **l == 0).map(|(&f, _)| f).collect();
            if patch.is_empty() {
                refused += 1;
                continue;
            }
            certified += 1;
            let corners = |f: u32| faces[f as usize].map(|v| positions[v as usize].as_dvec3());
            for (i, &f) in patch.iter().enumerate() {
                for &g in &patch[i + 1..] {
                    assert!(!triangles_cross(corners(f), corners(g)), "round {round}: faces {f} and {g} cross");
                }
            }
        }
        assert!(certified >= 100 && refused >= 100, "certified {certified}, refused {refused}");
    }

    #[test]
    fn a_sheet_folded_over_itself_past_its_boundary_is_refused() {
        // A strip whose far half is folded back over its near half (upside down, so it faces
        // −y there): the fold's faces are wound clockwise.
        let (mut positions, faces) = sheet(8, |_, _| 0.0);
        for p in positions.iter_mut().filter(|p| p.x > 0.5) {
            *p = Vec3::new(1.0 - p.x, 0.2, p.z);
        }
        assert!(certified_patch(&positions, &faces, &all(&faces)).iter().all(|&f| !f));
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
        let (labels, ring) = certified_patches(&positions, &faces, &patch, &others);
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
        let (labels, ring) = certified_patches(&positions, &faces, &patch, &others);
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
        let (labels, _) = certified_patches(&positions, &faces, &chosen, &[]);
        assert_eq!(labels[..2], [UNCERTIFIED; 2]);
        assert!(labels[2..26].iter().all(|&l| l == 1));
        assert!(labels[26..].iter().all(|&l| l == 0));
    }
}
