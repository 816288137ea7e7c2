//! Offscreen pictures of meshes (CPU rasterizer), for the CLI, the README and quick looks.

mod camera;
mod error;
mod raster;

pub use camera::Camera;
pub use error::RenderError;
pub use raster::{MAX_IMAGE_SIDE, Shaded, render};
