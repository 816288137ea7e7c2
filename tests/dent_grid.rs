//! Grid conventions (ARCHITECTURE.md §3) and the falloff the `displace` kernel applies agree with the
//! Rust-side definitions they mirror.

use dentbend::dent::{DentFrame, Grid};
use dentbend::glam::Vec3;
use dentbend::{Attenuation, DentMap, Impact, TriMesh};

#[test]
fn cell_centres_and_grid_coordinates_invert_each_other() {
    let frame = DentFrame::new(&Impact::head_on(Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.3, -1.0, 0.2)), 0.1);
    let (axis_x, axis_y, axis_z) = frame.plane_axes();
    for res in [1, 2, 7, 64] {
        let grid = Grid { origin: Vec3::new(1.0, 2.0, 3.0), axis_x, axis_y, axis_z, cell_size: 0.25, res };
        for (row, col) in [(0, 0), (res - 1, 0), (res / 2, res - 1)] {
            let c = grid.cell_centre(row, col);
            let g = grid.grid_coords(c);
            // f32 rounding of coordinates of magnitude ~4: 1e-5 cell.
            assert!((g - Vec3::new(col as f32, row as f32, 0.0)).abs().max_element() < 1e-4, "{g}");
        }
        // The centres are symmetric about the origin: the first and last cell centres average to it.
        let mid = 0.5 * (grid.cell_centre(0, 0) + grid.cell_centre(res - 1, res - 1));
        assert!(mid.distance(grid.origin) < 1e-5);
    }
    // Right-handed axes: x × y = z, and z is the denting normal.
    assert!((axis_x.cross(axis_y) - axis_z).length() < 1e-6);
    assert!((axis_z - Vec3::new(0.3, -1.0, 0.2).normalize()).length() < 1e-6);
}

/// A uniform map of depth 1 applied to a column of vertices at increasing depth: each moves by
/// exactly `a(z)` as `Attenuation::eval` defines it (the kernel has its own copy of the formulas,
/// as the shader will).
#[test]
fn displace_applies_the_documented_falloffs() {
    let d = 0.5;
    let depths: Vec<f32> = (0..40).map(|k| k as f32 * 0.1 - 0.5).collect();
    let column: Vec<Vec3> = depths.iter().map(|&z| Vec3::new(0.0, 0.0, z)).collect();
    let mut positions = column.clone();
    positions.extend([Vec3::new(9.0, 9.0, 0.0), Vec3::new(9.5, 9.0, 0.0)]);
    let faces: Vec<[u32; 3]> =
        (0..column.len() as u32).map(|k| [k, column.len() as u32, column.len() as u32 + 1]).collect();
    let target = TriMesh::new(positions, faces).unwrap();
    let res = 8;
    let map = DentMap {
        grid: Grid { origin: Vec3::ZERO, axis_x: Vec3::X, axis_y: Vec3::Y, axis_z: Vec3::Z, cell_size: 0.5, res },
        cells: vec![[0.0, 0.0, d, d]; res as usize * res as usize],
        dent_distance: d,
    };
    let custom = Attenuation::Custom(std::sync::Arc::new(|z, d| (-z / d).exp()));
    for falloff in [Attenuation::Logistic, Attenuation::Linear { scale: 2.0 }, Attenuation::None, custom] {
        let mut dented = target.clone();
        map.apply(&mut dented, &falloff).unwrap();
        for (k, &z) in depths.iter().enumerate() {
            let moved = dented.positions()[k].z - z;
            let expected = falloff.eval(z, d) * d;
            // Built-in falloffs: the same f32 formula. The custom one is read from a 257-sample
            // table over [0, 8d]; linear interpolation of e^{−z/d} errs by at most
            // (8/256)²/8 = 1.2e-4 relative.
            let tol = if matches!(falloff, Attenuation::Custom(_)) { 2e-4 * d } else { 1e-6 };
            assert!((moved - expected).abs() <= tol, "{falloff:?} at z = {z}: moved {moved}, a(z)·d = {expected}");
        }
        // Vertices off the map stay where they were.
        assert_eq!(dented.positions()[column.len()], target.positions()[column.len()]);
    }
}
