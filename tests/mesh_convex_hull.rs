//! `TriMesh::convex_hull`: a closed, outward-wound mesh of input vertices that every input vertex
//! lies behind (within 10⁻⁹ of the box diagonal), on clouds, spheres, boxes full of
//! coplanar vertices, dented balls, far from the origin; flat input refused.

mod common;

use common::closed::assert_closed;
use common::rng::SplitMix64;
use dentbend::TriMesh;
use dentbend::glam::Vec3;
use dentbend::mesh;

/// How far in front of a hull face an input vertex may lie, as a fraction of the input's box
/// diagonal: 10× the hull's documented 10⁻¹⁰ (its steps decide at that, its final check allows
/// folds of twice it); the planes rebuilt here in f64 from f32 corners err by ~10⁻¹⁶.
const TOLERANCE: f64 = 1e-9;

/// Asserts what makes `hull` the convex hull of `input`'s vertices: closed and consistently
/// wound, outward (positive volume), its vertices input vertices, every input vertex behind
/// every face's plane within [`TOLERANCE`] of the diagonal, and V − E + F = 2.
fn assert_hull_of(hull: &TriMesh, input: &TriMesh, what: &str) {
    assert_closed(hull, what);
    let euler = hull.vertex_count() as i64 - 3 * hull.face_count() as i64 / 2 + hull.face_count() as i64;
    assert_eq!(euler, 2, "{what}: V − E + F");
    assert!(hull.volume() > 0.0, "{what}: hull wound inward (volume {})", hull.volume());
    for p in hull.positions() {
        assert!(input.positions().contains(p), "{what}: hull vertex {p} is not an input vertex");
    }
    let (lo, hi) = input.bounds();
    let slack = TOLERANCE * f64::from((hi - lo).length());
    for (f, &[a, b, c]) in hull.faces().iter().enumerate() {
        let [a, b, c] = [a, b, c].map(|v| hull.positions()[v as usize].as_dvec3());
        let normal = (b - a).cross(c - a).normalize();
        for (v, p) in input.positions().iter().enumerate() {
            let height = normal.dot(p.as_dvec3() - a);
            assert!(height <= slack, "{what}: vertex {v} is {height:e} in front of face {f} (slack {slack:e})");
        }
    }
}

/// A mesh whose only use here is its vertices: `points` with one face.
fn cloud(points: Vec<Vec3>) -> TriMesh {
    TriMesh::new(points, vec![[0, 1, 2]]).unwrap()
}

#[test]
fn random_clouds_get_their_hull() {
    let mut rng = SplitMix64::new(11);
    for (k, n) in [4usize, 5, 8, 20, 100, 1000, 5000].into_iter().enumerate() {
        let points: Vec<Vec3> = (0..n).map(|_| Vec3::from_array([(); 3].map(|_| rng.range_f32(-1.0, 1.0)))).collect();
        let input = cloud(points);
        let hull = input.convex_hull().unwrap();
        assert_hull_of(&hull, &input, &format!("cloud {k} of {n} points"));
    }
}

#[test]
fn points_on_a_sphere_are_all_kept() {
    for level in [1, 2, 4] {
        let ball = mesh::icosphere(0.12, level).unwrap();
        let hull = ball.convex_hull().unwrap();
        assert_hull_of(&hull, &ball, &format!("icosphere level {level}"));
        assert_eq!(hull.vertex_count(), ball.vertex_count(), "icosphere level {level}: every vertex is on the hull");
        // Same vertices, both closed and convex: same solid; the volumes differ by f32 rounding.
        assert!((hull.volume() - ball.volume()).abs() <= 1e-5 * ball.volume(), "icosphere level {level}: volume");
    }
    // Many segments on few rings: the rings next to the poles are tiny, three neighbours on
    // them all but in a line (a hull that decided those with a coarse tolerance folded there).
    for (segments, rings) in [(200, 32), (64, 100)] {
        let dense = mesh::uv_sphere(1.0, segments, rings).unwrap();
        assert_hull_of(&dense.convex_hull().unwrap(), &dense, &format!("uv sphere {segments} × {rings}"));
    }
}

#[test]
fn coplanar_and_collinear_vertices_stay_inside() {
    // Every face of the box is a grid of coplanar vertices, every edge a row of collinear ones.
    let size = Vec3::new(1.6, 0.5, 1.6);
    let block = mesh::subdivided_box(size, [32, 10, 32]).unwrap();
    let hull = block.convex_hull().unwrap();
    assert_hull_of(&hull, &block, "subdivided box");
    assert_eq!(hull.vertex_count(), 8, "only the corners are hull vertices");
    let volume = size.x * size.y * size.z;
    assert!((hull.volume() - volume).abs() <= 1e-5 * volume, "box volume {} vs {volume}", hull.volume());
    // Duplicated vertices and a cube of integer lattice points.
    let lattice: Vec<Vec3> = (0..125)
        .map(|i| Vec3::new((i % 5) as f32, (i / 5 % 5) as f32, (i / 25) as f32))
        .chain([Vec3::ZERO; 4])
        .collect();
    let input = cloud(lattice);
    let hull = input.convex_hull().unwrap();
    assert_hull_of(&hull, &input, "lattice");
    assert_eq!(hull.vertex_count(), 8);
}

#[test]
fn a_dented_ball_and_a_far_one() {
    // Push a cap of the ball in: its vertices leave the hull, which keeps the rest.
    let ball = mesh::icosphere(0.12, 3).unwrap();
    let dented: Vec<Vec3> =
        ball.positions().iter().map(|&p| if p.y > 0.08 { p * Vec3::new(1.0, 0.7, 1.0) } else { p }).collect();
    let dented = TriMesh::new(dented, ball.faces().to_vec()).unwrap();
    let hull = dented.convex_hull().unwrap();
    assert_hull_of(&hull, &dented, "dented ball");
    assert!(hull.vertex_count() < ball.vertex_count(), "the dent's inner vertices are inside the hull");
    assert!(hull.volume() >= dented.volume(), "the hull holds the mesh");
    // The same ball 10 km from the origin: f32 spacing there is 1 mm, the ball 24 cm across.
    let far: Vec<Vec3> = ball.positions().iter().map(|&p| p + Vec3::new(1e4, -1e4, 1e4)).collect();
    let far = TriMesh::new(far, ball.faces().to_vec()).unwrap();
    assert_hull_of(&far.convex_hull().unwrap(), &far, "far ball");
}

#[test]
fn flat_and_degenerate_vertices_are_refused() {
    let flat = cloud((0..25).map(|i| Vec3::new((i % 5) as f32, 0.0, (i / 5) as f32)).collect());
    let line = cloud(vec![Vec3::ZERO, Vec3::X, 2.0 * Vec3::X, 3.0 * Vec3::X]);
    let point = cloud(vec![Vec3::ONE; 3]);
    for (what, mesh) in [("flat", flat), ("line", line), ("point", point)] {
        let err = mesh.convex_hull().unwrap_err().to_string();
        assert!(err.contains("one plane"), "{what}: {err}");
    }
}
