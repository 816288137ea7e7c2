//! GPU twin of the CPU `interleave` kernel: writes a resident target's positions
//! and normals into a caller's interleaved vertex buffer (an engine's own layout, at an offset
//! and stride), recorded into the caller's encoder with no read-back.

use super::{Binding, GpuContext, GpuError, Kernel, buffers};
use crate::cpu::{InterleaveParams, NO_NORMAL};

/// Invocations per workgroup along x. Keep in sync with `WORKGROUP` in `shaders/interleave.wgsl`.
pub(crate) const WORKGROUP: u32 = 64;

/// Bytes of one field written per vertex: three f32.
const FIELD_BYTES: u64 = 12;

/// Where the fields go within each vertex of the destination, bytes from the vertex's start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VertexLayout {
    /// Byte offset of the position (three f32, world units) within a vertex.
    pub position: u64,
    /// Byte offset of the unit normal (three f32) within a vertex; `None` copies positions only.
    pub normal: Option<u64>,
}

impl VertexLayout {
    /// Position at byte 0 and normal at byte 12 (Bevy's and most engines' first two attributes).
    pub const POSITION_NORMAL: Self = Self { position: 0, normal: Some(12) };
}

/// Why an interleaved copy was refused; nothing was recorded.
#[derive(Debug, Clone, thiserror::Error)]
pub enum InterleaveError {
    /// A byte quantity is not a multiple of 4 (the kernel writes whole f32 words).
    #[error("{what} = {value} bytes is not a multiple of 4")]
    Misaligned {
        /// `offset`, `stride`, `position` or `normal`.
        what: &'static str,
        /// The value given, bytes.
        value: u64,
    },
    /// A field does not fit within one vertex, or the position and normal overlap.
    #[error("the {what} field at byte {at} (12 bytes) does not fit a {stride}-byte vertex beside the other field")]
    BadLayout {
        /// `position` or `normal`.
        what: &'static str,
        /// Its byte offset within a vertex.
        at: u64,
        /// The stride, bytes.
        stride: u64,
    },
    /// The destination is too small for the target's vertices at this offset and stride.
    #[error("the destination holds {size} bytes; the copy writes up to byte {needed}")]
    TooSmall {
        /// Bytes the copy needs (end of the last written field).
        needed: u64,
        /// The destination's size, bytes.
        size: u64,
    },
    /// The destination buffer was created without `STORAGE` usage (the kernel writes it).
    #[error("the destination buffer needs STORAGE usage (it has {0:?})")]
    NotStorage(wgpu::BufferUsages),
    /// No resident target has this index.
    #[error("target {target} does not exist (the denter holds {count})")]
    UnknownTarget {
        /// The index given.
        target: usize,
        /// Resident targets.
        count: usize,
    },
    /// The device refused the copy (limits, validation, a lost device).
    #[error(transparent)]
    Gpu(#[from] GpuError),
}

/// A checked copy: the kernel's parameters and the byte range of the destination to bind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InterleavePlan {
    /// The kernel's parameters.
    pub params: InterleaveParams,
    /// First byte of the destination bound (a multiple of the device's storage offset alignment).
    pub bind_offset: u64,
    /// Bytes bound.
    pub bind_size: u64,
}

