//! A lost device is an error, not a hang: after `Device::destroy` (what a driver reset or an
//! unplugged GPU looks like to wgpu), batches, read-backs and waits return errors promptly.

mod common;

use std::time::{Duration, Instant};

use dentbend::dent::{DentJob, DentParams, Impact};
use dentbend::gpu::{GpuBatchError, GpuContext, GpuDenter, GpuError};
use dentbend::mesh::{self, TriMesh};
use glam::Vec3;

fn a_destroyed_device_gives_errors_and_leaves_the_meshes_alone(_: &'static GpuContext) {
    // The shared context is not the device destroyed below: a private one is, so other tests
    // keep the shared context.
    let context = GpuContext::new().expect("a second device on the same adapter");
    let targets = vec![mesh::builtin("block").unwrap()];
    let ball = mesh::builtin("sphere").unwrap();
    let mut denter = GpuDenter::new(&context, &targets).unwrap();
    let job = head_on(&ball);
    let before = targets[0].positions().to_vec();
    context.device.destroy();
    let started = Instant::now();
    let batch = denter.dent_batch(&[job]);
    let read = denter.read_positions(0);
    let wait = context.wait();
    // The waits are bounded by WAIT_TIMEOUT (120 s); a lost device must not come near it.
    assert!(started.elapsed() < Duration::from_secs(30), "took {:?}", started.elapsed());
    assert!(batch.is_err(), "a batch on a destroyed device succeeded");
    assert!(read.is_err(), "a read-back from a destroyed device succeeded");
    assert!(wait.is_err(), "waiting on a destroyed device succeeded");
    assert!(context.check_alive().is_err(), "the device-lost flag was not raised");
    // The caller's meshes are never touched by the GPU path.
    assert_eq!(targets[0].positions(), &before[..]);
}

/// The same on an application's device (`from_device`), where dentbend installs no device-lost
/// callback and finds the loss with a probe mapping: a typed `DeviceLost` error, the resident
/// copy and the caller's meshes unchanged.
fn a_destroyed_application_device_gives_a_typed_error(_: &'static GpuContext) {
    let (device, queue) = common::gpu::own_device(wgpu::Limits::downlevel_defaults());
    let context = GpuContext::from_device(device, queue).unwrap();
    let targets = vec![mesh::builtin("block").unwrap()];
    let ball = mesh::builtin("sphere").unwrap();
    let mut denter = GpuDenter::new(&context, &targets).unwrap();
    // The paper's dent, which a recorded batch runs (the kernels alone).
    let job = DentJob { params: DentParams::new(0.2).without_host_stages(), ..head_on(&ball) };
    let before = targets[0].positions().to_vec();
    // Lost mid-batch: recorded into the application's encoder, the device goes away before the
    // application submits.
    let mut encoder = context.device.create_command_encoder(&Default::default());
    denter.record_batch(&mut encoder, std::slice::from_ref(&job)).unwrap();
    context.device.destroy();
    context.queue.submit([encoder.finish()]);
    let started = Instant::now();
    let moved = denter.read_moved(0);
    assert!(matches!(moved, Err(GpuError::DeviceLost(_))), "{moved:?}");
    let batch = denter.dent_batch(&[job]);
    assert!(started.elapsed() < Duration::from_secs(30), "took {:?}", started.elapsed());
    assert!(matches!(batch, Err(GpuBatchError::Gpu(GpuError::DeviceLost(_)))), "{batch:?}");
    assert!(matches!(context.check_alive(), Err(GpuError::DeviceLost(_))));
    assert!(denter.read_positions(0).is_err(), "a read-back from a destroyed device succeeded");
    assert_eq!(targets[0].positions(), &before[..]);
}

/// A unit ball hitting the `block` target (slot 0) head-on on its top face, 0.2 m deep.
fn head_on(ball: &TriMesh) -> DentJob<'_> {
    DentJob {
        target: 0,
        projectile: ball,
        impact: Impact { point: Vec3::new(0.0, 0.5, 0.0), normal: -Vec3::Y, relative_velocity: -Vec3::Y },
        params: DentParams::new(0.2),
    }
}

gpu_test_main! {
    gpu: [
        a_destroyed_device_gives_errors_and_leaves_the_meshes_alone,
        a_destroyed_application_device_gives_a_typed_error,
    ],
}
