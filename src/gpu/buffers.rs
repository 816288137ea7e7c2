//! Uploading slices to GPU buffers and reading them back.

use bytemuck::Pod;

use super::context::MIN_BUFFER_BYTES;
use super::{GpuContext, GpuError};


/// A storage buffer holding `data` (readable and writable by kernels, copyable both ways).
pub fn storage<T: Pod>(context: &GpuContext, label: &str, data: &[T]) -> wgpu::Buffer {
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    context.buffer_with_contents(label, bytemuck::cast_slice(data), usage)
}

/// A zero-filled storage buffer of `bytes` bytes (at least 16).
pub fn storage_zeroed(context: &GpuContext, label: &str, bytes: u64) -> wgpu::Buffer {
    context.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(MIN_BUFFER_BYTES).next_multiple_of(4),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A uniform buffer holding `value`.
pub fn uniform<T: Pod>(context: &GpuContext, label: &str, value: &T) -> wgpu::Buffer {
    context.buffer_with_contents(label, bytemuck::bytes_of(value), wgpu::BufferUsages::UNIFORM)
}

/// Checks that `bytes` fits in one storage binding of this device.
///
/// # Errors
/// [`GpuError::OverLimit`].
pub(crate) fn check_binding_size(context: &GpuContext, what: &str, bytes: u64) -> Result<(), GpuError> {
    let limit = context.limits.max_storage_buffer_binding_size;
    if bytes > limit {
        return Err(GpuError::OverLimit { what: what.into(), needed: bytes, limit });
    }
    Ok(())
}

/// Copies the first `count` elements of `buffer` back to the CPU, waiting for the GPU.
///
/// # Errors
/// [`GpuError::Wait`] if mapping fails, [`GpuError::DeviceLost`].
pub fn read_back<T: Pod>(context: &GpuContext, buffer: &wgpu::Buffer, count: usize) -> Result<Vec<T>, GpuError> {
    read_back_range(context, buffer, 0, count)
}

/// Copies `count` elements of `buffer` starting at element `first` back to the CPU, waiting for
/// the GPU.
///
/// # Errors
/// As [`read_back`].
pub fn read_back_range<T: Pod>(
    context: &GpuContext,
    buffer: &wgpu::Buffer,
    first: usize,
    count: usize,
) -> Result<Vec<T>, GpuError> {
    let offset = (first * size_of::<T>()) as u64;
    let bytes = (count * size_of::<T>()) as u64;
    if bytes == 0 {
        return Ok(Vec::new());
    }
    context.check_alive()?;
    let (sender, receiver) = std::sync::mpsc::channel();
    // In an error scope: on a lost application device the copy and mapping fail validation,
    // which must become an error here rather than reach the application's error handler.
    let staging = context
        .scoped("read back", || {
            let staging = context.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("read back"),
                size: bytes.next_multiple_of(4),
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut encoder = context.device.create_command_encoder(&Default::default());
            encoder.copy_buffer_to_buffer(buffer, offset, &staging, 0, bytes.next_multiple_of(4));
            context.queue.submit([encoder.finish()]);
            staging.slice(..).map_async(wgpu::MapMode::Read, move |result| {
                let _ = sender.send(result);
            });
            staging
        })
        .map_err(|e| context.lost_or(e))?;
    let slice = staging.slice(..);
    context.wait()?;
    // The wait has run every callback of finished work; a mapping that never completes (a device
    // going away) times out rather than blocking the caller forever.
    receiver
        .recv_timeout(GpuContext::WAIT_TIMEOUT)
        .map_err(|e| GpuError::Wait(e.to_string()))?
        .map_err(|e| GpuError::Wait(e.to_string()))?;
    let data = slice.get_mapped_range().map_err(|e| GpuError::Wait(e.to_string()))?;
    let values = bytemuck::cast_slice::<u8, T>(&data[..bytes as usize]).to_vec();
    drop(data);
    staging.unmap();
    Ok(values)
}

/// Copies the first `count` elements of every `(buffer, count)` back to the CPU with one
/// submission and one wait (where [`read_back`] per buffer would wait once each): the sources
/// are packed into as few staging buffers as the device's buffer size limit allows. `work`
/// (commands that write the sources), when given, goes in the same submission before the
/// copies: no other submission can come between the work and its read-back.
///
/// # Errors
/// As [`read_back`]; [`GpuError::OverLimit`] for a source range larger than the device's
/// largest buffer.
pub(crate) fn read_back_all_after<T: Pod>(
    context: &GpuContext,
    work: Option<wgpu::CommandBuffer>,
    sources: &[(&wgpu::Buffer, usize)],
) -> Result<Vec<Vec<T>>, GpuError> {
    context.check_alive()?;
    let limit = context.limits.max_buffer_size;
    // Where each source lands: (staging buffer, byte offset, bytes); staging sizes in bytes.
    let mut places = Vec::with_capacity(sources.len());
    let mut sizes: Vec<u64> = Vec::new();
    for (_, count) in sources {
        let bytes = (count * size_of::<T>()) as u64;
        let padded = bytes.next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        if padded > limit {
            return Err(GpuError::OverLimit { what: "read-back buffer".into(), needed: padded, limit });
        }
        let count = sizes.len();
        match sizes.last_mut() {
            Some(size) if *size + padded <= limit => {
                places.push((count - 1, *size, bytes));
                *size += padded;
            }
            _ => {
                places.push((sizes.len(), 0, bytes));
                sizes.push(padded);
            }
        }
    }
    let (sender, receiver) = std::sync::mpsc::channel();
    // In an error scope, as in `read_back_range`.
    let staging = context
        .scoped("read back", || {
            let staging: Vec<wgpu::Buffer> = sizes
                .iter()
                .map(|&size| {
                    context.device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("read back"),
                        size: size.max(MIN_BUFFER_BYTES),
                        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    })
                })
                .collect();
            let mut encoder = context.device.create_command_encoder(&Default::default());
            for ((buffer, _), &(k, offset, bytes)) in sources.iter().zip(&places) {
                if bytes > 0 {
                    encoder.copy_buffer_to_buffer(buffer, 0, &staging[k], offset, bytes.next_multiple_of(4));
                }
            }
            context.queue.submit(work.into_iter().chain([encoder.finish()]));
            for (k, buffer) in staging.iter().enumerate() {
                let sender = sender.clone();
                buffer.slice(..).map_async(wgpu::MapMode::Read, move |result| {
                    let _ = sender.send((k, result));
                });
            }
            staging
        })
        .map_err(|e| context.lost_or(e))?;
    drop(sender);
    context.wait()?;
    for _ in &staging {
        let (_, result) = receiver.recv_timeout(GpuContext::WAIT_TIMEOUT).map_err(|e| GpuError::Wait(e.to_string()))?;
        result.map_err(|e| GpuError::Wait(e.to_string()))?;
    }
    let mapped = staging
        .iter()
        .map(|buffer| buffer.slice(..).get_mapped_range().map_err(|e| GpuError::Wait(e.to_string())))
        .collect::<Result<Vec<_>, _>>()?;
    let values = places
        .iter()
        .map(|&(k, offset, bytes)| {
            if bytes == 0 {
                return Vec::new();
            }
            // Read element by element: a range's start is only as aligned as the staging offset.
            let range = offset as usize..(offset + bytes) as usize;
            mapped[k][range].chunks_exact(size_of::<T>()).map(bytemuck::pod_read_unaligned).collect()
        })
        .collect();
    drop(mapped);
    staging.iter().for_each(wgpu::Buffer::unmap);
    Ok(values)
}
