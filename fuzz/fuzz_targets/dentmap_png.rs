//! PNG bytes → dent map: a map or a typed error. The first byte picks the dent's extent, the next
//! the impact's glancing angle, so stretched maps are reached too; the rest is the picture.
#![no_main]

use dentbend::glam::Vec3;
use dentbend::{DentMap, DentParams, Impact};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let [extent_byte, angle_byte, png @ ..] = data else { return };
    let extent = 0.05 + f32::from(*extent_byte) / 64.0;
    let angle = f32::from(*angle_byte) / 255.0 * 1.5;
    let impact = Impact {
        point: Vec3::new(0.0, 0.5, 0.0),
        normal: -Vec3::Y,
        relative_velocity: Vec3::new(angle.sin(), -angle.cos(), 0.0),
    };
    let params = DentParams::new(0.1);
    if let Ok(map) = DentMap::from_png_bytes(png, extent, &impact, &params) {
        assert!(map.cells.iter().flatten().all(|v| v.is_finite()), "a dent map cell is not finite");
        assert_eq!(map.cells.len(), map.grid.cell_count());
    }
});
