//! The meshes of one picture on the GPU: one interleaved vertex buffer, one index buffer (indices
//! already offset per mesh, so no base vertex is needed), one material slot per mesh at a
//! dynamic uniform offset, and the bind group tying them to the frame uniforms.

use std::num::NonZeroU64;
use std::ops::Range;

use super::Shaded;
use super::gpu_frame::{FrameUniform, GpuVertex, MaterialUniform, material};
use dentbend::gpu::{GpuContext, GpuError};

/// One indexed draw: the mesh's index range and its material's dynamic offset, bytes.
pub(super) struct Draw {
    /// Range in the index buffer, indices.
    pub indices: Range<u32>,
    /// Offset of the mesh's [`MaterialUniform`] in the material buffer, bytes.
    pub material_offset: u32,
}

/// Buffers and bind group of one picture's meshes.
pub(super) struct Scene {
    /// Interleaved [`GpuVertex`] of every mesh.
    pub vertices: wgpu::Buffer,
    /// `u32` triangle indices into `vertices`.
    pub indices: wgpu::Buffer,
    /// The [`FrameUniform`], rewritten before each tile.
    pub frame: wgpu::Buffer,
    /// Group 0: frame uniform and the material at a dynamic offset.
    pub bind_group: wgpu::BindGroup,
    /// One draw per mesh that has triangles, in the order given.
    pub draws: Vec<Draw>,
}

impl Scene {
    /// Uploads `meshes`; materials are spaced by the device's uniform offset alignment.
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] when a buffer would exceed the device's `max_buffer_size` or the
    /// vertices overflow `u32` indices.
    pub fn upload(
        context: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        meshes: &[Shaded<'_>],
    ) -> Result<Self, GpuError> {
        let stride = material_stride(context);
        let vertex_count: usize = meshes.iter().map(|m| m.mesh.vertex_count()).sum();
        let index_count: usize = meshes.iter().map(|m| 3 * m.mesh.face_count()).sum();
        check(context, "the render vertex buffer", vertex_count * size_of::<GpuVertex>())?;
        check(context, "the render index buffer", index_count * size_of::<u32>())?;
        check(context, "the render materials", meshes.len().max(1) * stride as usize)?;
        if u32::try_from(vertex_count).is_err() || u32::try_from(index_count).is_err() {
            let limit = u64::from(u32::MAX);
            return Err(GpuError::OverLimit { what: "render vertices".into(), needed: vertex_count as u64, limit });
        }
        let mut vertices = Vec::with_capacity(vertex_count);
        let mut indices = Vec::with_capacity(index_count);
        let mut materials = vec![0u8; meshes.len().max(1) * stride as usize];
        let mut draws = Vec::new();
        for (k, item) in meshes.iter().enumerate() {
            let base = vertices.len() as u32;
            let first = indices.len() as u32;
            let mesh = item.mesh;
            vertices.extend(
                mesh.positions()
                    .iter()
                    .zip(mesh.normals())
                    .map(|(p, n)| GpuVertex { position: p.to_array(), normal: n.to_array() }),
            );
            indices.extend(mesh.faces().iter().flatten().map(|&v| base + v));
            let offset = k * stride as usize;
            let slot = material(item.colour);
            let slot = bytemuck::bytes_of(&slot);
            materials[offset..offset + slot.len()].copy_from_slice(slot);
            if mesh.face_count() > 0 {
                draws.push(Draw { indices: first..indices.len() as u32, material_offset: offset as u32 });
            }
        }
        let usage = wgpu::BufferUsages::VERTEX;
        let vertices = context.buffer_with_contents("render vertices", bytemuck::cast_slice(&vertices), usage);
        let usage = wgpu::BufferUsages::INDEX;
        let indices = context.buffer_with_contents("render indices", bytemuck::cast_slice(&indices), usage);
        let materials = context.buffer_with_contents("render materials", &materials, wgpu::BufferUsages::UNIFORM);
        let frame = context.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("render frame"),
            size: size_of::<FrameUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = context.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("render"),
            layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: frame.as_entire_binding() },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &materials,
                        offset: 0,
                        size: NonZeroU64::new(size_of::<MaterialUniform>() as u64),
                    }),
                },
            ],
        });
        Ok(Self { vertices, indices, frame, bind_group, draws })
    }
}

/// Bytes between material slots: the uniform size rounded up to the device's
/// `min_uniform_buffer_offset_alignment` (256 on most devices).
fn material_stride(context: &GpuContext) -> u32 {
    let align = context.limits.min_uniform_buffer_offset_alignment.max(1);
    (size_of::<MaterialUniform>() as u32).next_multiple_of(align)
}

/// Fails if a buffer of `bytes` would exceed the device's `max_buffer_size`.
fn check(context: &GpuContext, what: &str, bytes: usize) -> Result<(), GpuError> {
    let limit = context.limits.max_buffer_size;
    if bytes as u64 > limit {
        return Err(GpuError::OverLimit { what: what.into(), needed: bytes as u64, limit });
    }
    Ok(())
}
