//! GPU twin of [`cpu::moved`](crate::cpu::moved): compacts the vertices of one resident target
//! that the last batch moved (the `w` flag `displace` sets) into a short list, and reads back only
//! that list, for a physics engine to refit its collider.
//!
//! The kernel appends through an atomic counter, so slots come in no fixed order; the host sorts
//! them by vertex index, which makes the result equal to the CPU twin's.

use std::ops::Range;
use std::sync::{Arc, OnceLock};

use glam::Vec3;

use super::{Binding, GpuContext, GpuError, Kernel, buffers};
use crate::cpu::MovedParams;

/// Invocations per workgroup along x. Keep in sync with `WORKGROUP` in `shaders/moved.wgsl`.
pub(crate) const WORKGROUP: u32 = 64;

/// The vertices of one target that moved in the last batch, in ascending index order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MovedVertices {
    /// Vertex indices within the target (as in its mesh).
    pub indices: Vec<u32>,
    /// Their new positions, world units, one per index.
    pub positions: Vec<Vec3>,
}

impl MovedVertices {
    /// Sorts compacted `[index, x bits, y bits, z bits]` slots into ascending index order.
    pub fn from_slots(mut slots: Vec<[u32; 4]>) -> Self {
        slots.sort_unstable_by_key(|s| s[0]);
        let indices = slots.iter().map(|s| s[0]).collect();
        let positions =
            slots.iter().map(|s| Vec3::new(f32::from_bits(s[1]), f32::from_bits(s[2]), f32::from_bits(s[3])));
        Self { indices, positions: positions.collect() }
    }
}

/// The `moved` kernel, compiled once.
#[derive(Debug)]
pub struct Moved {
    kernel: Kernel,
}

impl Moved {
    /// Compiles the kernel.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader does not compile on this device.
    pub fn new(context: &GpuContext) -> Result<Self, GpuError> {
        let bindings = [Binding::Uniform, Binding::Read, Binding::ReadWrite, Binding::ReadWrite];
        let kernel = Kernel::new(context, "moved", super::shaders::body("moved"), "main", &bindings)?;
        Ok(Self { kernel })
    }

    /// Compacts the moved vertices of the target `params` names in `positions` (`vec4` per
    /// vertex: xyz world units, w moved flag) and reads back the count, then only that many slots
    /// (16 bytes each): two small waits, no read-back of unmoved vertices.
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] when the target has more than 4,194,240 (65,535 workgroups of 64) vertices or
    /// its list exceeds the binding limit; device errors.
    pub fn run(
        &self,
        context: &GpuContext,
        params: MovedParams,
        positions: &wgpu::Buffer,
    ) -> Result<MovedVertices, GpuError> {
        let Some(groups) = check(context, params)? else { return Ok(MovedVertices::default()) };
        let (list, used) = context
            .scoped("moved", || {
                let mut encoder = context.device.create_command_encoder(&Default::default());
                let lists = self.encode(context, &mut encoder, params, groups, positions);
                context.queue.submit([encoder.finish()]);
                lists
            })
            .map_err(|e| context.lost_or(e))?;
        let count: Vec<u32> = buffers::read_back(context, &used, 1)?;
        let count = count[0].min(params.vertex_count) as usize;
        let slots: Vec<[u32; 4]> = buffers::read_back(context, &list, count)?;
        Ok(MovedVertices::from_slots(slots))
    }

    /// Records the compaction into `encoder`, then copies its count and list into a staging
    /// buffer that [`PendingMoved`] maps once the caller has submitted `encoder`.
    ///
    /// # Errors
    /// As [`run`](Self::run).
    pub fn record(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        params: MovedParams,
        positions: &wgpu::Buffer,
    ) -> Result<PendingMoved, GpuError> {
        let Some(groups) = check(context, params)? else { return Ok(PendingMoved::empty(context)) };
        let list_bytes = u64::from(params.vertex_count) * SLOT_BYTES;
        let staging = context.scoped("moved read-back", || {
            let (list, used) = self.encode(context, encoder, params, groups, positions);
            let staging = context.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("moved read-back"),
                size: LIST_AT + list_bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            encoder.copy_buffer_to_buffer(&used, 0, &staging, 0, 4);
            encoder.copy_buffer_to_buffer(&list, 0, &staging, LIST_AT, list_bytes);
            staging
        })?;
        Ok(PendingMoved {
            context: context.clone(),
            staging: Some(staging),
            capacity: params.vertex_count,
            state: ReadState::Recorded,
            bytes_read: 0,
        })
    }

    /// Records the kernel over `groups` workgroups; the list and count buffers it fills.
    fn encode(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        params: MovedParams,
        groups: u32,
        positions: &wgpu::Buffer,
    ) -> (wgpu::Buffer, wgpu::Buffer) {
        let list = buffers::storage_zeroed(context, "moved list", u64::from(params.vertex_count) * SLOT_BYTES);
        let used = buffers::storage_zeroed(context, "moved count", 4);
        let uniform = buffers::uniform(context, "moved params", &params);
        let bind = self.kernel.bind(context, &[&uniform, positions, &list, &used]);
        self.kernel.dispatch(encoder, &bind, [groups, 1, 1]);
        (list, used)
    }
}

