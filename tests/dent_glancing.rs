//! Glancing impacts (paper §3.3, Figures 8–9): stretch, shear and widening of the dent map.

mod common;

use common::sphere_at;
use dentbend::dent::dent_map_stages;
use dentbend::glam::Vec3;
use dentbend::{DentParams, Impact, Resolution, dent_map};

const D: f32 = 0.3;

/// A unit ball approaching the plane y = 0 from above at angle `theta_deg` to the normal (-y),
/// touching the impact point at the origin with its most advanced point.
fn glancing(theta_deg: f32) -> (dentbend::TriMesh, Impact) {
    let theta = theta_deg.to_radians();
    let velocity = Vec3::new(theta.sin(), -theta.cos(), 0.0) * 4.0;
    let ball = sphere_at(-velocity.normalize(), 1.0);
    (ball, Impact { point: Vec3::ZERO, normal: -Vec3::Y, relative_velocity: velocity })
}

fn params(widen: f32) -> DentParams {
    DentParams { widen, resolution: Resolution::Fixed(96), ..DentParams::new(D) }
}

#[test]
fn plain_shear_moves_every_cell_along_the_velocity_by_its_height() {
    let (ball, impact) = glancing(30.0);
    let map = dent_map(&ball, &impact, &params(0.0), None).unwrap();
    let v = impact.relative_velocity.normalize();
    let mut peak: f32 = 0.0;
    let mut deepest: f32 = 0.0;
    for cell in &map.cells {
        let delta = Vec3::new(cell[0], cell[1], cell[2]);
        let height = cell[3];
        // f32 products of unit vectors: a few ulps of d.
        assert!(delta.cross(v).length() <= 1e-5 * D, "Δ {delta} is not along the velocity");
        assert!((delta.length() - height).abs() <= 1e-5 * D, "|Δ| {} ≠ height {height}", delta.length());
        peak = peak.max(delta.length());
        deepest = deepest.max(delta.dot(-Vec3::Y));
    }
    let cos = 30f32.to_radians().cos();
    // The peak lands between map cells after the 1/cos θ stretch; the smoothed dome is flat
    // there to well within 1 % of d.
    assert!((peak - D).abs() <= 0.01 * D, "length along the velocity {peak}, expected {D}");
    assert!((deepest - D * cos).abs() <= 0.01 * D, "depth {deepest}, expected d·cos θ = {}", D * cos);
}

#[test]
fn oblique_projection_stretches_the_footprint_by_one_over_cos_theta() {
    let (ball, impact) = glancing(60.0);
    let stages = dent_map_stages(&ball, &impact, &params(0.0), None).unwrap();
    let z = &stages.zbuffer_grid;
    let m = &stages.map.grid;
    // Half-cell rounding of the stretched grid side.
    let stretched = z.extent() / 0.5;
    assert!((m.extent() - stretched).abs() <= 1e-4 * stretched, "map side {} vs {stretched}", m.extent());
    // The map keeps the profile's cell size (up to the rounding of its side to whole cells), so
    // nothing is lost across the velocity.
    assert!((m.res as f32 - 2.0 * z.res as f32).abs() <= 1.0, "map side {} cells", m.res);
    assert!((m.cell_size / z.cell_size - 1.0).abs() <= 1.0 / z.res as f32);
    assert!((stages.frame.theta_deg() - 60.0).abs() < 1e-3);
    // The in-plane footprint (cells with height > 5 % d) is 1/cos θ = 2× longer along t̂ than across.
    let res = m.res as usize;
    let extent_along = |along_t: bool| {
        let mut count = 0;
        for i in 0..res {
            let (row, col) = if along_t { (res / 2, i) } else { (i, res / 2) };
            if m.res > 0 && stages.map.cells[row * res + col][3] > 0.05 * D {
                count += 1;
            }
        }
        count as f32 * m.cell_size
    };
    let ratio = extent_along(true) / extent_along(false);
    // One cell of quantization on each end of a ~40-cell footprint.
    assert!((ratio - 2.0).abs() < 0.1, "footprint ratio {ratio}, expected 2");
}

#[test]
fn widening_pushes_the_leading_side_further_and_keeps_the_depth() {
    let (ball, impact) = glancing(45.0);
    let plain = dent_map(&ball, &impact, &params(0.0), None).unwrap();
    let widened = dent_map(&ball, &impact, &params(4.0), None).unwrap();
    assert_eq!(plain.grid, widened.grid);
    let res = plain.grid.res as usize;
    let t = Vec3::X;
    let mut leading_gain = 0.0;
    for row in 0..res {
        for col in 0..res {
            let k = row * res + col;
            let (p, w) = (plain.cells[k], widened.cells[k]);
            let depth = |c: [f32; 4]| -c[1];
            let along = |c: [f32; 4]| Vec3::new(c[0], c[1], c[2]).dot(t);
            // t changes only the tangential part.
            assert!((depth(p) - depth(w)).abs() <= 1e-6, "widening changed the depth");
            let u = (col as f32 + 0.5 - res as f32 / 2.0) * plain.grid.cell_size;
            if u > 0.0 {
                assert!(along(w) >= along(p) - 1e-6, "leading side must not shrink");
                leading_gain += along(w) - along(p);
            } else {
                assert!(along(w) <= along(p) + 1e-6, "trailing side must not grow");
            }
        }
    }
    assert!(leading_gain > 0.0);
}

