//! Fracture of game assets: a mesh with split vertices (hard edges, UV seams) breaks into a rest
//! and pieces split along the same seams, each cut face with vertices of its own, and every
//! vertex says where it lies on the mesh that broke, so that UVs and other attributes carry
//! over. A welded mesh breaks exactly as before, its vertices' origins told all the same.

mod common;

use std::collections::HashMap;

use common::seams::{key, unpaired_edges};
use dentbend::fracture::{
    FractureOutcome, FracturePattern, PatternParams, Placement, SurfacePoint, VertexOrigin, break_body, volume_after,
};
use dentbend::glam::Vec3;
use dentbend::{DentParams, Impact, TriMesh, dent, mesh};

/// `mesh` with every face given vertices of its own: fully hard-edged, every edge a seam.
fn faceted(mesh: &TriMesh) -> TriMesh {
    let positions = mesh.faces().iter().flat_map(|f| f.map(|v| mesh.positions()[v as usize])).collect();
    let faces = (0..mesh.face_count() as u32).map(|f| [3 * f, 3 * f + 1, 3 * f + 2]).collect();
    TriMesh::new(positions, faces).unwrap()
}

/// A 1.2 × 0.8 × 0.1 m panel, 24 × 16 × 2 cells, hit in the middle of its front face.
fn panel() -> (TriMesh, FracturePattern, Placement) {
    let panel = mesh::subdivided_box(Vec3::new(1.2, 0.8, 0.1), [24, 16, 2]).unwrap();
    let pattern = FracturePattern::new(PatternParams { cells: 16, seed: 7, radius: 0.3 }).unwrap();
    let placement = Placement { point: Vec3::new(0.05, -0.03, 0.05), normal: -Vec3::Z };
    (panel, pattern, placement)
}

/// Every output mesh of `outcome` with its origins.
fn meshes(outcome: &FractureOutcome) -> Vec<(&TriMesh, &[VertexOrigin])> {
    let mut all: Vec<(&TriMesh, &[VertexOrigin])> = outcome.pieces.iter().map(|p| (&p.mesh, &p.origins[..])).collect();
    all.extend(outcome.rest.as_ref().map(|r| (r, &outcome.rest_origins[..])));
    all
}

/// The surface points among `origins`.
fn surface_points(origins: &[VertexOrigin]) -> Vec<SurfacePoint> {
    origins
        .iter()
        .filter_map(|o| match o {
            VertexOrigin::Surface(p) => Some(*p),
            VertexOrigin::Cut { .. } => None,
        })
        .collect()
}

/// The point of `input` a surface origin names.
fn point_on(input: &TriMesh, point: &SurfacePoint) -> Vec3 {
    let corners = input.faces()[point.face as usize];
    (0..3).map(|k| input.positions()[corners[k] as usize] * point.weights[k]).sum()
}

/// Checks the origins of every output mesh of `outcome` against `input` (`size` m across):
/// one per vertex; a surface origin's weights are a convex combination that lands on the
/// vertex within 1e-5 of the size (f32 weights of f64 barycentrics, f32 positions), and a cut
/// vertex's nearest surface point is one of the same mesh's surface points.
fn check_origins(input: &TriMesh, outcome: &FractureOutcome, size: f32) {
    for (k, (mesh, origins)) in meshes(outcome).into_iter().enumerate() {
        assert_eq!(origins.len(), mesh.vertex_count(), "mesh {k}: one origin per vertex");
        let surface = surface_points(origins);
        for (v, origin) in origins.iter().enumerate() {
            match origin {
                VertexOrigin::Surface(point) => {
                    let sum: f32 = point.weights.iter().sum();
                    assert!(point.weights.iter().all(|&w| w >= 0.0) && (sum - 1.0).abs() < 1e-5, "{point:?}");
                    let at = point_on(input, point);
                    let p = mesh.positions()[v];
                    assert!(at.distance(p) < 1e-5 * size, "mesh {k} vertex {v}: {p} named {at}");
                }
                VertexOrigin::Cut { normal, nearest } => {
                    assert!((normal.length() - 1.0).abs() < 1e-5, "mesh {k} vertex {v}: cut normal {normal}");
                    let nearest = nearest.expect("every piece of the panel has some surface");
                    assert!(surface.contains(&nearest), "mesh {k} vertex {v}: {nearest:?} is not its surface");
                }
            }
        }
    }
}

