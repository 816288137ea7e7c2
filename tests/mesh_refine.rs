//! Local refinement (`mesh::refine`): crack-free, bounded, appending only, with exact
//! provenance, idempotent and deterministic; on a 12-triangle cube and the dense bunny.

mod common;

use std::collections::HashMap;

use common::cube12 as cube;
use dentbend::TriMesh;
use dentbend::glam::Vec3;
use dentbend::mesh::{self, Ball, OrientedBox, RefineError, RefineRegion, Refinement};

/// Faces per undirected edge.
fn edge_counts(mesh: &TriMesh) -> HashMap<(u32, u32), usize> {
    let mut counts = HashMap::new();
    for f in mesh.faces() {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            *counts.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    counts
}

/// V − E + F.
fn euler(mesh: &TriMesh) -> i64 {
    mesh.vertex_count() as i64 - edge_counts(mesh).len() as i64 + mesh.face_count() as i64
}

fn longest_edge(t: [Vec3; 3]) -> f32 {
    t[0].distance(t[1]).max(t[1].distance(t[2])).max(t[2].distance(t[0]))
}

fn corners(mesh: &TriMesh, f: usize) -> [Vec3; 3] {
    mesh.faces()[f].map(|v| mesh.positions()[v as usize])
}

/// The checks every refinement must pass: appended only, exact provenance, no split edge left
/// in any face (no T-junction), Euler characteristic and area kept, and no face that touches
/// the region left with an edge over `max_edge`, and no edge split that was not over it.
fn check(before: &TriMesh, after: &TriMesh, r: &Refinement, region: &dyn RefineRegion, max_edge: f32) {
    assert_eq!(r.base_vertex_count, before.vertex_count());
    assert_eq!(r.base_face_count, before.face_count());
    assert_eq!(after.vertex_count(), before.vertex_count() + r.added_vertices());
    assert_eq!(after.face_count(), before.face_count() + r.added_faces());
    assert_eq!(&after.positions()[..before.vertex_count()], before.positions(), "old vertices keep their place");
    let p = after.positions();
    for (k, s) in r.vertices.iter().enumerate() {
        let v = before.vertex_count() + k;
        assert!((s.parents[0] as usize) < v && (s.parents[1] as usize) < v);
        assert_eq!(s.fraction, 0.5);
        assert_eq!(p[v], p[s.parents[0] as usize] * 0.5 + p[s.parents[1] as usize] * 0.5, "vertex {v}");
        // Only edges too long are split: a surface already fine enough gains nothing.
        let split = p[s.parents[0] as usize].distance(p[s.parents[1] as usize]);
        assert!(split > max_edge, "vertex {v} halves an edge of {split}, not over {max_edge}");
    }
    let counts = edge_counts(after);
    for s in &r.vertices {
        let [a, b] = s.parents;
        assert!(!counts.contains_key(&(a.min(b), a.max(b))), "split edge {a}-{b} still used: a T-junction");
    }
    assert_eq!(euler(after), euler(before), "an edge split keeps V − E + F");
    let (area_before, area_after) = (before.area(), after.area());
    assert!((area_after - area_before).abs() <= 1e-5 * area_before, "area {area_before} → {area_after}");
    for f in 0..after.face_count() {
        let t = corners(after, f);
        if region.touches(t) {
            assert!(longest_edge(t) <= max_edge * (1.0 + 1e-6), "face {f} touches the region with a long edge");
        }
    }
    // Every piece lies in its parent's plane (the shape is unchanged, only cut).
    for (k, &parent) in r.face_parents.iter().enumerate() {
        let [a, b, c] = corners(before, parent as usize);
        let n = (b - a).cross(c - a).normalize();
        for q in corners(after, before.face_count() + k) {
            assert!((q - a).dot(n).abs() < 1e-5, "piece of face {parent} off its plane");
        }
    }
}

#[test]
fn a_cube_face_refines_closed_around_a_ball() {
    let cube = cube();
    let region = Ball { centre: Vec3::new(0.0, 1.0, 0.0), radius: 0.4 };
    let (fine, r) = mesh::refine(&cube, &region, 0.1, 100_000).unwrap();
    check(&cube, &fine, &r, &region, 0.1);
    assert!(edge_counts(&fine).values().all(|&n| n == 2), "a closed mesh stays closed");
    assert!((fine.volume() - 8.0).abs() < 1e-4, "volume {}", fine.volume());
    // A disc of radius 0.4 needs hundreds of triangles with 0.1 m edges, not the whole cube.
    assert!(r.added_faces() > 100 && r.added_faces() < 5000, "added {}", r.added_faces());
    // Faces of the bottom (y = −1) are never touched.
    for f in [4, 5] {
        assert_eq!(fine.faces()[f], cube.faces()[f]);
    }
}

#[test]
fn refinement_is_bounded_by_its_cap() {
    let cube = cube();
    let region = Ball { centre: Vec3::new(0.0, 1.0, 0.0), radius: 0.4 };
    let error = mesh::refine(&cube, &region, 0.01, 500).unwrap_err();
    assert_eq!(error, RefineError::TooManyTriangles { limit: 500, max_edge: 0.01 });
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert!(matches!(mesh::refine(&cube, &region, bad, 500), Err(RefineError::InvalidMaxEdge(_))));
    }
}

