//! Offscreen pictures of meshes, for the CLI, the README and quick looks: a CPU rasterizer
//! ([`render`]), a wgpu renderer ([`GpuRenderer`], `shaders/render.wgsl`) that takes the same
//! inputs, and [`Renderer`] / [`render_auto`] to pick one by [`Backend`](crate::gpu::Backend).

mod camera;
mod check;
mod error;
mod gpu;
mod gpu_frame;
mod gpu_pipeline;
mod gpu_scene;
mod gpu_target;
mod raster;
mod renderer;

pub use camera::Camera;
pub use error::RenderError;
pub use gpu::{GpuRenderer, MAX_TILE_SIDE};
pub use gpu_pipeline::RENDER_WGSL;
pub use raster::{MAX_IMAGE_SIDE, Shaded, render};
pub use renderer::{Renderer, render_auto};
