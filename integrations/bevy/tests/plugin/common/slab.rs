//! Reads a mesh's vertices back from Bevy's mesh allocator slab (a test-only read-back): what
//! the renderer actually draws.

use std::sync::{Arc, Mutex};

use bevy::prelude::*;
use bevy::render::mesh::allocator::MeshAllocator;
use bevy::render::render_resource::{BufferDescriptor, BufferUsages, MapMode, PollType};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::{Render, RenderApp, RenderSystems};

/// A mesh asset and its vertex stride, bytes.
type Request = (AssetId<Mesh>, u64);

/// Asks the render world for the slab bytes of a mesh; shared by both worlds.
#[derive(Resource, Clone, Default)]
pub struct SlabProbe {
    request: Arc<Mutex<Option<Request>>>,
    bytes: Arc<Mutex<Option<Vec<u8>>>>,
}

impl SlabProbe {
    /// Adds the probe to `app`.
    pub fn install(app: &mut App) -> Self {
        let probe = Self::default();
        app.insert_resource(probe.clone());
        app.sub_app_mut(RenderApp)
            .insert_resource(probe.clone())
            .add_systems(Render, read.in_set(RenderSystems::Cleanup));
        probe
    }

    /// Requests asset `mesh`'s vertices (`stride` bytes each) at the next frame.
    pub fn request(&self, mesh: AssetId<Mesh>, stride: u64) {
        *self.bytes.lock().unwrap() = None;
        *self.request.lock().unwrap() = Some((mesh, stride));
    }

    /// The bytes read, once there.
    pub fn take(&self) -> Option<Vec<u8>> {
        self.bytes.lock().unwrap().take()
    }
}

fn read(probe: Res<SlabProbe>, allocator: Res<MeshAllocator>, device: Res<RenderDevice>, queue: Res<RenderQueue>) {
    let Some((mesh, stride)) = *probe.request.lock().unwrap() else { return };
    let Some(slice) = allocator.mesh_vertex_slice(&mesh) else { return };
    let size = u64::from(slice.range.end - slice.range.start) * stride;
    let staging = device.wgpu_device().create_buffer(&BufferDescriptor {
        label: Some("slab probe"),
        size,
        usage: BufferUsages::MAP_READ | BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.wgpu_device().create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(slice.buffer, u64::from(slice.range.start) * stride, &staging, 0, size);
    queue.submit([encoder.finish()]);
    staging.slice(..).map_async(MapMode::Read, |_| {});
    device.wgpu_device().poll(PollType::wait_indefinitely()).expect("the device");
    let bytes = staging.slice(..).get_mapped_range().expect("mapped").to_vec();
    *probe.bytes.lock().unwrap() = Some(bytes);
    *probe.request.lock().unwrap() = None;
}
