//! False-colour PNG pictures of scalar grids (profiles, envelopes, displacement lengths).

use std::path::Path;

use image::{Rgb, RgbImage};

use super::IoError;

/// Control points `(t, [r, g, b])` of the colour ramp, `t` ascending in [0, 1]: black through
/// deep purple, crimson and orange to pale yellow. Lightness rises monotonically, so the
/// picture still reads in grayscale.
const RAMP: [(f32, [f32; 3]); 6] = [
    (0.0, [0.0, 0.0, 0.0]),
    (0.2, [58.0, 12.0, 98.0]),
    (0.45, [150.0, 32.0, 110.0]),
    (0.65, [220.0, 72.0, 58.0]),
    (0.85, [250.0, 160.0, 30.0]),
    (1.0, [255.0, 250.0, 190.0]),
];

/// The ramp colour of `t` in [0, 1] (values outside are clamped, NaN is 0), piecewise linear
/// between the control points.
fn heat_colour(t: f32) -> [u8; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let upper = RAMP.iter().position(|&(at, _)| at >= t).unwrap_or(RAMP.len() - 1).max(1);
    let ((t0, c0), (t1, c1)) = (RAMP[upper - 1], RAMP[upper]);
    let s = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
    std::array::from_fn(|k| (c0[k] + s * (c1[k] - c0[k])).round().clamp(0.0, 255.0) as u8)
}

/// A `width × height` RGB picture of `values` (row-major, row 0 at the top), each coloured by
/// `value / max_value` on the ramp. Values ≤ 0 or NaN are black, values ≥ `max_value` pale
/// yellow; a `max_value` that is ≤ 0 or not finite gives an all-black picture.
///
/// # Errors
/// [`IoError::InvalidArgument`] when `values.len() != width·height` or a side is zero.
pub fn heatmap_rgb(values: &[f32], width: u32, height: u32, max_value: f32) -> Result<RgbImage, IoError> {
    check_size(values.len(), width, height)?;
    let scale = if max_value.is_finite() && max_value > 0.0 { 1.0 / max_value } else { 0.0 };
    Ok(RgbImage::from_fn(width, height, |col, row| {
        let v = values[row as usize * width as usize + col as usize];
        Rgb(heat_colour(if scale > 0.0 { v * scale } else { 0.0 }))
    }))
}

/// Writes [`heatmap_rgb`]'s picture as an 8-bit RGB PNG (whatever the file's extension).
///
/// # Errors
/// As [`heatmap_rgb`]; [`IoError::Io`] or [`IoError::Image`] when the file cannot be written.
pub fn write_heatmap_png(
    path: impl AsRef<Path>,
    values: &[f32],
    width: u32,
    height: u32,
    max_value: f32,
) -> Result<(), IoError> {
    let path = path.as_ref();
    let picture = heatmap_rgb(values, width, height, max_value)?;
    super::write_png(path, &picture)
}

/// Checks that a row-major array of `len` values is a non-empty `width × height` grid.
pub(crate) fn check_size(len: usize, width: u32, height: u32) -> Result<(), IoError> {
    if width == 0 || height == 0 || (width as usize).checked_mul(height as usize) != Some(len) {
        return Err(IoError::InvalidArgument(format!(
            "an image of {width}×{height} pixels needs {} values, got {len}",
            width as u64 * height as u64
        )));
    }
    Ok(())
}
