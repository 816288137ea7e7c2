//! The map-building buffers a [`GpuDenter`](super::GpuDenter) keeps from one batch to the next.
//!
//! A batch of 1,024 dents at 100² needs about 400 MB of grid and map buffers. Allocating them
//! afresh every batch costs the driver a large allocation (and wgpu its zeroing) each time; the
//! arena keeps the largest seen and grows a buffer by half again when a batch needs more.
//!
//! Nothing is cleared between batches: every kernel writes each cell of its outputs before any
//! kernel reads it (the Z-buffer clears its own work buffer; the envelope passes emit every cell
//! of every line and fill the hull scratch before reading it; heat, glance and the smoothed copy
//! write every cell of every dent), so what an earlier batch left is never read.
//! `tests/parity_pipeline.rs` checks that a batch after a larger one gives the same bits as on a
//! fresh denter.

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
    /// A buffer of at least `bytes` bytes (a multiple of 4) for `slot`, holding whatever the
    /// last batch left. An existing buffer large enough is reused; otherwise a new one, half again
    /// as large as the old one where that stays within the device's binding and buffer limits,
    /// replaces it (wgpu keeps the old one alive until the work already recorded on it has run).
    /// A need past the binding limit gets a buffer of its own that is not kept: the kernel then
    /// refuses the chunk, and later batches are not burdened with it.
    pub(super) fn take(&mut self, context: &GpuContext, slot: Slot, bytes: u64) -> wgpu::Buffer {
        let limits = &context.limits;
        // Rounded down to a multiple of 4, so rounding the size up never passes the limit.
        let cap = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size) & !3;
        if bytes > cap {
            return buffers::storage_zeroed(context, slot.label(), bytes);
        }
        let held = &mut self.buffers[slot as usize];
        match held {
            Some(buffer) if buffer.size() >= bytes => buffer.clone(),
            _ => {
                let old = held.as_ref().map_or(0, wgpu::Buffer::size);
                let buffer = buffers::storage_zeroed(context, slot.label(), bytes.max((old + old / 2).min(cap)));
                *held = Some(buffer.clone());
                buffer
            }
        }
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
