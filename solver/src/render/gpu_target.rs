//! The textures one picture tile is drawn into (colour, optional MSAA resolve, depth) and the
//! read-back of a finished tile into the picture, rows padded to
//! [`wgpu::COPY_BYTES_PER_ROW_ALIGNMENT`].

use image::RgbImage;

use super::gpu_frame::Tile;
use dentbend::gpu::{GpuContext, GpuError};

/// Colour format drawn into: 8-bit sRGB, so shaders write linear colour and the hardware encodes.
pub(super) const COLOUR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Depth format.
pub(super) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Bytes per pixel of [`COLOUR_FORMAT`].
const PIXEL_BYTES: u32 = 4;

/// Render targets sized to the largest tile of a picture, and the staging buffer its pixels
/// come back through.
pub(super) struct Targets {
    /// Drawn into: multisampled when `samples > 1`, else the output itself.
    colour: wgpu::TextureView,
    /// Single-sample resolve target when `samples > 1`.
    resolve: Option<wgpu::TextureView>,
    /// The single-sample texture copied out (the resolve target, or the colour target).
    output: wgpu::Texture,
    depth: wgpu::TextureView,
    staging: wgpu::Buffer,
    /// Row pitch of `staging`, bytes (a multiple of 256).
    bytes_per_row: u32,
}

impl Targets {
    /// Targets of `width × height` pixels (the largest tile) with `samples` samples per pixel.
    pub fn new(context: &GpuContext, width: u32, height: u32, samples: u32) -> Self {
        let device = &context.device;
        let size = wgpu::Extent3d { width, height, depth_or_array_layers: 1 };
        let texture = |label, format, samples, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let output = texture("render output", COLOUR_FORMAT, 1, attachment | wgpu::TextureUsages::COPY_SRC);
        let (colour, resolve) = if samples > 1 {
            let msaa = texture("render msaa colour", COLOUR_FORMAT, samples, attachment);
            (msaa.create_view(&Default::default()), Some(output.create_view(&Default::default())))
        } else {
            (output.create_view(&Default::default()), None)
        };
        let depth = texture("render depth", DEPTH_FORMAT, samples, attachment).create_view(&Default::default());
        let bytes_per_row = (width * PIXEL_BYTES).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("render read back"),
            size: u64::from(bytes_per_row) * u64::from(height),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self { colour, resolve, output, depth, staging, bytes_per_row }
    }

    /// The colour attachment, cleared to black (the background pass covers it).
    pub fn colour_attachment(&self) -> wgpu::RenderPassColorAttachment<'_> {
        // Multisampled samples are only needed until resolved.
        let store = if self.resolve.is_some() { wgpu::StoreOp::Discard } else { wgpu::StoreOp::Store };
        wgpu::RenderPassColorAttachment {
            view: &self.colour,
            depth_slice: None,
            resolve_target: self.resolve.as_ref(),
            ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::BLACK), store },
        }
    }

    /// The depth attachment, cleared to the far plane (1) and discarded after the pass.
    pub fn depth_attachment(&self) -> wgpu::RenderPassDepthStencilAttachment<'_> {
        wgpu::RenderPassDepthStencilAttachment {
            view: &self.depth,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
            stencil_ops: None,
        }
    }

    /// Records the copy of the tile's pixels (at the output's top-left corner) to the staging
    /// buffer.
    pub fn copy_out(&self, encoder: &mut wgpu::CommandEncoder, tile: Tile) {
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &self.output,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.staging,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.bytes_per_row),
                    rows_per_image: Some(tile.height),
                },
            },
            wgpu::Extent3d { width: tile.width, height: tile.height, depth_or_array_layers: 1 },
        );
    }

    /// Waits for the submitted copy of `tile` and writes its pixels (alpha dropped) into
    /// `picture` at the tile's place.
    ///
    /// # Errors
    /// [`GpuError::Wait`] if mapping fails or times out, [`GpuError::DeviceLost`].
    pub fn read_into(&self, context: &GpuContext, picture: &mut RgbImage, tile: Tile) -> Result<(), GpuError> {
        let slice = self.staging.slice(..u64::from(self.bytes_per_row) * u64::from(tile.height));
        let (sender, receiver) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |result| {
            let _ = sender.send(result);
        });
        context.wait()?;
        receiver
            .recv_timeout(GpuContext::WAIT_TIMEOUT)
            .map_err(|e| GpuError::Wait(e.to_string()))?
            .map_err(|e| GpuError::Wait(e.to_string()))?;
        let data = slice.get_mapped_range().map_err(|e| GpuError::Wait(e.to_string()))?;
        for row in 0..tile.height {
            let start = (row * self.bytes_per_row) as usize;
            let pixels = &data[start..start + (tile.width * PIXEL_BYTES) as usize];
            for (column, rgba) in pixels.chunks_exact(PIXEL_BYTES as usize).enumerate() {
                picture.put_pixel(tile.x + column as u32, tile.y + row, image::Rgb([rgba[0], rgba[1], rgba[2]]));
            }
        }
        drop(data);
        self.staging.unmap();
        Ok(())
    }
}
