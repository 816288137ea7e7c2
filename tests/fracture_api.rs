//! The engine-neutral fracture API: pieces and the rest are closed, volume is
//! conserved, the result is deterministic and replayable, pieces keep a dent made first, and bad
//! input is refused with a typed error.

mod common;

use common::closed::assert_closed;
use dentbend::fracture::{
    FractureError, FractureRecord, FractureSettings, PatternParams, Placement, break_body, replay, volume_after,
};
use dentbend::glam::{Affine3A, Vec3};
use dentbend::{DentParams, Impact, TriMesh, dent, mesh};

/// A 3 × 2 × 0.2 m wall in the xy plane (front face at z = 0.1), 60 × 40 × 2 cells.
fn wall() -> TriMesh {
    mesh::subdivided_box(Vec3::new(3.0, 2.0, 0.2), [60, 40, 2]).unwrap()
}

fn params(cells: u32, seed: u64, radius: f32) -> PatternParams {
    PatternParams { cells, seed, radius }
}

/// The wall hit in the middle of its front face breaks into closed pieces and a closed rest
/// whose volumes add up to the wall's within 1e-4 relative (f64 sums over f32 vertices; the
/// cuts move planes by a few 1e-6 of the size at most, which changes a volume by less).
/// whose volumes add up to the wall's within 1e-4 relative (f64 sums of f32 vertices; the cuts
/// move planes by 1e-9 of the size at most).
#[test]
fn a_wall_breaks_into_closed_pieces_that_keep_its_volume() {
    let wall = wall();
    let settings = FractureSettings::new(params(40, 3, 0.6), Some(10.0), None).unwrap();
    let placement = Placement { point: Vec3::new(0.1, -0.2, 0.1), normal: -Vec3::Z };
    let outcome = break_body(&wall, &settings.pattern, &placement, 2400.0).unwrap().expect("the wall breaks");
    assert!(outcome.pieces.len() >= 20 && outcome.pieces.len() <= 60, "{} pieces", outcome.pieces.len());
    for (k, piece) in outcome.pieces.iter().enumerate() {
        assert_closed(&piece.mesh, &format!("piece {k}"));
        assert!(piece.mass.volume > 0.0 && piece.mass.mass > 0.0);
        // Within the pattern's radius of the impact (the 16-gon's corners are 2 % further out).
        let reach =
            piece.mesh.positions().iter().map(|p| (*p - placement.point).truncate().length()).fold(0.0, f32::max);
        assert!(reach <= 0.6 * 1.02 + 1e-4, "piece {k} reaches {reach} m");
    }
    let rest = outcome.rest.as_ref().expect("the wall is larger than the pattern");
    assert_closed(rest, "rest");
    let before = f64::from(wall.volume());
    let after = volume_after(&outcome);
    assert!((after - before).abs() < 1e-4 * before, "volume {before} → {after}");
    // The hole goes through the wall: its area is the 16-gon's, π·R²·(16/π)·tan(π/16).
    let hole = before - f64::from(outcome.rest_mass.unwrap().volume);
    let polygon_area = 16.0 * 0.36 * (std::f64::consts::PI / 16.0).tan();
    assert!((hole - polygon_area * 0.2).abs() < 1e-3 * hole, "hole volume {hole}");
}

/// The bunny (closed, non-convex: its cross-sections have several loops) breaks into closed
/// pieces and a closed rest of the same total volume.
#[test]
fn the_bunny_breaks_into_closed_pieces() {
    let bunny = mesh::builtin("bunny").unwrap();
    let settings = FractureSettings::new(params(24, 11, 2.5), Some(1.0), None).unwrap();
    // An ear-level hit from the front.
    let placement = Placement { point: Vec3::new(-1.0, 7.0, 0.5), normal: Vec3::new(0.3, -0.2, -1.0) };
    let outcome = break_body(&bunny, &settings.pattern, &placement, 1000.0).unwrap().expect("it breaks");
    assert!(outcome.pieces.len() >= 5, "{} pieces", outcome.pieces.len());
    for (k, piece) in outcome.pieces.iter().enumerate() {
        assert_closed(&piece.mesh, &format!("piece {k}"));
    }
    assert_closed(outcome.rest.as_ref().unwrap(), "rest");
    let before = f64::from(bunny.volume());
    let after = volume_after(&outcome);
    assert!((after - before).abs() < 1e-4 * before, "volume {before} → {after}");
}

