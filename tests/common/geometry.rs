//! Geometry helpers shared by the dent tests: placing meshes and finding self-intersections.

use dentbend::glam::{Affine3A, Vec3};
use dentbend::{TriMesh, mesh};

/// The built-in unit icosphere scaled to `radius` and moved to `centre`.
pub fn sphere_at(centre: Vec3, radius: f32) -> TriMesh {
    let mut s = mesh::builtin("sphere").expect("built-in sphere");
    s.transform(Affine3A::from_scale_rotation_translation(Vec3::splat(radius), Default::default(), centre)).unwrap();
    s
}

/// Enclosed volume of a closed mesh in f64 (the library's `TriMesh::volume` sums in f32, too
/// coarse to see a small difference of two large volumes).
pub fn enclosed_volume(mesh: &TriMesh) -> f64 {
    let p = mesh.positions();
    let tetra = |f: &[u32; 3]| {
        let [a, b, c] = f.map(|v| p[v as usize].as_dvec3());
        a.dot(b.cross(c)) / 6.0
    };
    mesh.faces().iter().map(tetra).sum()
}

/// Pairs of faces that share no vertex and cross each other, among faces with at least one
/// vertex flagged in `focus` against every face. Uses a uniform hash grid on face bounds.
pub fn self_intersections(mesh: &TriMesh, focus: &[bool]) -> Vec<(usize, usize)> {
    let p = mesh.positions();
    let faces = mesh.faces();
    let bounds = |f: &[u32; 3]| {
        let [a, b, c] = f.map(|v| p[v as usize]);
        (a.min(b).min(c), a.max(b).max(c))
    };
    let cell = 2.0 * mesh.mean_edge_length();
    let key = |q: Vec3| (q / cell).floor().as_ivec3();
    let mut buckets: std::collections::HashMap<_, Vec<usize>> = Default::default();
    for (k, f) in faces.iter().enumerate() {
        let (lo, hi) = bounds(f);
        let (klo, khi) = (key(lo), key(hi));
        for x in klo.x..=khi.x {
            for y in klo.y..=khi.y {
                for z in klo.z..=khi.z {
                    buckets.entry((x, y, z)).or_default().push(k);
                }
            }
        }
    }
    let mut hits = Vec::new();
    for (i, fi) in faces.iter().enumerate() {
        if !fi.iter().any(|&v| focus[v as usize]) {
            continue;
        }
        let (lo, hi) = bounds(fi);
        let (klo, khi) = (key(lo), key(hi));
        let mut seen = std::collections::HashSet::new();
        for x in klo.x..=khi.x {
            for y in klo.y..=khi.y {
                for z in klo.z..=khi.z {
                    for &j in buckets.get(&(x, y, z)).into_iter().flatten() {
                        if j == i || !seen.insert(j) || fi.iter().any(|v| faces[j].contains(v)) {
                            continue;
                        }
                        if triangles_cross(fi.map(|v| p[v as usize]), faces[j].map(|v| p[v as usize])) {
                            hits.push((i.min(j), i.max(j)));
                        }
                    }
                }
            }
        }
    }
    hits.sort_unstable();
    hits.dedup();
    hits
}

/// True when an edge of either triangle passes through or touches the other (its interior or
/// its border: faces that share no vertex never touch in a valid closed mesh, and a dent that
/// moves vertices straight down keeps grid-aligned edges exactly above each other). Coplanar
/// contact is not counted: it has measure zero after a dent.
pub fn triangles_cross(a: [Vec3; 3], b: [Vec3; 3]) -> bool {
    let edges_hit = |t: [Vec3; 3], s: [Vec3; 3]| (0..3).any(|k| segment_hits_triangle(t[k], t[(k + 1) % 3], s));
    edges_hit(a, b) || edges_hit(b, a)
}

fn segment_hits_triangle(p: Vec3, q: Vec3, [a, b, c]: [Vec3; 3]) -> bool {
    let (p, q, a, b, c) = (p.as_dvec3(), q.as_dvec3(), a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
    let dir = q - p;
    let (e1, e2) = (b - a, c - a);
    let h = dir.cross(e2);
    let det = e1.dot(h);
    if det.abs() < 1e-14 {
        return false;
    }
    let s = p - a;
    let u = s.dot(h) / det;
    let qv = s.cross(e1);
    let v = dir.dot(qv) / det;
    let t = e2.dot(qv) / det;
    let eps = 1e-9;
    u >= -eps && v >= -eps && u + v <= 1.0 + eps && t >= -eps && t <= 1.0 + eps
}

/// A 2 m cube centred at the origin (top face y = +1): 8 vertices, 12 triangles, wound outwards
/// (the refine tests' low-poly target, with a fixed vertex and face order).
pub fn cube12() -> TriMesh {
    let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let positions = vec![
        p(-1., -1., -1.),
        p(1., -1., -1.),
        p(1., 1., -1.),
        p(-1., 1., -1.),
        p(-1., -1., 1.),
        p(1., -1., 1.),
        p(1., 1., 1.),
        p(-1., 1., 1.),
    ];
    let faces = vec![
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [3, 7, 6],
        [3, 6, 2],
        [0, 4, 7],
        [0, 7, 3],
        [1, 2, 6],
        [1, 6, 5],
    ];
    TriMesh::new(positions, faces).unwrap()
}
