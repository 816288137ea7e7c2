//! Paper Figure 2: a ball hits a block head-on. Guards the dent depth, the logistic back-face
//! bulge, and that a gentle falloff never folds the block while a steep one does (Figure 2d).

mod common;

use common::{self_intersections, sphere_at};
use dentbend::glam::Vec3;
use dentbend::{Attenuation, DentParams, Impact, dent, mesh};

const D: f32 = 0.3;
const THICKNESS: f32 = 1.0;

/// The built-in block (4 × 1 × 4, top face at y = 0.5) and a unit ball resting on its centre.
fn block_and_ball() -> (dentbend::TriMesh, dentbend::TriMesh, Impact) {
    let block = mesh::builtin("block").unwrap();
    let ball = sphere_at(Vec3::new(0.0, 0.5 + 1.0, 0.0), 1.0);
    let impact = Impact { point: Vec3::new(0.0, 0.5, 0.0), normal: -Vec3::Y, relative_velocity: -2.0 * Vec3::Y };
    (block, ball, impact)
}

fn vertex_at(mesh: &dentbend::TriMesh, p: Vec3) -> usize {
    mesh.positions()
        .iter()
        .position(|q| q.distance(p) < 1e-5)
        .unwrap_or_else(|| panic!("the block has no vertex at {p}"))
}

#[test]
fn deepest_vertex_moves_by_d_along_the_normal() {
    let (mut block, ball, impact) = block_and_ball();
    let before = block.clone();
    let top = vertex_at(&block, Vec3::new(0.0, 0.5, 0.0));
    let report = dent(&mut block, &ball, &impact, &DentParams::new(D)).unwrap();
    let moves: Vec<Vec3> = block.positions().iter().zip(before.positions()).map(|(a, b)| *a - *b).collect();
    let deepest = moves.iter().map(|m| -m.y).fold(0.0, f32::max);
    // The map's peak is exactly d (rescaled, then only raised by clamped steps up to the peak);
    // the vertex under the impact point reads a bilinear mix of the four central cells, which
    // differ from the peak by the tessellated sphere's asymmetry: 1 % of d.
    assert!((deepest - D).abs() <= 0.01 * D, "deepest move {deepest}, expected {D}");
    assert!(deepest <= D * (1.0 + 1e-5), "no vertex may move past d: {deepest}");
    let centre = moves[top];
    assert!((-centre.y - D).abs() <= 0.01 * D, "centre moved {centre}");
    assert!(centre.x.abs().max(centre.z.abs()) <= 1e-4 * D, "head-on dents move along the normal only: {centre}");
    assert!((report.max_displacement - deepest).abs() <= 1e-5);
    assert!(report.theta_deg.abs() < 1e-3);
    assert!(report.warnings.is_empty(), "the logistic falloff is gentler than 1 - z/d");
}

#[test]
fn logistic_falloff_bulges_the_far_face_by_a_of_thickness() {
    let (mut block, ball, impact) = block_and_ball();
    let top = vertex_at(&block, Vec3::new(0.0, 0.5, 0.0));
    let bottom = vertex_at(&block, Vec3::new(0.0, -0.5, 0.0));
    let (top_before, bottom_before) = (block.positions()[top], block.positions()[bottom]);
    dent(&mut block, &ball, &impact, &DentParams::new(D)).unwrap();
    let top_move = top_before.y - block.positions()[top].y;
    let bottom_move = bottom_before.y - block.positions()[bottom].y;
    let a = 2.0 / (1.0 + (THICKNESS / D).exp());
    // Both vertices read the same map cell, so the ratio is a(thickness) up to f32 rounding.
    assert!((bottom_move / top_move - a).abs() <= 1e-4, "bulge {bottom_move} vs a·move {}", a * top_move);
    assert!(bottom_move > 0.01 * D, "the far face must visibly bulge (Figure 2c): {bottom_move}");
}

#[test]
fn gentle_falloff_keeps_the_block_free_of_self_intersections() {
    let (mut block, ball, impact) = block_and_ball();
    let before = block.clone();
    dent(&mut block, &ball, &impact, &DentParams::new(D)).unwrap();
    let moved: Vec<bool> = block.positions().iter().zip(before.positions()).map(|(a, b)| a != b).collect();
    assert!(moved.iter().filter(|&&m| m).count() > 100, "the dent must move a patch of vertices");
    let hits = self_intersections(&block, &moved);
    assert!(hits.is_empty(), "{} crossing face pairs, first {:?}", hits.len(), hits.first());
}

/// A plank thinner than d: the logistic falloff keeps it whole. A linear falloff five times
/// steeper than 1 − z/d would push the top face through the bottom one (the paper's Figure 2d);
/// the wall measured under the dent makes the falloff stretch to keep half of it, with a warning
/// that names the fold it prevented, and no faces cross (the warning reads the body).
#[test]
fn steep_falloff_on_a_thin_wall_is_fitted_and_warned_about() {
    let plank = mesh::subdivided_box(Vec3::new(4.0, 0.25, 4.0), [64, 4, 64]).unwrap();
    let ball = sphere_at(Vec3::new(0.0, 0.125 + 1.0, 0.0), 1.0);
    let impact = Impact { point: Vec3::new(0.0, 0.125, 0.0), normal: -Vec3::Y, relative_velocity: -Vec3::Y };
    let d = 0.4;

    let mut gentle = plank.clone();
    let report = dent(&mut gentle, &ball, &impact, &DentParams::new(d)).unwrap();
    assert!(report.warnings.is_empty());
    let moved: Vec<bool> = gentle.positions().iter().zip(plank.positions()).map(|(a, b)| a != b).collect();
    assert!(self_intersections(&gentle, &moved).is_empty(), "logistic falloff must not fold the plank");

    let mut steep = plank.clone();
    let params = DentParams { attenuation: Attenuation::Linear { scale: 0.2 }, ..DentParams::new(d) };
    let report = dent(&mut steep, &ball, &impact, &params).unwrap();
    assert_eq!(
        report.warnings.len(),
        1,
        "a falloff that would fold this wall must be warned about: {:?}",
        report.warnings
    );
    let moved: Vec<bool> = steep.positions().iter().zip(plank.positions()).map(|(a, b)| a != b).collect();
    assert!(self_intersections(&steep, &moved).is_empty(), "the fitted falloff must not fold the thin plank");
}
