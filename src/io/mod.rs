//! Files for people and other tools: NumPy `.npy` arrays, PNG heat maps, grayscale height maps.

mod error;
mod heatmap;
mod height_png;
mod npy;
mod png;

pub use error::IoError;
pub use heatmap::{heatmap_rgb, write_heatmap_png};
pub use height_png::{HeightImage, read_height_png, write_height_png16};
pub(crate) use height_png::{decode_height_png_within, read_height_png_within};
pub use npy::{read_npy_f32, write_npy_f32};
pub use png::write_png;
