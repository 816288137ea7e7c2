//! The GPU context: an adapter is found (lavapipe in CI), a trivial kernel round-trips data, a
//! broken shader is a typed validation error, and backend names parse.

mod common;

use dentbend::gpu::{Binding, GpuContext, GpuError, Kernel, KernelDevice, buffers};

const DOUBLE: &str = "
@group(0) @binding(0) var<storage, read_write> values: array<f32>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < arrayLength(&values) { values[id.x] = 2.0 * values[id.x]; }
}";

fn a_kernel_round_trips_data(context: &'static GpuContext) {
    eprintln!("adapter: {}", context.adapter_name());
    let kernel = Kernel::new(context, "double", DOUBLE, "main", &[Binding::ReadWrite]).unwrap();
    let input: Vec<f32> = (0..1000).map(|k| k as f32 * 0.5).collect();
    let buffer = buffers::storage(context, "values", &input);
    let bind = kernel.bind(context, &[&buffer]);
    let mut encoder = context.device.create_command_encoder(&Default::default());
    kernel.dispatch(&mut encoder, &bind, [1000u32.div_ceil(64), 1, 1]);
    context.queue.submit([encoder.finish()]);
    let output: Vec<f32> = buffers::read_back(context, &buffer, input.len()).unwrap();
    // Doubling is exact in f32.
    assert!(output.iter().zip(&input).all(|(o, i)| *o == 2.0 * i));
}

fn a_broken_shader_is_a_validation_error(context: &'static GpuContext) {
    let broken = "@compute @workgroup_size(64) fn main() { let x: f32 = undefined_name; }";
    let error = Kernel::new(context, "broken", broken, "main", &[]).unwrap_err();
    assert!(matches!(error, GpuError::Validation { ref label, .. } if label == "broken"), "{error}");
}

fn backend_names_parse() {
    assert_eq!(KernelDevice::parse("cpu").unwrap(), KernelDevice::Cpu);
    assert_eq!(KernelDevice::parse("GPU").unwrap(), KernelDevice::Gpu);
    assert_eq!(KernelDevice::parse("auto").unwrap(), KernelDevice::Auto);
    assert!(matches!(KernelDevice::parse("cuda"), Err(GpuError::BadBackend(_))));
    assert!(KernelDevice::Cpu.context().unwrap().is_none());
}

gpu_test_main! {
    plain: [backend_names_parse],
    gpu: [a_kernel_round_trips_data, a_broken_shader_is_a_validation_error],
}
