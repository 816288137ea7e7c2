//! Choosing the renderer: the GPU one when a context is available, else the CPU rasterizer,
//! following [`KernelDevice`] (`DENTBEND_BACKEND=cpu|gpu|auto`) like the dent kernels do.

use std::sync::OnceLock;

use image::RgbImage;

use super::{Camera, GpuRenderer, RenderError, Shaded, render};
use dentbend::gpu::{GpuContext, KernelDevice};

/// A renderer of either kind; both draw the same inputs into pictures of the same size.
#[derive(Debug)]
pub enum Renderer<'c> {
    /// The wgpu renderer ([`GpuRenderer`]).
    Gpu(GpuRenderer<'c>),
    /// The CPU rasterizer ([`render`]).
    Cpu,
}

impl<'c> Renderer<'c> {
    /// The GPU renderer on `context`, or the CPU rasterizer for `None`; logs (once per process
    /// and kind) which one draws.
    ///
    /// # Errors
    /// [`RenderError::Gpu`] if the GPU pipelines cannot be built.
    pub fn new(context: Option<&'c GpuContext>) -> Result<Self, RenderError> {
        let renderer = match context {
            Some(context) => Self::Gpu(GpuRenderer::new(context)?),
            None => Self::Cpu,
        };
        renderer.announce();
        Ok(renderer)
    }

    /// Whether pictures are drawn on the GPU.
    pub fn is_gpu(&self) -> bool {
        matches!(self, Self::Gpu(_))
    }

    /// Renders `meshes` seen by `camera` into a `width × height` picture with this renderer.
    ///
    /// # Errors
    /// As [`render`] and [`GpuRenderer::render`].
    pub fn render(
        &self,
        meshes: &[Shaded<'_>],
        camera: &Camera,
        width: u32,
        height: u32,
    ) -> Result<RgbImage, RenderError> {
        match self {
            Self::Gpu(gpu) => gpu.render(meshes, camera, width, height),
            Self::Cpu => render(meshes, camera, width, height),
        }
    }

    fn announce(&self) {
        static GPU: OnceLock<()> = OnceLock::new();
        static CPU: OnceLock<()> = OnceLock::new();
        match self {
            Self::Gpu(gpu) => GPU.get_or_init(|| {
                let adapter = gpu.context().adapter_name();
                log::info!("pictures drawn on the GPU: {adapter}, {}× MSAA", gpu.sample_count());
            }),
            Self::Cpu => CPU.get_or_init(|| log::info!("pictures drawn by the CPU rasterizer")),
        };
    }
}

impl Renderer<'static> {
    /// The renderer `backend` selects on the process-wide context: `Cpu` → CPU; `Gpu` → GPU or
    /// an error; `Auto` → GPU when an adapter exists and its pipelines build, else the CPU with
    /// one notice.
    ///
    /// # Errors
    /// For `Gpu`, [`RenderError::Gpu`] when no device or pipeline can be created.
    pub fn from_backend(backend: KernelDevice) -> Result<Self, RenderError> {
        let context = backend.context()?;
        match (backend, Self::new(context)) {
            (KernelDevice::Auto, Err(error)) => {
                static NOTICE: OnceLock<()> = OnceLock::new();
                NOTICE.get_or_init(|| log::warn!("{error}; drawing pictures on the CPU instead"));
                Self::new(None)
            }
            (_, result) => result,
        }
    }
}