/// The same input gives the same pieces bit for bit, and a record replays it; another seed
/// gives another pattern.
#[test]
fn fracture_is_deterministic_and_replays_from_its_record() {
    let wall = wall();
    let record = FractureRecord {
        pattern: params(30, 5, 0.5),
        placement: Placement { point: Vec3::new(0.0, 0.0, 0.1), normal: -Vec3::Z },
        density: 2000.0,
        weld_output: false,
    };
    let first = replay(&wall, &record).unwrap().unwrap();
    let json = serde_json::to_string(&record).unwrap();
    let second = replay(&wall, &serde_json::from_str(&json).unwrap()).unwrap().unwrap();
    assert_eq!(first.pieces.len(), second.pieces.len());
    for (a, b) in first.pieces.iter().zip(&second.pieces) {
        assert_eq!(a.mesh, b.mesh);
        assert_eq!(a.mass, b.mass);
    }
    assert_eq!(first.rest, second.rest);
    let other = replay(&wall, &FractureRecord { pattern: params(30, 6, 0.5), ..record }).unwrap().unwrap();
    assert_ne!(other.pieces[0].mesh, first.pieces[0].mesh);
}

/// Dent first, then break: the piece under the impact keeps the dent (its front face reaches
/// the dent's depth behind the undented face), and the total volume is the dented wall's.
#[test]
fn pieces_keep_the_dent() {
    let mut wall = wall();
    let mut ball = mesh::icosphere(0.3, 3).unwrap();
    ball.transform(Affine3A::from_translation(Vec3::new(0.0, 0.0, 0.45))).unwrap();
    let impact = Impact { point: Vec3::new(0.0, 0.0, 0.1), normal: -Vec3::Z, relative_velocity: -4.0 * Vec3::Z };
    let report = dent(&mut wall, &ball, &impact, &DentParams::new(0.05)).unwrap();
    assert!(report.max_displacement > 0.04);
    let settings = FractureSettings::new(params(30, 9, 0.5), None, Some(0.01)).unwrap();
    let placement = Placement { point: impact.point, normal: impact.normal };
    let outcome = break_body(&wall, &settings.pattern, &placement, 2000.0).unwrap().unwrap();
    let deepest = outcome
        .pieces
        .iter()
        .flat_map(|p| p.mesh.positions().iter().filter(|q| q.truncate().length() < 0.02).map(|q| q.z))
        .fold(f32::INFINITY, f32::min);
    assert!(deepest < 0.1 - 0.04, "the front face under the impact is at z = {deepest}, undented 0.1");
    let after = volume_after(&outcome);
    let dented = f64::from(wall.volume());
    assert!((after - dented).abs() < 1e-4 * dented, "volume {dented} → {after}");
}

/// Bad settings and input are refused with typed errors, the mesh untouched.
#[test]
fn bad_input_is_refused() {
    for (p, t, d, name) in [
        (params(0, 1, 0.5), Some(1.0), None, "cells"),
        (params(10, 1, f32::NAN), Some(1.0), None, "radius"),
        (params(10, 1, -0.5), Some(1.0), None, "radius"),
        (params(10, 1, 0.5), Some(f32::NAN), None, "toughness"),
        (params(10, 1, 0.5), Some(-1.0), None, "toughness"),
        (params(10, 1, 0.5), None, Some(-0.1), "dent_limit"),
        (params(10, 1, 0.5), None, None, "toughness"),
    ] {
        match FractureSettings::new(p, t, d) {
            Err(FractureError::InvalidParameter { name: got, .. }) => assert_eq!(got, name),
            other => panic!("{name}: {other:?}"),
        }
    }
    let wall = wall();
    let copy = wall.clone();
    let settings = FractureSettings::new(params(10, 1, 0.5), Some(1.0), None).unwrap();
    let bad = Placement { point: Vec3::new(f32::NAN, 0.0, 0.0), normal: -Vec3::Z };
    assert!(matches!(break_body(&wall, &settings.pattern, &bad, 1000.0), Err(FractureError::InvalidPlacement(_))));
    let zero = Placement { point: Vec3::ZERO, normal: Vec3::ZERO };
    assert!(matches!(break_body(&wall, &settings.pattern, &zero, 1000.0), Err(FractureError::InvalidPlacement(_))));
    let good = Placement { point: Vec3::new(0.0, 0.0, 0.1), normal: -Vec3::Z };
    assert!(matches!(
        break_body(&wall, &settings.pattern, &good, -1.0),
        Err(FractureError::InvalidParameter { name: "density", .. })
    ));
    // An open mesh (the wall without its first face) bounds no solid.
    let open = TriMesh::new(wall.positions().to_vec(), wall.faces()[1..].to_vec()).unwrap();
    assert!(matches!(break_body(&open, &settings.pattern, &good, 1000.0), Err(FractureError::OpenMesh { .. })));
    assert_eq!(wall, copy);
}

/// A pattern placed away from the body breaks nothing.
#[test]
fn a_pattern_that_misses_breaks_nothing() {
    let settings = FractureSettings::new(params(10, 1, 0.5), Some(1.0), None).unwrap();
    let far = Placement { point: Vec3::new(10.0, 0.0, 0.0), normal: -Vec3::Z };
    assert!(break_body(&wall(), &settings.pattern, &far, 1000.0).unwrap().is_none());
}