#[test]
fn head_on_glance_is_the_identity() {
    let (ball, impact) = glancing(0.0);
    let stages = dent_map_stages(&ball, &impact, &params(2.0), None).unwrap();
    let (z, m) = (&stages.zbuffer_grid, &stages.map.grid);
    assert_eq!(z.res, m.res);
    assert!((z.cell_size - m.cell_size).abs() <= 1e-6 * z.cell_size);
    for (cell, &h) in stages.map.cells.iter().zip(&stages.smoothed) {
        // Cell centres coincide, so bilinear weights are 1 up to f32 rounding of the index.
        assert!((cell[3] - h).abs() <= 1e-5 * D, "height {} vs smoothed {h}", cell[3]);
        assert!(cell[0].abs() <= 1e-6 && cell[2].abs() <= 1e-6, "head-on moves along the normal only");
        assert!((-cell[1] - h).abs() <= 1e-5 * D);
    }
}

#[test]
fn grazing_angles_are_clamped_to_min_cos() {
    let (ball, impact) = glancing(89.0);
    let stages = dent_map_stages(&ball, &impact, &params(0.0), None).unwrap();
    let expected = 0.1f32.acos().to_degrees();
    assert!((stages.frame.theta_deg() - expected).abs() < 1e-3, "θ {}", stages.frame.theta_deg());
    // A 10× stretch of the profile's extent, on at most GLANCE_STRETCH_CAP·res cells (at least
    // GLANCE_RESOLUTION_FLOOR): the cells grow rather than their count past that.
    let (z, m) = (&stages.zbuffer_grid, &stages.map.grid);
    let cap = (dentbend::dent::GLANCE_STRETCH_CAP * z.res).max(dentbend::dent::GLANCE_RESOLUTION_FLOOR);
    assert_eq!(m.res, (10 * z.res).min(cap).min(dentbend::dent::MAX_RESOLUTION), "profile {} cells", z.res);
    let stretch = m.extent() / z.extent();
    assert!((stretch - 10.0).abs() < 1e-3, "the map covers {stretch}× the profile");
}

/// A ball resting on the plane, touching it at the contact point the solver reports, dents the
/// plane there whatever the angle: the profile's tip (the ball's most advanced point along the
/// velocity) is placed on the contact point, not the line through it (which would put the
/// dent R·tan θ ahead, off the contact).
#[test]
fn glancing_dents_are_anchored_at_the_contact_point() {
    for theta_deg in [30.0f32, 60.0, 80.0] {
        let theta = theta_deg.to_radians();
        let ball = sphere_at(Vec3::Y, 1.0); // touches y = 0 at the origin
        let velocity = Vec3::new(theta.sin(), -theta.cos(), 0.0);
        let impact = Impact { point: Vec3::ZERO, normal: -Vec3::Y, relative_velocity: velocity };
        let map = dent_map(&ball, &impact, &params(0.0), None).unwrap();
        let res = map.grid.res;
        // Even side: the contact point is the corner shared by the four central cells.
        let centre: Vec<f32> =
            [(res / 2 - 1, res / 2 - 1), (res / 2 - 1, res / 2), (res / 2, res / 2 - 1), (res / 2, res / 2)]
                .iter()
                .map(|&(row, col)| map.cells[(row * res + col) as usize][3])
                .collect();
        // The smoothed dome is flat at its top to within 2 % of d over a cell.
        assert!(centre.iter().all(|&h| h >= 0.98 * D), "θ {theta_deg}°: heights {centre:?} at the contact");
        // Height-weighted centre of the dent: on the contact point, up to one map cell plus the
        // offset of the tessellated ball's tip vertex from its symmetry axis (at most one edge,
        // stretched by 1/cos θ on the plane).
        let (mut sum, mut weight) = (Vec3::ZERO, 0.0);
        for row in 0..res {
            for col in 0..res {
                let h = map.cells[(row * res + col) as usize][3];
                sum += h * map.grid.cell_centre(row, col);
                weight += h;
            }
        }
        let centroid = sum / weight;
        let tolerance = map.grid.cell_size + ball.mean_edge_length() / theta.cos();
        assert!(centroid.length() <= tolerance, "θ {theta_deg}°: dent centred at {centroid}, allowed {tolerance}");
    }
}

#[test]
fn separating_bodies_are_refused() {
    let (ball, mut impact) = glancing(30.0);
    impact.relative_velocity = -impact.relative_velocity;
    let err = dent_map(&ball, &impact, &params(0.0), None).unwrap_err();
    assert!(matches!(err, dentbend::DentError::Separating { .. }), "{err}");
}