/// Checks a copy of `vertex_count` vertices (from `vertex_offset` in the resident buffers) to a
/// destination of `dst_size` bytes, vertex 0 at byte `offset`, `stride` bytes apart, and plans it.
///
/// # Errors
/// [`InterleaveError::Misaligned`], [`InterleaveError::BadLayout`], [`InterleaveError::TooSmall`];
/// [`GpuError::OverLimit`] when the bound range exceeds the device's binding limit or the
/// vertices its dispatch limit.
pub fn plan(
    context: &GpuContext,
    vertex_offset: u32,
    vertex_count: u32,
    dst_size: u64,
    offset: u64,
    stride: u64,
    layout: VertexLayout,
) -> Result<InterleavePlan, InterleaveError> {
    let fields = [("position", Some(layout.position)), ("normal", layout.normal)];
    for (what, value) in
        [("offset", offset), ("stride", stride)].into_iter().chain(fields.map(|(w, v)| (w, v.unwrap_or(0))))
    {
        if value % 4 != 0 {
            return Err(InterleaveError::Misaligned { what, value });
        }
    }
    for (what, at) in fields.iter().filter_map(|(w, v)| v.map(|v| (*w, v))) {
        let overlaps = layout.normal.is_some_and(|n| layout.position.abs_diff(n) < FIELD_BYTES);
        if at.checked_add(FIELD_BYTES).is_none_or(|end| end > stride) || overlaps {
            return Err(InterleaveError::BadLayout { what, at, stride });
        }
    }
    let last_field = layout.position.max(layout.normal.unwrap_or(0)) + FIELD_BYTES;
    let needed = u64::from(vertex_count.saturating_sub(1))
        .checked_mul(stride)
        .and_then(|b| b.checked_add(offset))
        .and_then(|b| b.checked_add(last_field))
        .unwrap_or(u64::MAX);
    if needed > dst_size {
        return Err(InterleaveError::TooSmall { needed, size: dst_size });
    }
    let align = u64::from(context.limits.min_storage_buffer_offset_alignment.max(4));
    let bind_offset = offset / align * align;
    let bind_size = needed - bind_offset;
    buffers::check_binding_size(context, "interleaved destination range", bind_size)?;
    let groups = vertex_count.div_ceil(WORKGROUP);
    let limit = context.limits.max_compute_workgroups_per_dimension;
    if groups > limit {
        let what = "interleave workgroups (vertices / WORKGROUP)".into();
        return Err(GpuError::OverLimit { what, needed: groups.into(), limit: limit.into() }.into());
    }
    let words = |bytes: u64| u32::try_from(bytes / 4).unwrap_or(u32::MAX);
    let params = InterleaveParams {
        vertex_offset,
        vertex_count,
        dst_word: words(offset - bind_offset),
        stride_words: words(stride),
        position_word: words(layout.position),
        normal_word: layout.normal.map_or(NO_NORMAL, words),
        _pad: [0; 2],
    };
    Ok(InterleavePlan { params, bind_offset, bind_size })
}

/// The `interleave` kernel, compiled once.
#[derive(Debug)]
pub struct Interleave {
    kernel: Kernel,
}

impl Interleave {
    /// Compiles the kernel.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader does not compile on this device.
    pub fn new(context: &GpuContext) -> Result<Self, GpuError> {
        let bindings = [Binding::Uniform, Binding::Read, Binding::Read, Binding::ReadWrite];
        let kernel = Kernel::new(context, "interleave", super::shaders::body("interleave"), "main", &bindings)?;
        Ok(Self { kernel })
    }

    /// Records the copy `plan` describes from `positions` and `normals` (`vec4` per vertex) into
    /// `dst`, which must have `STORAGE` usage and be on `context`'s device.
    ///
    /// # Errors
    /// [`InterleaveError::NotStorage`]; [`GpuError::Validation`] if wgpu refuses the binding
    /// (e.g. a buffer of another device).
    pub fn encode(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        plan: &InterleavePlan,
        positions: &wgpu::Buffer,
        normals: &wgpu::Buffer,
        dst: &wgpu::Buffer,
    ) -> Result<(), InterleaveError> {
        if !dst.usage().contains(wgpu::BufferUsages::STORAGE) {
            return Err(InterleaveError::NotStorage(dst.usage()));
        }
        if plan.params.vertex_count == 0 {
            return Ok(());
        }
        context.scoped("interleave", || {
            let uniform = buffers::uniform(context, "interleave params", &plan.params);
            let dst_range = wgpu::BufferBinding {
                buffer: dst,
                offset: plan.bind_offset,
                size: std::num::NonZeroU64::new(plan.bind_size),
            };
            let bind = self.kernel.bind_ranges(
                context,
                &[
                    uniform.as_entire_buffer_binding(),
                    positions.as_entire_buffer_binding(),
                    normals.as_entire_buffer_binding(),
                    dst_range,
                ],
            );
            self.kernel.dispatch(encoder, &bind, [plan.params.vertex_count.div_ceil(WORKGROUP), 1, 1]);
        })?;
        Ok(())
    }
}