#[test]
fn refinement_is_idempotent_and_deterministic() {
    let cube = cube();
    let region = OrientedBox {
        centre: Vec3::new(0.7, 1.0, -0.6),
        axes: [Vec3::X, Vec3::Y, Vec3::Z],
        half_extents: Vec3::new(0.3, 0.2, 0.3),
    };
    let (once, r1) = mesh::refine(&cube, &region, 0.15, 100_000).unwrap();
    check(&cube, &once, &r1, &region, 0.15);
    let (again, r2) = mesh::refine(&cube, &region, 0.15, 100_000).unwrap();
    let bits = |m: &TriMesh| m.positions().iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>();
    assert_eq!(bits(&once), bits(&again));
    assert_eq!(once.faces(), again.faces());
    assert_eq!(r1, r2);
    let (twice, nothing) = mesh::refine(&once, &region, 0.15, 100_000).unwrap();
    assert!(nothing.is_empty(), "nothing is too long any more");
    assert_eq!(twice, once);
}

#[test]
fn provenance_carries_attributes_and_chains() {
    let cube = cube();
    let region = Ball { centre: Vec3::new(1.0, 1.0, 1.0), radius: 0.5 };
    let (fine, r) = mesh::refine(&cube, &region, 0.2, 100_000).unwrap();
    // An attribute linear in position (a UV from x and z) interpolates exactly.
    let uv: Vec<[f32; 2]> = cube.positions().iter().map(|p| [p.x, p.z]).collect();
    let lerp = |a: &[f32; 2], b: &[f32; 2], t: f32| [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t];
    let fine_uv = r.interpolate(&uv, lerp).unwrap();
    assert_eq!(fine_uv.len(), fine.vertex_count());
    for (p, uv) in fine.positions().iter().zip(&fine_uv) {
        assert!((p.x - uv[0]).abs() < 1e-6 && (p.z - uv[1]).abs() < 1e-6);
    }
    assert!(matches!(r.interpolate(&uv[..3], lerp), Err(RefineError::AttributeCount { expected: 8, actual: 3 })));

    // A second refinement chained onto the first describes both from the cube.
    let (finer, r2) = mesh::refine(&fine, &region, 0.1, 100_000).unwrap();
    let mut both = r.clone();
    both.extend(r2.clone()).unwrap();
    let finer_uv = both.interpolate(&uv, lerp).unwrap();
    assert_eq!(finer_uv.len(), finer.vertex_count());
    for (p, uv) in finer.positions().iter().zip(&finer_uv) {
        assert!((p.x - uv[0]).abs() < 1e-6 && (p.z - uv[1]).abs() < 1e-6);
    }
    assert!(both.face_parents.iter().all(|&f| (f as usize) < cube.face_count()));
    assert_eq!(r2.clone().extend(r), Err(RefineError::NotConsecutive));
}

#[test]
fn the_dense_bunny_refines_only_near_a_small_region() {
    let bunny = mesh::builtin("bunny-dense").unwrap();
    let top = bunny.support_point(Vec3::Y);
    let region = Ball { centre: top, radius: 0.6 };
    let mean = bunny.mean_edge_length();
    let max_edge = 0.25 * mean;
    let (fine, r) = mesh::refine(&bunny, &region, max_edge, 200_000).unwrap();
    check(&bunny, &fine, &r, &region, max_edge);
    assert!(r.added_faces() > 100, "the region must need refining (added {})", r.added_faces());
    // Local: the base faces cut are few, and all within a few edges of the ball.
    assert!(
        r.split_faces.len() < bunny.face_count() / 50,
        "{} of {} faces cut",
        r.split_faces.len(),
        bunny.face_count()
    );
    let longest = (0..bunny.face_count()).map(|f| longest_edge(corners(&bunny, f))).fold(0.0, f32::max);
    let near = Ball { centre: top, radius: 0.6 + 4.0 * longest };
    assert!(r.split_faces.iter().all(|&f| near.touches(corners(&bunny, f as usize))));
}

#[test]
fn an_oriented_box_touches_exactly() {
    let b = OrientedBox {
        centre: Vec3::ZERO,
        axes: [Vec3::new(1.0, 1.0, 0.0).normalize(), Vec3::new(-1.0, 1.0, 0.0).normalize(), Vec3::Z],
        half_extents: Vec3::splat(1.0),
    };
    let t = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| [Vec3::from(a), Vec3::from(b), Vec3::from(c)];
    assert!(b.touches(t([0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0])), "inside");
    assert!(b.touches(t([-5.0, -5.0, 0.0], [5.0, -5.0, 0.0], [0.0, 5.0, 0.0])), "a big triangle around it");
    // The box's corner along +x sits at √2; a triangle just past it does not touch.
    assert!(!b.touches(t([1.5, -1.0, 0.0], [1.5, 1.0, 0.0], [2.0, 0.0, 0.5])));
    assert!(b.touches(t([1.4, -1.0, 0.0], [1.4, 1.0, 0.0], [2.0, 0.0, 0.5])));
    // A triangle past a face of the box, its plane crossing the box's slab.
    assert!(!b.touches(t([1.2, 1.2, -3.0], [1.2, 1.2, 3.0], [3.0, 3.0, 0.0])));
    let ball = Ball { centre: Vec3::new(0.0, 0.0, 1.0), radius: 0.99 };
    assert!(!ball.touches(t([-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0])));
    assert!(Ball { radius: 1.01, ..ball }.touches(t([-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0])));
    assert!(!Ball { centre: Vec3::new(3.0, 0.0, 0.0), radius: 1.9 }.touches(t(
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [0.0, 1.0, 0.0]
    )));
}
