//! One compute pipeline per WGSL kernel, with an explicit bind-group layout, built inside error
//! scopes so a broken shader is a typed error.

use super::{GpuContext, GpuError};

/// WGSL declarations shared by every kernel, prepended to each shader: the parameter structs of
/// `src/cpu/layout.rs` (`shaders/shared/layout.wgsl`) and the sampling helpers of
/// `src/cpu/sample.rs` (`shaders/shared/sample.wgsl`).
pub const SHARED_WGSL: &str =
    concat!(include_str!("../../shaders/shared/layout.wgsl"), "\n", include_str!("../../shaders/shared/sample.wgsl"));

/// How a kernel binds one buffer, in `@binding` order of group 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Binding {
    /// `var<uniform>`.
    Uniform,
    /// `var<storage, read>`.
    Read,
    /// `var<storage, read_write>`.
    ReadWrite,
}

/// A compute pipeline and its bind-group layout.
#[derive(Debug)]
pub struct Kernel {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    label: &'static str,
}

impl Kernel {
    /// Compiles `source` (the shared declarations are prepended) with entry point `entry`.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader or its layout does not validate.
    pub fn new(
        context: &GpuContext,
        label: &'static str,
        source: &str,
        entry: &str,
        bindings: &[Binding],
    ) -> Result<Self, GpuError> {
        let device = &context.device;
        context.scoped(label, || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(format!("{SHARED_WGSL}\n{source}").into()),
            });
            let entries: Vec<wgpu::BindGroupLayoutEntry> = bindings
                .iter()
                .enumerate()
                .map(|(k, binding)| wgpu::BindGroupLayoutEntry {
                    binding: k as u32,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: match binding {
                            Binding::Uniform => wgpu::BufferBindingType::Uniform,
                            Binding::Read => wgpu::BufferBindingType::Storage { read_only: true },
                            Binding::ReadWrite => wgpu::BufferBindingType::Storage { read_only: false },
                        },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                })
                .collect();
            let layout = device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries: &entries });
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            });
            Self { pipeline, layout, label }
        })
    }

    /// A bind group of `buffers` in binding order.
    pub fn bind(&self, context: &GpuContext, buffers: &[&wgpu::Buffer]) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry> = buffers
            .iter()
            .enumerate()
            .map(|(k, buffer)| wgpu::BindGroupEntry { binding: k as u32, resource: buffer.as_entire_binding() })
            .collect();
        context.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.label),
            layout: &self.layout,
            entries: &entries,
        })
    }

    /// A bind group of buffer ranges in binding order (for a caller's buffer bound from an
    /// offset).
    pub fn bind_ranges(&self, context: &GpuContext, ranges: &[wgpu::BufferBinding<'_>]) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry> = ranges
            .iter()
            .enumerate()
            .map(|(k, range)| wgpu::BindGroupEntry {
                binding: k as u32,
                resource: wgpu::BindingResource::Buffer(range.clone()),
            })
            .collect();
        context.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.label),
            layout: &self.layout,
            entries: &entries,
        })
    }

    /// Records one dispatch of `workgroups` (x, y, z) with `bind_group`.
    pub fn dispatch(&self, encoder: &mut wgpu::CommandEncoder, bind_group: &wgpu::BindGroup, workgroups: [u32; 3]) {
        let mut pass = encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(self.label), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(workgroups[0], workgroups[1], workgroups[2]);
    }

    /// Records one dispatch per `(bind group, workgroups)` in one compute pass, in order (for many
    /// small independent dispatches, such as one per skinned mesh).
    pub fn dispatch_all(&self, encoder: &mut wgpu::CommandEncoder, dispatches: &[(&wgpu::BindGroup, [u32; 3])]) {
        let mut pass = encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(self.label), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        for (bind_group, [x, y, z]) in dispatches {
            pass.set_bind_group(0, *bind_group, &[]);
            pass.dispatch_workgroups(*x, *y, *z);
        }
    }
}