/// The faceted panel (every vertex split per face) breaks like the welded one: closed once
/// welded, the same volume, and with the seams kept: every surface triangle's corners name the
/// same input face (their vertices belong to that face alone), no vertex is shared between a
/// surface face and a cut face, and a cut vertex's normal is its cap's plane's.
#[test]
fn a_faceted_panel_breaks_along_its_seams() {
    let (panel, pattern, placement) = panel();
    let hard = faceted(&panel);
    let outcome = break_body(&hard, &pattern, &placement, 2000.0).unwrap().expect("it breaks");
    assert!(outcome.pieces.len() >= 8, "{} pieces", outcome.pieces.len());
    check_origins(&hard, &outcome, 1.2);
    let before = f64::from(hard.volume());
    assert!((volume_after(&outcome) - before).abs() < 1e-4 * before);
    for (k, (mesh, origins)) in meshes(&outcome).into_iter().enumerate() {
        assert_eq!(unpaired_edges(mesh), 0, "mesh {k} is not closed once welded");
        let mut on_cut = vec![None; mesh.vertex_count()];
        for face in mesh.faces() {
            let named = face.map(|v| match origins[v as usize] {
                VertexOrigin::Surface(point) => Some(point.face),
                VertexOrigin::Cut { .. } => None,
            });
            assert!(named.iter().all(|n| *n == named[0]), "mesh {k}: a triangle spans faces {named:?}");
            for &v in face {
                let cut = named[0].is_none();
                assert_ne!(on_cut[v as usize].replace(cut), Some(!cut), "mesh {k}: vertex {v} on surface and cut");
            }
        }
        for (v, origin) in origins.iter().enumerate() {
            if let VertexOrigin::Cut { normal, .. } = origin {
                let n = mesh.normals()[v];
                assert_eq!(n, *normal, "mesh {k}: cut vertex {v}'s normal is its cut's");
                for face in mesh.faces().iter().filter(|f| f.contains(&(v as u32))) {
                    let [a, b, c] = face.map(|u| mesh.positions()[u as usize]);
                    // A sliver's f32 normal is off by about 1e-7·(edge length)²/area: only
                    // faces of 5e-6 m² or more (error below 1e-4 here) are compared.
                    let area_normal = (b - a).cross(c - a);
                    if area_normal.length() < 1e-5 {
                        continue;
                    }
                    let face_normal = area_normal.normalize();
                    assert!(n.dot(face_normal) > 0.9999, "mesh {k}: cut vertex {v}'s normal {n} off {face_normal}");
                }
            }
        }
    }
}

/// A welded panel breaks into welded output (no two vertices of one mesh at one position) whose
/// vertices' origins are told too; its seam-split twin gives the same surfaces to within
/// rounding (total area and volume within 1e-5 relative).
#[test]
fn a_welded_panel_stays_welded_and_tells_origins() {
    let (panel, pattern, placement) = panel();
    let outcome = break_body(&panel, &pattern, &placement, 2000.0).unwrap().expect("it breaks");
    check_origins(&panel, &outcome, 1.2);
    for (k, (mesh, _)) in meshes(&outcome).into_iter().enumerate() {
        let mut seen = HashMap::new();
        for (v, &p) in mesh.positions().iter().enumerate() {
            assert_eq!(seen.insert(key(p), v), None, "mesh {k}: two vertices at {p}");
        }
    }
    let split = break_body(&faceted(&panel), &pattern, &placement, 2000.0).unwrap().unwrap();
    assert_eq!(split.pieces.len(), outcome.pieces.len());
    let area = |o: &FractureOutcome| meshes(o).iter().map(|(m, _)| f64::from(m.area())).sum::<f64>();
    let (a, b) = (area(&outcome), area(&split));
    assert!((a - b).abs() < 1e-5 * a, "area {a} vs {b}");
    let (a, b) = (volume_after(&outcome), volume_after(&split));
    assert!((a - b).abs() < 1e-5 * a, "volume {a} vs {b}");
}