/// Bytes of one compacted slot: the vertex index and three f32.
const SLOT_BYTES: u64 = 16;

/// Where the list starts in a [`PendingMoved`] staging buffer (after the count, aligned for
/// mapping).
const LIST_AT: u64 = 16;

/// The kernel's workgroup count for `params`, checked against the device's limits; `None` for an
/// empty target.
fn check(context: &GpuContext, params: MovedParams) -> Result<Option<u32>, GpuError> {
    let groups = params.vertex_count.div_ceil(WORKGROUP);
    let limit = context.limits.max_compute_workgroups_per_dimension;
    if groups > limit {
        let what = "moved workgroups (vertices / WORKGROUP)".into();
        return Err(GpuError::OverLimit { what, needed: groups.into(), limit: limit.into() });
    }
    buffers::check_binding_size(context, "moved list", u64::from(params.vertex_count) * SLOT_BYTES)?;
    Ok((groups > 0).then_some(groups))
}

/// Where a [`PendingMoved`] stands.
#[derive(Debug)]
enum ReadState {
    /// Recorded; waiting for the caller to submit and call [`PendingMoved::submitted`].
    Recorded,
    /// The count is being mapped.
    Count(Mapping),
    /// The list's first `count` slots are being mapped.
    List(Mapping, u32),
    /// Read (or nothing to read); the result was handed out once.
    Done(Option<MovedVertices>),
}

/// A read-back of the vertices one batch moved that never blocks, for a renderer's frame loop:
/// [`GpuDenter::record_moved`](super::GpuDenter::record_moved) records it into the caller's
/// encoder; after submitting that encoder call [`submitted`](Self::submitted), then
/// [`poll`](Self::poll) once a frame until it returns the vertices. Reads 4 bytes (the count),
/// then 16 per moved vertex ([`bytes_read`](Self::bytes_read)), two frames or more after the
/// submission.
#[derive(Debug)]
pub struct PendingMoved {
    context: GpuContext,
    staging: Option<wgpu::Buffer>,
    capacity: u32,
    state: ReadState,
    bytes_read: u64,
}

impl PendingMoved {
    /// A read-back of an empty target: done, with no vertex.
    fn empty(context: &GpuContext) -> Self {
        let state = ReadState::Done(Some(MovedVertices::default()));
        Self { context: context.clone(), staging: None, capacity: 0, state, bytes_read: 0 }
    }

    /// Starts mapping the count; call once, after submitting the encoder it was recorded into.
    pub fn submitted(&mut self) {
        if let (ReadState::Recorded, Some(staging)) = (&self.state, &self.staging) {
            self.state = ReadState::Count(map(staging, 0..8));
        }
    }

    /// Advances without blocking: `Ok(None)` while the GPU has not finished, then the moved
    /// vertices (ascending index order, as [`GpuDenter::read_moved`](super::GpuDenter::read_moved)
    /// returns them) exactly once; `Ok(None)` again after that.
    ///
    /// # Errors
    /// [`GpuError::Wait`] when a mapping failed (a lost device, a destroyed buffer). The
    /// read-back is over then: [`is_done`](Self::is_done) holds and later polls return `Ok(None)`.
    pub fn poll(&mut self) -> Result<Option<MovedVertices>, GpuError> {
        let polled = self.advance();
        if polled.is_err() {
            self.state = ReadState::Done(None);
            self.staging = None;
        }
        polled
    }

