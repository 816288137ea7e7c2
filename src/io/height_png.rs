//! Grayscale height maps as PNG: artist-painted dent maps in, 16-bit pictures of heights out.

use std::io::{BufRead, Cursor, Seek};
use std::path::Path;

use image::{DynamicImage, ImageBuffer, ImageFormat, ImageReader, Limits, Luma};

use super::IoError;
use super::heatmap::check_size;

/// Path reported in errors for a PNG read from memory.
const MEMORY: &str = "<memory>";

/// A grayscale picture read as heights in [0, 1], row-major with row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightImage {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width × height` values in [0, 1]: black is 0, white is 1.
    pub values: Vec<f32>,
}

/// Reads a PNG as heights in [0, 1].
///
/// 8-bit gray is divided by 255 and 16-bit gray by 65535, exactly. Gray + alpha ignores the
/// alpha channel. RGB and RGBA are converted to luma first, `0.2126 R + 0.7152 G + 0.0722 B`
/// on the stored (gamma-encoded) values, alpha ignored; 8-bit colour keeps 8-bit precision.
///
/// # Errors
/// [`IoError::Io`] when the file cannot be read; [`IoError::Image`] when it is not a PNG or
/// cannot be decoded.
pub fn read_height_png(path: impl AsRef<Path>) -> Result<HeightImage, IoError> {
    let path = path.as_ref();
    let reader = ImageReader::open(path).map_err(|e| IoError::io(path, e))?;
    let reader = reader.with_guessed_format().map_err(|e| IoError::io(path, e))?;
    heights_of(reader, path, None)
}

/// [`read_height_png`], refusing a picture wider or taller than `max_side` pixels from its
/// header, before anything is decoded.
///
/// # Errors
/// As [`read_height_png`]; [`IoError::Image`] holding an [`image::ImageError::Limits`] for a
/// picture over `max_side`.
pub(crate) fn read_height_png_within(path: &Path, max_side: u32) -> Result<HeightImage, IoError> {
    let reader = ImageReader::open(path).map_err(|e| IoError::io(path, e))?;
    let reader = reader.with_guessed_format().map_err(|e| IoError::io(path, e))?;
    heights_of(reader, path, Some(max_side))
}

/// [`read_height_png_within`] for the bytes of a PNG held in memory (errors name the path
/// `<memory>`).
///
/// # Errors
/// As [`read_height_png_within`].
pub(crate) fn decode_height_png_within(bytes: &[u8], max_side: u32) -> Result<HeightImage, IoError> {
    let reader = ImageReader::with_format(Cursor::new(bytes), ImageFormat::Png);
    heights_of(reader, Path::new(MEMORY), Some(max_side))
}

/// Decodes `reader`'s picture as heights in [0, 1], refusing sides over `max_side` pixels when
/// given; `path` names it in errors.
fn heights_of<R: BufRead + Seek>(
    mut reader: ImageReader<R>,
    path: &Path,
    max_side: Option<u32>,
) -> Result<HeightImage, IoError> {
    if let Some(max_side) = max_side {
        let mut limits = Limits::default();
        limits.max_image_width = Some(max_side);
        limits.max_image_height = Some(max_side);
        reader.limits(limits);
    }
    let picture = reader.decode().map_err(|e| IoError::image(path, e))?;
    let (width, height) = (picture.width(), picture.height());
    let values = match picture {
        DynamicImage::ImageLuma8(p) => p.into_raw().into_iter().map(|v| f32::from(v) / 255.0).collect(),
        DynamicImage::ImageLuma16(p) => p.into_raw().into_iter().map(|v| f32::from(v) / 65535.0).collect(),
        DynamicImage::ImageLumaA8(p) => p.into_raw().chunks_exact(2).map(|c| f32::from(c[0]) / 255.0).collect(),
        DynamicImage::ImageLumaA16(p) => p.into_raw().chunks_exact(2).map(|c| f32::from(c[0]) / 65535.0).collect(),
        p @ (DynamicImage::ImageRgb8(_) | DynamicImage::ImageRgba8(_)) => {
            p.to_luma8().into_raw().into_iter().map(|v| f32::from(v) / 255.0).collect()
        }
        other => other.to_luma32f().into_raw().into_iter().map(|v| v.clamp(0.0, 1.0)).collect(),
    };
    Ok(HeightImage { width, height, values })
}

/// Writes `values` (row-major, row 0 at the top) as a 16-bit grayscale PNG: each pixel is
/// `round(value / max_value · 65535)`, clamped to 0..=65535 (NaN is 0). A `max_value` that is
/// ≤ 0 or not finite gives an all-black picture.
///
/// # Errors
/// [`IoError::InvalidArgument`] when `values.len() != width·height` or a side is zero;
/// [`IoError::Io`] or [`IoError::Image`] when the file cannot be written.
pub fn write_height_png16(
    path: impl AsRef<Path>,
    values: &[f32],
    width: u32,
    height: u32,
    max_value: f32,
) -> Result<(), IoError> {
    let path = path.as_ref();
    check_size(values.len(), width, height)?;
    let scale = if max_value.is_finite() && max_value > 0.0 { 65535.0 / f64::from(max_value) } else { 0.0 };
    let pixels: Vec<u16> = values
        .iter()
        .map(|&v| if v.is_nan() { 0 } else { (f64::from(v) * scale).round().clamp(0.0, 65535.0) as u16 })
        .collect();
    let picture = ImageBuffer::<Luma<u16>, Vec<u16>>::from_raw(width, height, pixels)
        .ok_or_else(|| IoError::InvalidArgument("image buffer size mismatch".into()))?;
    super::write_png(path, &picture)
}