/// A surface whose only seams are UV seams (smooth normals on both sides) keeps its smooth
/// normals across them: a surface vertex's normal is the input's interpolated, within 1e-4.
#[test]
fn uv_seams_keep_smooth_normals() {
    let (panel, pattern, placement) = panel();
    // Split every vertex per face, but give each copy the welded mesh's smooth normal.
    let hard = faceted(&panel);
    let normals = panel.faces().iter().flat_map(|f| f.map(|v| panel.normals()[v as usize])).collect();
    let smooth = TriMesh::with_normals(hard.positions().to_vec(), hard.faces().to_vec(), normals).unwrap();
    let outcome = break_body(&smooth, &pattern, &placement, 2000.0).unwrap().unwrap();
    for (mesh, origins) in meshes(&outcome) {
        for (v, origin) in origins.iter().enumerate() {
            if let VertexOrigin::Surface(point) = origin {
                let corners = smooth.faces()[point.face as usize];
                let expected: Vec3 =
                    (0..3).map(|k| smooth.normals()[corners[k] as usize] * point.weights[k]).sum::<Vec3>().normalize();
                assert!(mesh.normals()[v].distance(expected) < 1e-4, "{} vs {expected}", mesh.normals()[v]);
            }
        }
    }
}

/// The rest of a broken faceted panel dents again at the edge of the hole, where the cut left
/// vertices a few µm apart joined by tiny edges on both sides of the cap's rim seam (they are
/// joined through their copies, not a seam that nearly coincides), and farther out: each dent
/// moves vertices and the rest stays closed once welded.
#[test]
fn a_faceted_rest_dents_again_at_the_edge_of_the_hole() {
    let (panel, pattern, placement) = panel();
    let outcome = break_body(&faceted(&panel), &pattern, &placement, 2000.0).unwrap().unwrap();
    let mut rest = outcome.rest.expect("the panel is larger than the pattern");
    // The pattern's 16-gon has an inradius of 0.294 m around the impact.
    for x in [0.31f32, -0.32, 0.5] {
        let point = Vec3::new(placement.point.x + x, placement.point.y, 0.05);
        let mut ball = mesh::icosphere(0.05, 3).unwrap();
        ball.transform(dentbend::glam::Affine3A::from_translation(point + Vec3::Z * 0.05)).unwrap();
        let impact = Impact { point, normal: -Vec3::Z, relative_velocity: -3.0 * Vec3::Z };
        let report = dent(&mut rest, &ball, &impact, &DentParams::new(0.01)).expect("the rest dents");
        assert!(report.max_displacement > 0.0, "the dent at x = {x} moves vertices");
        assert_eq!(unpaired_edges(&rest), 0, "the rest dented at x = {x} is not closed once welded");
    }
}

/// A thick faceted block (a 1 m cube) breaks where the pattern's prism ends inside it, so cuts
/// meet inside the body: every cut vertex of a mesh that has any surface is given a nearest
/// surface point of that mesh (with seams a cap shares no vertex with the surface, so it is
/// found through the cap's rim).
#[test]
fn cut_vertices_inside_a_thick_faceted_block_find_the_surface() {
    let cube = mesh::subdivided_box(Vec3::splat(1.0), [8, 8, 8]).unwrap();
    let hard = faceted(&cube);
    let pattern = FracturePattern::new(PatternParams { cells: 12, seed: 4, radius: 0.25 }).unwrap();
    let placement = Placement { point: Vec3::new(0.02, 0.03, 0.5), normal: -Vec3::Z };
    let outcome = break_body(&hard, &pattern, &placement, 1000.0).unwrap().expect("it breaks");
    let mut inside = 0;
    for (k, (mesh, origins)) in meshes(&outcome).into_iter().enumerate() {
        let surface = surface_points(origins);
        if surface.is_empty() {
            continue;
        }
        let at_surface: std::collections::HashSet<_> = origins
            .iter()
            .zip(mesh.positions())
            .filter(|(o, _)| matches!(o, VertexOrigin::Surface(_)))
            .map(|(_, &p)| key(p))
            .collect();
        for (v, origin) in origins.iter().enumerate() {
            if let VertexOrigin::Cut { nearest, .. } = origin {
                inside += usize::from(!at_surface.contains(&key(mesh.positions()[v])));
                let nearest =
                    nearest.unwrap_or_else(|| panic!("mesh {k}: cut vertex {v} has no nearest surface point"));
                assert!(surface.contains(&nearest), "mesh {k} vertex {v}: {nearest:?} is not its surface");
            }
        }
    }
    assert!(inside > 0, "no cut vertex lies inside the block: the test shows nothing");
}
