//! The GPU renderer: the same pictures as [`render`](super::render) (same inputs, same checks),
//! drawn by `shaders/render.wgsl` on wgpu with a depth buffer and 4× MSAA where available, and
//! read back through a staging buffer.

use image::RgbImage;

use super::gpu_frame::{FrameUniform, Tile, tiles};
use super::gpu_pipeline::Pipelines;
use super::gpu_scene::Scene;
use super::gpu_target::Targets;
use super::{Camera, RenderError, Shaded, check};
use dentbend::gpu::{GpuContext, GpuError};

/// Largest tile side drawn in one pass, pixels: bounds the render targets' memory (4 samples ×
/// (4 + 4) bytes × 2048² = 128 MiB) on top of the device's `max_texture_dimension_2d`.
pub(crate) const MAX_TILE_SIDE: u32 = 2048;

/// Draws shaded pictures of meshes on a GPU.
///
/// Lighting (linear RGB, then sRGB-encoded by the Rgba8UnormSrgb target): a key light from the
/// upper left of the picture and in front, a dim fill from the lower right, a hemispherical
/// ambient around the picture's up direction and a modest Blinn–Phong highlight, two-sided;
/// the background is a soft vertical gradient (lightest at the top). Pictures larger than a
/// tile (the device's `max_texture_dimension_2d`, at most 2,048) are drawn tile by
/// tile, so every size the CPU renderer accepts works here too.
///
/// # Example
/// ```no_run
/// use dentbend::{glam::Vec3, gpu::shared_context, mesh};
/// use dentbend_solver::render::{Camera, GpuRenderer, Shaded};
///
/// let context = shared_context()?;
/// let renderer = GpuRenderer::new(context)?;
/// let sphere = mesh::builtin("sphere")?;
/// let camera = Camera::framing(sphere.bounds(), -Vec3::Z, Vec3::Y);
/// let picture = renderer.render(&[Shaded { mesh: &sphere, colour: [0.8, 0.3, 0.2] }], &camera, 320, 240)?;
/// picture.save("/tmp/sphere.png")?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct GpuRenderer<'c> {
    context: &'c GpuContext,
    pipelines: Pipelines,
    tile_side: u32,
}

impl std::fmt::Debug for GpuRenderer<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuRenderer")
            .field("adapter", &self.context.adapter_name())
            .field("samples", &self.pipelines.samples)
            .field("tile_side", &self.tile_side)
            .finish()
    }
}

impl<'c> GpuRenderer<'c> {
    /// Builds the pipelines once on `context`.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader or pipelines do not validate,
    /// [`GpuError::OutOfMemory`], [`GpuError::DeviceLost`].
    pub fn new(context: &'c GpuContext) -> Result<Self, GpuError> {
        context.check_alive()?;
        let pipelines = Pipelines::new(context)?;
        let tile_side = context.limits.max_texture_dimension_2d.clamp(1, MAX_TILE_SIDE);
        log::debug!("GPU renderer: {} samples per pixel, tiles of up to {tile_side} px", pipelines.samples);
        Ok(Self { context, pipelines, tile_side })
    }

    /// The context the renderer draws on.
    pub fn context(&self) -> &'c GpuContext {
        self.context
    }

    /// Samples per pixel: 4 (MSAA) where the device supports it, else 1.
    pub fn sample_count(&self) -> u32 {
        self.pipelines.samples
    }

    /// Largest tile side drawn in one pass, pixels.
    pub fn tile_side(&self) -> u32 {
        self.tile_side
    }

    /// Draws pictures in tiles of at most `side × side` pixels (clamped to `1..=` the current
    /// [`tile_side`](Self::tile_side)): less GPU memory per pass, same picture.
    #[must_use]
    pub fn with_tile_side(mut self, side: u32) -> Self {
        self.tile_side = side.clamp(1, self.tile_side);
        self
    }

    /// Renders `meshes` seen by `camera` into a `width × height` picture (8-bit sRGB), exactly
    /// like [`render`](super::render) takes them; an empty list gives the background alone.
    ///
    /// # Errors
    /// [`RenderError::ImageSize`] for a side outside `1..=`[`MAX_IMAGE_SIDE`](super::MAX_IMAGE_SIDE),
    /// [`RenderError::Camera`] for an unusable camera (non-finite, eye on target, up parallel to
    /// the view, field of view outside 1..179°), [`RenderError::Gpu`] when the device fails
    /// (validation, out of memory, over a buffer limit, lost, read-back).
    pub fn render(
        &self,
        meshes: &[Shaded<'_>],
        camera: &Camera,
        width: u32,
        height: u32,
    ) -> Result<RgbImage, RenderError> {
        check::image_size(width, height)?;
        check::camera(camera)?;
        let context = self.context;
        context.check_alive()?;
        let (tile_width, tile_height) = (width.min(self.tile_side), height.min(self.tile_side));
        let (scene, targets) = context.scoped("render upload", || {
            let scene = Scene::upload(context, &self.pipelines.layout, meshes);
            (scene, Targets::new(context, tile_width, tile_height, self.pipelines.samples))
        })?;
        let scene = scene?;
        let mut picture = RgbImage::new(width, height);
        for tile in tiles(width, height, self.tile_side) {
            context.scoped("render tile", || {
                let frame = FrameUniform::new(camera, width, height, tile);
                context.queue.write_buffer(&scene.frame, 0, bytemuck::bytes_of(&frame));
                let mut encoder = context.device.create_command_encoder(&Default::default());
                self.draw(&mut encoder, &scene, &targets, tile);
                targets.copy_out(&mut encoder, tile);
                context.queue.submit([encoder.finish()]);
            })?;
            targets.read_into(context, &mut picture, tile)?;
        }
        Ok(picture)
    }

    /// Records one pass over `tile`: background, then every mesh.
    fn draw(&self, encoder: &mut wgpu::CommandEncoder, scene: &Scene, targets: &Targets, tile: Tile) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("render"),
            color_attachments: &[Some(targets.colour_attachment())],
            depth_stencil_attachment: Some(targets.depth_attachment()),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        // Edge tiles are smaller than the targets: draw into their top-left corner.
        pass.set_viewport(0.0, 0.0, tile.width as f32, tile.height as f32, 0.0, 1.0);
        pass.set_scissor_rect(0, 0, tile.width, tile.height);
        pass.set_pipeline(&self.pipelines.background);
        pass.set_bind_group(0, &scene.bind_group, &[0]);
        pass.draw(0..3, 0..1);
        if scene.draws.is_empty() {
            return;
        }
        pass.set_pipeline(&self.pipelines.meshes);
        pass.set_vertex_buffer(0, scene.vertices.slice(..));
        pass.set_index_buffer(scene.indices.slice(..), wgpu::IndexFormat::Uint32);
        for draw in &scene.draws {
            pass.set_bind_group(0, &scene.bind_group, &[draw.material_offset]);
            pass.draw_indexed(draw.indices.clone(), 0, 0..1);
        }
    }
}
