//! Offscreen pictures of meshes, for the CLI, the README and quick looks: a CPU rasterizer
//! ([`render`]), a wgpu renderer ([`GpuRenderer`], `shaders/render.wgsl`) that takes the same
//! inputs, and [`Renderer`] to pick one by [`KernelDevice`](dentbend::gpu::KernelDevice).
//! For bending bodies, [`rest_pictures`] draws the skeleton, the sub-bodies and the level set
//! of the rest state (paper Figure 12), with 2D marks (`draw_segment`, `draw_disc` at
//! `project_point`) and colours ([`bone_colour`]).

mod check;
mod error;
mod gpu;
mod gpu_frame;
mod gpu_pipeline;
mod gpu_scene;
mod gpu_target;
mod level_slices;
mod overlay;
mod palette;
mod raster;
mod renderer;
mod rest_pictures;

pub use crate::scene::Camera;
pub use error::RenderError;
pub use gpu::GpuRenderer;
pub use gpu_pipeline::RENDER_WGSL;
pub use palette::bone_colour;

pub use check::MAX_IMAGE_SIDE;
pub use raster::{Shaded, render};
pub use renderer::Renderer;
pub use rest_pictures::{RestPictures, rest_pictures};