    /// [`poll`](Self::poll)'s work, leaving the state as it was on an error.
    fn advance(&mut self) -> Result<Option<MovedVertices>, GpuError> {
        // Runs the callbacks of finished work without waiting.
        let _ = self.context.device.poll(wgpu::PollType::Poll);
        while let Some(staging) = &self.staging {
            let next = match &self.state {
                ReadState::Count(receiver) => match mapped(receiver)? {
                    false => return Ok(None),
                    true => {
                        let count = read_words(staging, 0..8)?[0].min(self.capacity);
                        self.bytes_read += 4;
                        if count == 0 {
                            ReadState::Done(Some(MovedVertices::default()))
                        } else {
                            let end = LIST_AT + u64::from(count) * SLOT_BYTES;
                            ReadState::List(map(staging, LIST_AT..end), count)
                        }
                    }
                },
                ReadState::List(receiver, count) => match mapped(receiver)? {
                    false => return Ok(None),
                    true => {
                        let end = LIST_AT + u64::from(*count) * SLOT_BYTES;
                        let words = read_words(staging, LIST_AT..end)?;
                        self.bytes_read += end - LIST_AT;
                        let slots = words.chunks_exact(4).map(|s| [s[0], s[1], s[2], s[3]]).collect();
                        ReadState::Done(Some(MovedVertices::from_slots(slots)))
                    }
                },
                ReadState::Recorded | ReadState::Done(_) => break,
            };
            self.state = next;
        }
        match &mut self.state {
            ReadState::Done(result) => {
                self.staging = None;
                Ok(result.take())
            }
            _ => Ok(None),
        }
    }

    /// Whether the vertices have been handed out (or the target was empty).
    pub fn is_done(&self) -> bool {
        matches!(self.state, ReadState::Done(_))
    }

    /// Bytes read back from the device so far: 4 for the count, 16 per moved vertex.
    pub fn bytes_read(&self) -> u64 {
        self.bytes_read
    }
}

/// A mapping's outcome, set by wgpu's callback (shareable, so a read-back can live in a
/// multi-threaded engine's resources).
type Mapping = Arc<OnceLock<Result<(), wgpu::BufferAsyncError>>>;

/// Starts mapping `range` of `staging` for reading.
fn map(staging: &wgpu::Buffer, range: Range<u64>) -> Mapping {
    let outcome = Mapping::default();
    let set = outcome.clone();
    staging.slice(range).map_async(wgpu::MapMode::Read, move |result| {
        let _ = set.set(result);
    });
    outcome
}

/// Whether `mapping` is done (`false`: still pending).
fn mapped(mapping: &Mapping) -> Result<bool, GpuError> {
    match mapping.get() {
        Some(Ok(())) => Ok(true),
        Some(Err(e)) => Err(GpuError::Wait(e.to_string())),
        None => Ok(false),
    }
}

/// The u32 words of the mapped `range` of `staging`, which is unmapped afterwards.
fn read_words(staging: &wgpu::Buffer, range: Range<u64>) -> Result<Vec<u32>, GpuError> {
    let words = match staging.slice(range).get_mapped_range() {
        Ok(view) => Ok(bytemuck::cast_slice::<u8, u32>(&view).to_vec()),
        Err(e) => Err(GpuError::Wait(e.to_string())),
    };
    staging.unmap();
    words
}

/// How long a batch's read-backs may take to arrive once the device is idle before they are
/// given up: a loaded software device (lavapipe on a busy 2-core machine) has been seen to
/// deliver a mapping several waits late.
const READ_BACK_PATIENCE: std::time::Duration = std::time::Duration::from_secs(10);

/// Waits for `pending` read-backs, recorded into one submission the caller has made, and returns
/// each one's vertices (in `pending`'s order): two waits for the device however many there are
/// (the counts, then the lists), more when a mapping arrives late.
///
/// # Errors
/// [`GpuError::Wait`] when a mapping failed or a read-back gave nothing within
/// [`READ_BACK_PATIENCE`]; device errors.
pub(crate) fn wait_all(context: &GpuContext, pending: &mut [PendingMoved]) -> Result<Vec<MovedVertices>, GpuError> {
    pending.iter_mut().for_each(PendingMoved::submitted);
    let mut out: Vec<Option<MovedVertices>> = vec![None; pending.len()];
    let started = std::time::Instant::now();
    // A count, then a list, each mapped after a wait: two rounds when the driver keeps up. Each
    // later round is a poll of an idle device (microseconds) after a millisecond's pause that
    // lets the driver's threads deliver the mapping.
    for round in 0.. {
        if round >= 2 {
            if started.elapsed() > READ_BACK_PATIENCE {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        context.wait()?;
        for (read, slot) in pending.iter_mut().zip(&mut out) {
            if slot.is_none() {
                *slot = read.poll()?;
            }
        }
        if out.iter().all(Option::is_some) {
            return Ok(out.into_iter().flatten().collect());
        }
    }
    Err(GpuError::Wait(format!(
        "a moved-vertex read-back did not arrive within {} s of the device going idle",
        READ_BACK_PATIENCE.as_secs()
    )))
}
