//! Where a GPU batch records its commands: an encoder of its own (submitted by the batch, and
//! when timing submitted and waited on after every kernel stage) or the caller's encoder (left
//! for the caller to submit).

use super::{GpuContext, GpuError};

/// Seconds spent in each kernel stage (`zbuffer`, `envelope_rows`, `envelope_cols`, `heat`,
/// `glance`, `displace`, `normals`), summed over a batch's chunks.
pub type KernelTimes = std::collections::BTreeMap<&'static str, f64>;

/// The encoder a [`Recorder`] writes to.
enum Slot<'a> {
    /// The recorder's own, finished into a command buffer by [`Recorder::finish`].
    Own(wgpu::CommandEncoder),
    /// The caller's, which the caller submits.
    Caller(&'a mut wgpu::CommandEncoder),
}

/// A command encoder that, when timing, submits and waits at the end of every stage and records
/// how long the stage took: its GPU time from timestamp queries where the device has them,
/// else the wall time of submit-and-wait. A recorder on the caller's encoder never times.
pub(super) struct Recorder<'a> {
    context: &'a GpuContext,
    slot: Slot<'a>,
    timings: Option<&'a mut KernelTimes>,
    started: std::time::Instant,
    stamps: Option<(wgpu::QuerySet, wgpu::Buffer)>,
}

impl<'a> Recorder<'a> {
    /// A recorder on a new encoder of its own, timing into `timings` when given.
    pub(super) fn new(context: &'a GpuContext, timings: Option<&'a mut KernelTimes>) -> Self {
        let mut encoder = context.device.create_command_encoder(&Default::default());
        let stamps = (timings.is_some() && context.timestamps).then(|| {
            let set = context.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("stage timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            });
            let resolved = context.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("stage timestamps"),
                size: 16,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            encoder.write_timestamp(&set, 0);
            (set, resolved)
        });
        Self { context, slot: Slot::Own(encoder), timings, started: std::time::Instant::now(), stamps }
    }

    /// A recorder on the caller's `encoder`: it records only, never submits, waits or times.
    pub(super) fn caller(context: &'a GpuContext, encoder: &'a mut wgpu::CommandEncoder) -> Self {
        Self { context, slot: Slot::Caller(encoder), timings: None, started: std::time::Instant::now(), stamps: None }
    }

    /// The encoder to record into.
    pub(super) fn encoder(&mut self) -> &mut wgpu::CommandEncoder {
        match &mut self.slot {
            Slot::Own(encoder) => encoder,
            Slot::Caller(encoder) => encoder,
        }
    }

    /// Ends stage `name`: when timing, submits what was recorded, waits, and adds the time.
    pub(super) fn stage(&mut self, name: &'static str) -> Result<(), GpuError> {
        let Some(timings) = self.timings.as_deref_mut() else { return Ok(()) };
        let Slot::Own(encoder) = &mut self.slot else { return Ok(()) };
        if let Some((set, resolved)) = &self.stamps {
            encoder.write_timestamp(set, 1);
            encoder.resolve_query_set(set, 0..2, resolved, 0);
        }
        let done = std::mem::replace(encoder, self.context.device.create_command_encoder(&Default::default()));
        self.context.queue.submit([done.finish()]);
        self.context.wait()?;
        let seconds = match &self.stamps {
            Some((set, resolved)) => {
                let ticks: Vec<u64> = super::buffers::read_back(self.context, resolved, 2)?;
                encoder.write_timestamp(set, 0);
                let period_ns = f64::from(self.context.queue.get_timestamp_period());
                ticks[1].saturating_sub(ticks[0]) as f64 * period_ns * 1e-9
            }
            None => self.started.elapsed().as_secs_f64(),
        };
        *timings.entry(name).or_default() += seconds;
        self.started = std::time::Instant::now();
        Ok(())
    }

    /// Finishes what is left in an encoder of its own into a command buffer for the caller to
    /// submit; `None` on the caller's encoder.
    pub(super) fn finish(self) -> Option<wgpu::CommandBuffer> {
        match self.slot {
            Slot::Own(encoder) => Some(encoder.finish()),
            Slot::Caller(_) => None,
        }
    }
}
