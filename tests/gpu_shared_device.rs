//! dentbend on an application's device (`GpuContext::from_device`): a batch recorded into the
//! application's own encoder and submitted by it dents like the CPU pipeline, the resident
//! buffers can carry `VERTEX` usage, a device short of a needed limit is refused by name, and the
//! denter is an owned `Send + Sync + 'static` value.

mod common;

use dentbend::dent::{DentJob, DentParams, Impact, dent_batch};
use dentbend::gpu::{GpuContext, GpuDenter, GpuDenterOptions, GpuError};
use dentbend::{TriMesh, mesh};
use glam::Vec3;

/// Compile-time: a denter can live in an application's resources and move between threads.
const _: fn() = || {
    fn owned<T: Send + Sync + 'static>() {}
    owned::<GpuDenter>();
    owned::<GpuContext>();
};

/// A context on a device the test made itself, as an application would.
fn application_context() -> GpuContext {
    let (device, queue) = common::gpu::own_device(wgpu::Limits::downlevel_defaults());
    GpuContext::from_device(device, queue).expect("downlevel defaults meet dentbend's limits")
}

/// A ball above the block and one in front of the box (+z).
fn balls() -> [TriMesh; 2] {
    [common::sphere_at(Vec3::new(0.0, 5.0, 0.0), 0.6), common::sphere_at(Vec3::new(0.0, 0.0, 3.0), 0.5)]
}

/// The first ball dropped on the block (d = 0.2), the second on the box's side (d = 0.1): the
/// paper's dents, which a recorded batch runs (the kernels alone).
fn jobs(balls: &[TriMesh; 2]) -> Vec<DentJob<'_>> {
    let hit = |target: usize, point: Vec3, normal: Vec3, d| DentJob {
        target,
        projectile: &balls[target],
        impact: Impact { point, normal, relative_velocity: normal },
        params: DentParams::new(d).without_host_stages(),
    };
    vec![hit(0, Vec3::new(0.0, 0.5, 0.0), -Vec3::Y, 0.2), hit(1, Vec3::new(0.0, 0.0, 1.0), -Vec3::Z, 0.1)]
}

/// Recorded into the application's encoder and submitted by it, the batch gives the CPU batch's
/// vertices. Tolerance as tests/parity_pipeline.rs: the map's 2e-5·d error plus a few ulps of the
/// coordinate per dent (tests/parity_displace.rs), with a factor 3 of margin.
fn a_batch_recorded_into_the_applications_encoder_matches_the_cpu(_: &'static GpuContext) {
    let context = application_context();
    assert!(!context.owns_device());
    let balls = balls();
    let mut cpu = vec![mesh::builtin("block").unwrap(), mesh::builtin("box").unwrap()];
    let original = cpu.clone();
    let jobs = jobs(&balls);
    let mut denter = GpuDenter::new(&context, &cpu).unwrap();
    let before = denter.read_positions(0).unwrap();
    let mut encoder = context.device.create_command_encoder(&Default::default());
    let info = denter.record_batch(&mut encoder, &jobs).unwrap();
    assert_eq!(info.len(), jobs.len());
    // Nothing was submitted by the denter: the resident vertices are still the originals.
    assert_eq!(denter.read_positions(0).unwrap(), before, "record_batch submitted work");
    context.queue.submit([encoder.finish()]);
    dent_batch(&mut cpu, &jobs).unwrap();
    for (t, target) in cpu.iter().enumerate() {
        let gpu = denter.read_positions(t).unwrap();
        let scale = target.bounds().1.abs().max_element().max(1.0);
        let tol = 3.0 * (2e-5 * 0.2 + 8.0 * f32::EPSILON * scale);
        let err = gpu.iter().zip(target.positions()).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
        assert!(err <= tol, "target {t}: GPU and CPU vertices differ by {err} (allowed {tol})");
        assert_ne!(target.positions(), original[t].positions(), "target {t} was not dented");
    }
}

