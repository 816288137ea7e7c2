//! Artist-supplied dents (paper §3.1): PNG height maps round-trip into the same dent map the
//! pipeline built, and analytic Gaussians have the stated shape.

use dentbend::dent::dent_map_stages;
use dentbend::glam::Vec3;
use dentbend::{DentError, DentMap, DentParams, Impact, Resolution, io, mesh};

const D: f32 = 0.8;

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("dentbend-artist-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Bunny profile, glancing at 25° so the round trip goes through the stretch and shear.
fn bunny_stages() -> (dentbend::dent::DentStages, Impact, DentParams) {
    let bunny = mesh::builtin("bunny").unwrap();
    let theta = 25f32.to_radians();
    let velocity = Vec3::new(theta.sin(), -theta.cos(), 0.0);
    let tip = bunny.positions().iter().copied().max_by(|a, b| a.dot(velocity).total_cmp(&b.dot(velocity))).unwrap();
    let impact = Impact { point: tip, normal: -Vec3::Y, relative_velocity: velocity };
    let params = DentParams { resolution: Resolution::Fixed(80), ..DentParams::new(D) };
    let stages = dent_map_stages(&bunny, &impact, &params, None).unwrap();
    (stages, impact, params)
}

fn max_cell_error(a: &DentMap, b: &DentMap) -> f32 {
    a.cells.iter().zip(&b.cells).flat_map(|(x, y)| (0..4).map(move |k| (x[k] - y[k]).abs())).fold(0.0, f32::max)
}

#[test]
fn sixteen_bit_png_round_trip_reproduces_the_map() {
    let (stages, impact, params) = bunny_stages();
    let dir = scratch("png16");
    let path = dir.join("smoothed.png");
    let res = stages.zbuffer_grid.res;
    io::write_height_png16(&path, &stages.smoothed, res, res, D).unwrap();
    let map = DentMap::from_png(&path, stages.zbuffer_grid.extent(), &impact, &params).unwrap();
    assert_eq!(map.grid, stages.map.grid);
    // Heights quantize to d/65535 (half a step each way) and every output is a convex
    // combination of heights, scaled by at most 2·sinθ + cosθ < 2.
    let err = max_cell_error(&map, &stages.map);
    assert!(err <= 2.0 * D / 65535.0, "16-bit round trip error {err}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn eight_bit_png_round_trip_within_quantization() {
    let (stages, impact, params) = bunny_stages();
    let dir = scratch("png8");
    let path = dir.join("smoothed8.png");
    let res = stages.zbuffer_grid.res;
    let pixels: Vec<u8> = stages.smoothed.iter().map(|h| (h / D * 255.0).round() as u8).collect();
    image::GrayImage::from_raw(res, res, pixels).unwrap().save(&path).unwrap();
    let map = DentMap::from_png(&path, stages.zbuffer_grid.extent(), &impact, &params).unwrap();
    let err = max_cell_error(&map, &stages.map);
    assert!(err <= 2.0 * D / 255.0, "8-bit round trip error {err}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn bad_pictures_are_refused() {
    let (_, impact, params) = bunny_stages();
    let dir = scratch("bad");
    let wide = dir.join("wide.png");
    image::GrayImage::from_pixel(8, 4, image::Luma([200])).save(&wide).unwrap();
    let black = dir.join("black.png");
    image::GrayImage::from_pixel(8, 8, image::Luma([0])).save(&black).unwrap();
    let garbage = dir.join("garbage.png");
    std::fs::write(&garbage, b"not a png").unwrap();
    for path in [wide, black, garbage, dir.join("missing.png")] {
        let err = DentMap::from_png(&path, 1.0, &impact, &params).unwrap_err();
        assert!(matches!(err, DentError::Image { .. }), "{path:?}: {err:?}");
    }
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn gaussian_map_has_its_stated_shape() {
    let impact = Impact { point: Vec3::new(1.0, 2.0, 3.0), normal: Vec3::Z, relative_velocity: Vec3::Z };
    let width = 0.5;
    let params = DentParams { resolution: Resolution::Fixed(65), ..DentParams::new(D) };
    let map = DentMap::gaussian(width, &impact, &params).unwrap();
    assert_eq!(map.grid.res, 65);
    assert!((map.grid.extent() - 7.0 * width).abs() < 1e-5);
    // Odd side: the centre cell sits on the impact point.
    let centre = map.displacement(32, 32);
    assert!((centre - D * Vec3::Z).length() <= 1e-6 * D, "{centre}");
    let h = map.grid.cell_size;
    for (row, col) in [(32, 40), (20, 32), (10, 50)] {
        let (x, y) = ((col as f32 - 32.0) * h, (row as f32 - 32.0) * h);
        let expected = D * (-(x * x + y * y) / (2.0 * width * width)).exp();
        let got = map.displacement(row, col);
        assert!((got.z - expected).abs() <= 1e-5 * D && got.x == 0.0 && got.y.abs() <= 1e-7, "{got} vs {expected}");
    }
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert!(DentMap::gaussian(bad, &impact, &params).is_err());
    }
}

#[test]
fn height_maps_reject_bad_values() {
    let impact = Impact::head_on(Vec3::ZERO, Vec3::Z);
    let params = DentParams::new(D);
    let ok = vec![0.1; 16];
    assert!(DentMap::from_heights(&ok, 4, 1.0, &impact, &params).is_ok());
    assert!(DentMap::from_heights(&ok, 5, 1.0, &impact, &params).is_err());
    assert!(DentMap::from_heights(&ok, 4, 0.0, &impact, &params).is_err());
    assert!(DentMap::from_heights(&ok, 4, f32::NAN, &impact, &params).is_err());
    let mut bad = ok.clone();
    bad[3] = f32::NAN;
    assert!(DentMap::from_heights(&bad, 4, 1.0, &impact, &params).is_err());
    bad[3] = -0.5;
    assert!(DentMap::from_heights(&bad, 4, 1.0, &impact, &params).is_err());
    assert!(DentMap::from_heights(&[], 0, 1.0, &impact, &params).is_err());
}
