//! Builds dentbend's GPU context from Bevy's render device, or says why it cannot.

use bevy::prelude::*;
use bevy::render::renderer::{RenderDevice, RenderQueue};
use dentbend::gpu::GpuContext;

use super::ResidentDents;
use crate::link::{GpuStatus, RenderLink};

/// `RenderStartup`: wraps Bevy's device and queue (no second device) when they meet the
/// kernels' limits; otherwise every body takes the CPU path, and the log says why.
pub(crate) fn start_on_bevys_device(
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    link: Res<RenderLink>,
    mut resident: ResMut<ResidentDents>,
) {
    if matches!(*link.status.lock().unwrap_or_else(|e| e.into_inner()), GpuStatus::Unavailable(_)) {
        // The plug-in was told to use the CPU path.
        return;
    }
    match GpuContext::from_device(device.wgpu_device().clone(), (**queue).clone()) {
        Ok(context) => {
            let name = context.adapter_name();
            info!("bevy_dentbend: dents run on Bevy's device, {name}");
            resident.start(context);
            link.set_status(GpuStatus::Ready(name));
        }
        Err(e) => {
            warn!("bevy_dentbend: Bevy's device cannot run the dent kernels ({e}); dents take the CPU path");
            link.set_status(GpuStatus::Unavailable(e.to_string()));
        }
    }
}
