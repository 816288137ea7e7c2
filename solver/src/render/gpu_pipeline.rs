//! The two render pipelines of `shaders/render.wgsl` (background gradient, lit meshes) and their
//! bind-group layout, built inside error scopes; 4× MSAA when the device accepts it for the
//! colour and depth formats, else 1×.

use std::num::NonZeroU64;

use super::gpu_frame::{FrameUniform, GpuVertex, MaterialUniform, VERTEX_ATTRIBUTES};
use super::gpu_target::{COLOUR_FORMAT, DEPTH_FORMAT};
use dentbend::gpu::{GpuContext, GpuError};

/// The render shader's WGSL source (`shaders/render.wgsl`), embedded at compile time.
pub const RENDER_WGSL: &str = include_str!("../../shaders/render.wgsl");

/// Samples per pixel tried first.
const MSAA: u32 = 4;

/// The pipelines of one sample count and their shared bind-group layout.
pub(super) struct Pipelines {
    /// Group 0: `Frame` at binding 0, `Material` (dynamic offset) at binding 1.
    pub layout: wgpu::BindGroupLayout,
    /// Full-screen gradient; depth test always passes, no depth write.
    pub background: wgpu::RenderPipeline,
    /// Lit, two-sided, depth-tested triangles.
    pub meshes: wgpu::RenderPipeline,
    /// Samples per pixel (4, or 1 where the device refuses 4).
    pub samples: u32,
}

impl Pipelines {
    /// Compiles the shader and builds the pipelines with 4× MSAA, falling back to 1× (with an
    /// info line in the log) when the device reports a validation error for 4 samples.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader or the 1× pipelines do not validate,
    /// [`GpuError::OutOfMemory`], [`GpuError::DeviceLost`].
    pub fn new(context: &GpuContext) -> Result<Self, GpuError> {
        let device = &context.device;
        let (module, layout, pipeline_layout) = context.scoped("render.wgsl", || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("render.wgsl"),
                source: wgpu::ShaderSource::Wgsl(RENDER_WGSL.into()),
            });
            let layout = bind_group_layout(device);
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("render"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            (module, layout, pipeline_layout)
        })?;
        let build = |samples: u32| {
            context.scoped("render pipelines", || {
                // A throwaway texture: texture creation checks the format's sample counts too.
                probe(device, samples);
                let background = pipeline(device, &pipeline_layout, &module, Stage::Background, samples);
                let meshes = pipeline(device, &pipeline_layout, &module, Stage::Meshes, samples);
                (background, meshes)
            })
        };
        let ((background, meshes), samples) = match build(MSAA) {
            Ok(pipelines) => (pipelines, MSAA),
            Err(GpuError::Validation { message, .. }) => {
                log::info!("{MSAA}× MSAA unavailable ({message}); rendering with 1 sample per pixel");
                (build(1)?, 1)
            }
            Err(error) => return Err(error),
        };
        Ok(Self { layout, background, meshes, samples })
    }
}

/// Which entry points a pipeline uses.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Stage {
    Background,
    Meshes,
}

fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let uniform = |binding, dynamic, size: usize| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: dynamic,
            min_binding_size: NonZeroU64::new(size as u64),
        },
        count: None,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("render"),
        entries: &[uniform(0, false, size_of::<FrameUniform>()), uniform(1, true, size_of::<MaterialUniform>())],
    })
}

fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    stage: Stage,
    samples: u32,
) -> wgpu::RenderPipeline {
    let vertex_buffers = [Some(wgpu::VertexBufferLayout {
        array_stride: size_of::<GpuVertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &VERTEX_ATTRIBUTES,
    })];
    let (vertex, fragment, buffers, depth_write, compare): (_, _, &[_], _, _) = match stage {
        Stage::Background => ("vs_background", "fs_background", &[], false, wgpu::CompareFunction::Always),
        Stage::Meshes => ("vs_mesh", "fs_mesh", &vertex_buffers, true, wgpu::CompareFunction::Less),
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(match stage {
            Stage::Background => "render background",
            Stage::Meshes => "render meshes",
        }),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(vertex),
            compilation_options: Default::default(),
            buffers,
        },
        // No culling: thin dented meshes show their inside faces, which the shader lights too.
        primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(depth_write),
            depth_compare: Some(compare),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState { count: samples, ..Default::default() },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(fragment),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: COLOUR_FORMAT,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// Creates (and drops) 1×1 colour and depth textures with `samples` samples, so an unsupported
/// count shows up as a validation error in the enclosing scope.
fn probe(device: &wgpu::Device, samples: u32) {
    for format in [COLOUR_FORMAT, DEPTH_FORMAT] {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("render msaa probe"),
            size: wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        texture.destroy();
    }
}
