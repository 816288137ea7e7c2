//! The map-building buffers a [`GpuDenter`](super::GpuDenter) keeps from one batch to the next.
//!
//! A batch of 1,024 dents at 100² needs about 400 MB of grid and map buffers. Allocating them
//! afresh every batch costs the driver a large allocation (and its zeroing) each time; the arena
//! keeps the largest seen, grows a buffer by half again when a batch needs more, and clears only
//! the bytes a chunk uses before its kernels run, so every chunk still starts from zeros as a
//! fresh buffer would.

use crate::gpu::{GpuContext, buffers};

/// Which buffer of a chunk's map building.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Slot {
    /// Z-buffer profiles and tip words (the `zbuffer` kernel clears it itself).
    Work,
    /// Envelope rows pass output, then the heat steps' ping-pong scratch.
    Rows,
    /// Envelope, smoothed in place unless the stages are read back.
    Envelope,
    /// Lower-hull scratch of the envelope passes.
    Scratch,
    /// Dent maps, `vec4<f32>` per map cell.
    Map,
    /// A copy of the envelope for the heat steps when the envelope itself is read back.
    Smoothed,
}

impl Slot {
    const COUNT: usize = 6;

    fn label(self) -> &'static str {
        match self {
            Slot::Work => "zbuffer work",
            Slot::Rows => "envelope rows",
            Slot::Envelope => "envelope",
            Slot::Scratch => "envelope scratch",
            Slot::Map => "dent maps",
            Slot::Smoothed => "smoothed",
        }
    }
}

/// Reusable storage buffers, one per [`Slot`].
#[derive(Debug, Default)]
pub(super) struct Arena {
    buffers: [Option<wgpu::Buffer>; Slot::COUNT],
}

impl Arena {
    /// A buffer of at least `bytes` bytes for `slot`, its first `bytes` (rounded up to 4)
    /// cleared to zero in `encoder` before anything recorded after this call. An existing buffer
    /// large enough is reused; otherwise a new one, half again as large as the old one where that
    /// stays within the device's binding limit, replaces it (wgpu keeps the old one alive until
    /// the work already recorded on it has run).
    pub(super) fn take(
        &mut self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        slot: Slot,
        bytes: u64,
    ) -> wgpu::Buffer {
        let bytes = bytes.next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        let held = &mut self.buffers[slot as usize];
        let buffer = match held {
            Some(buffer) if buffer.size() >= bytes => buffer.clone(),
            _ => {
                let old = held.as_ref().map_or(0, wgpu::Buffer::size);
                let grown = (old + old / 2).min(context.limits.max_storage_buffer_binding_size);
                let size = bytes.max(grown).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
                let buffer = buffers::storage_zeroed(context, slot.label(), size);
                *held = Some(buffer.clone());
                buffer
            }
        };
        if slot != Slot::Work && bytes > 0 {
            encoder.clear_buffer(&buffer, 0, Some(bytes));
        }
        buffer
    }

    /// Bytes held across every slot.
    pub(super) fn bytes(&self) -> u64 {
        self.buffers.iter().flatten().map(wgpu::Buffer::size).sum()
    }

    /// Drops every buffer (wgpu frees each once the work recorded on it has run).
    pub(super) fn release(&mut self) {
        self.buffers = Default::default();
    }
}
