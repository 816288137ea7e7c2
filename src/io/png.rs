//! PNG files written whole or not at all: the picture is encoded in memory, then written through
//! [`crate::mesh::write_file_atomically`], so a failure never truncates an existing file.

use std::io::{Cursor, Write};
use std::path::Path;

use image::{EncodableLayout, ImageBuffer, ImageFormat, PixelWithColorType};

use super::IoError;
use crate::mesh::write_file_atomically;

/// Writes `picture` as a PNG file at `path` (whatever the file's extension), replacing an
/// existing file only once the new one is complete.
///
/// # Errors
/// [`IoError::Image`] if the picture cannot be encoded (nothing is written); [`IoError::Io`] if
/// the file cannot be written (an existing file is left as it was).
pub fn write_png<P>(path: impl AsRef<Path>, picture: &ImageBuffer<P, Vec<P::Subpixel>>) -> Result<(), IoError>
where
    P: PixelWithColorType,
    [P::Subpixel]: EncodableLayout,
{
    let path = path.as_ref();
    let mut encoded = Cursor::new(Vec::new());
    picture.write_to(&mut encoded, ImageFormat::Png).map_err(|e| IoError::image(path, e))?;
    let bytes = encoded.into_inner();
    write_file_atomically(path, |out| out.write_all(&bytes)).map_err(|e| IoError::io(path, e))
}