fn resident_buffers_take_vertex_usage_on_request(_: &'static GpuContext) {
    let context = application_context();
    let targets = [mesh::builtin("block").unwrap()];
    let plain = GpuDenter::new(&context, &targets).unwrap();
    assert!(!plain.vertex_buffer().usage().contains(wgpu::BufferUsages::VERTEX));
    let options = GpuDenterOptions { vertex_usage: true };
    let bindable = GpuDenter::with_options(&context, &targets, options).unwrap();
    for buffer in [bindable.vertex_buffer(), bindable.normal_buffer()] {
        assert!(buffer.usage().contains(wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE));
    }
}

/// A device created with 2 storage buffers per stage (the kernels bind 4) is refused, naming the
/// limit, and no context is made.
fn a_device_short_of_a_needed_limit_is_refused_by_name(_: &'static GpuContext) {
    let limits = wgpu::Limits { max_storage_buffers_per_shader_stage: 2, ..wgpu::Limits::downlevel_defaults() };
    let (device, queue) = common::gpu::own_device(limits);
    let error = GpuContext::from_device(device, queue).unwrap_err();
    assert!(
        matches!(
            error,
            GpuError::MissingLimits { limit: "max_storage_buffers_per_shader_stage", needed: 4, available: 2 }
        ),
        "{error}"
    );
    assert!(error.to_string().contains("max_storage_buffers_per_shader_stage"), "{error}");
}

/// The denter keeps its own handles: it outlives the context value it was made from and works on
/// another thread.
fn a_denter_outlives_its_context_value_and_crosses_threads(_: &'static GpuContext) {
    let context = application_context();
    let mut denter = GpuDenter::new(&context, &[mesh::builtin("block").unwrap()]).unwrap();
    drop(context);
    let moved = std::thread::spawn(move || {
        denter.dent_batch(&jobs(&balls())[..1]).unwrap();
        denter.read_moved(0).unwrap().indices.len()
    })
    .join()
    .unwrap();
    assert!(moved > 0);
}

/// dentbend replaces neither of the application's device-wide callbacks: after a batch, the
/// application's uncaptured-error handler still sees the application's own mistakes, and its
/// device-lost callback still fires.
fn the_applications_callbacks_stay_in_place(_: &'static GpuContext) {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicUsize, Ordering};
    let (device, queue) = common::gpu::own_device(wgpu::Limits::downlevel_defaults());
    let (errors, lost) = (Arc::new(AtomicUsize::new(0)), Arc::new(AtomicUsize::new(0)));
    let seen = errors.clone();
    device.on_uncaptured_error(Arc::new(move |_| {
        seen.fetch_add(1, Ordering::SeqCst);
    }));
    let seen = lost.clone();
    device.set_device_lost_callback(move |_, _| {
        seen.fetch_add(1, Ordering::SeqCst);
    });
    let context = GpuContext::from_device(device.clone(), queue).unwrap();
    let mut denter = GpuDenter::new(&context, &[mesh::builtin("block").unwrap()]).unwrap();
    denter.dent_batch(&jobs(&balls())[..1]).unwrap();
    assert_eq!(errors.load(Ordering::SeqCst), 0, "dentbend's batch raised an uncaptured error");
    // The application's own mistake: a copy from an unaligned offset.
    let buffer = |usage| {
        device.create_buffer(&wgpu::BufferDescriptor { label: None, size: 16, usage, mapped_at_creation: false })
    };
    let (src, dst) = (buffer(wgpu::BufferUsages::COPY_SRC), buffer(wgpu::BufferUsages::COPY_DST));
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(&src, 2, &dst, 0, 4);
    drop(encoder.finish());
    assert_eq!(errors.load(Ordering::SeqCst), 1, "the application's error handler was replaced");
    // wgpu calls the lost callback from the first poll that finds the destroyed device's queue
    // empty, so let the batch finish first.
    context.wait().unwrap();
    device.destroy();
    let _ = device.poll(wgpu::PollType::Poll);
    assert_eq!(lost.load(Ordering::SeqCst), 1, "the application's device-lost callback was replaced");
}

gpu_test_main! {
    gpu: [
        a_batch_recorded_into_the_applications_encoder_matches_the_cpu,
        resident_buffers_take_vertex_usage_on_request,
        a_device_short_of_a_needed_limit_is_refused_by_name,
        a_denter_outlives_its_context_value_and_crosses_threads,
        the_applications_callbacks_stay_in_place,
    ],
}
