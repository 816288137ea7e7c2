//! `interleave` on the GPU against its CPU twin: a resident target copied into an interleaved
//! vertex buffer (engine layout, non-zero offset, 40-byte stride) is byte-for-byte what the CPU
//! twin writes, bytes outside the position and normal fields keep their old values, and bad
//! layouts are typed errors that record nothing.

mod common;

use dentbend::cpu;
use dentbend::gpu::interleave::{InterleaveError, plan};
use dentbend::gpu::{GpuContext, GpuDenter, VertexLayout, buffers};
use dentbend::mesh;

/// A recognisable byte pattern, so an overwritten byte shows.
fn pattern(bytes: usize) -> Vec<u8> {
    (0..bytes).map(|k| (k * 7 + 3) as u8).collect()
}

fn destination(context: &GpuContext, bytes: usize, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    context.buffer_with_contents("interleaved destination", &pattern(bytes), usage | wgpu::BufferUsages::COPY_SRC)
}

fn words(bytes: &[u8]) -> Vec<u32> {
    bytes.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])).collect()
}

/// Copies target 1 (the bunny, after the sphere: a non-zero vertex offset) with `layout`, then
/// checks the GPU's bytes against the CPU twin applied to the same old contents.
fn check(context: &GpuContext, denter: &GpuDenter, offset: u64, stride: u64, layout: VertexLayout) {
    let n = denter.read_positions(1).unwrap().len();
    let bytes = (offset + n as u64 * stride + 64) as usize;
    let dst = destination(context, bytes, wgpu::BufferUsages::STORAGE);
    let mut encoder = context.device.create_command_encoder(&Default::default());
    denter.copy_target_into(&mut encoder, 1, &dst, offset, stride, layout).unwrap();
    context.queue.submit([encoder.finish()]);
    let gpu: Vec<u32> = buffers::read_back(context, &dst, bytes / 4).unwrap();

    let all = denter.vertex_buffer().size() as usize / 16;
    let positions: Vec<[f32; 4]> = buffers::read_back(context, denter.vertex_buffer(), all).unwrap();
    let normals: Vec<[f32; 4]> = buffers::read_back(context, denter.normal_buffer(), all).unwrap();
    let first = (denter.vertex_range(1).start / 16) as u32;
    let planned = plan(context, first, n as u32, bytes as u64, offset, stride, layout).unwrap();
    let mut expected = words(&pattern(bytes));
    cpu::interleave(&planned.params, &positions, &normals, &mut expected[(planned.bind_offset / 4) as usize..]);
    assert_eq!(gpu, expected, "GPU and CPU twin differ (offset {offset}, stride {stride}, {layout:?})");

    // Independently of the twin: the fields hold the target's positions and normals, and every
    // other byte is the old pattern.
    let (p, nrm) = (denter.read_positions(1).unwrap(), denter.read_normals(1).unwrap());
    let mut written = vec![false; bytes / 4];
    for v in 0..n {
        let base = (offset + v as u64 * stride) as usize / 4;
        let fields =
            [(layout.position, p[v].to_array())].into_iter().chain(layout.normal.map(|o| (o, nrm[v].to_array())));
        for (at, value) in fields {
            let word = base + at as usize / 4;
            assert_eq!(&gpu[word..word + 3], value.map(f32::to_bits), "vertex {v} field at {at}");
            written[word..word + 3].iter_mut().for_each(|w| *w = true);
        }
    }
    let old = words(&pattern(bytes));
    assert!((0..bytes / 4).all(|w| written[w] || gpu[w] == old[w]), "a byte outside the fields changed");
}

fn an_interleaved_copy_matches_the_cpu_twin_byte_for_byte(context: &'static GpuContext) {
    let targets = [mesh::builtin("sphere").unwrap(), mesh::builtin("bunny").unwrap()];
    let denter = GpuDenter::new(context, &targets).unwrap();
    // Offset 100 is not a multiple of the 256-byte storage offset alignment: the kernel binds
    // from byte 0 and starts 25 words in. Position at 8 and normal at 24 of a 40-byte vertex
    // leave UV-like gaps at 0..8 and 36..40.
    check(context, &denter, 100, 40, VertexLayout { position: 8, normal: Some(24) });
    check(context, &denter, 1028, 32, VertexLayout::POSITION_NORMAL);
    check(context, &denter, 0, 28, VertexLayout { position: 16, normal: None });
}

fn bad_layouts_are_typed_errors_and_record_nothing(context: &'static GpuContext) {
    let denter = GpuDenter::new(context, &[mesh::builtin("block").unwrap()]).unwrap();
    let n = denter.read_positions(0).unwrap().len() as u64;
    let bytes = (n * 40 + 64) as usize;
    let dst = destination(context, bytes, wgpu::BufferUsages::STORAGE);
    let vertex_only = destination(context, bytes, wgpu::BufferUsages::VERTEX);
    let pn = VertexLayout::POSITION_NORMAL;
    let mut encoder = context.device.create_command_encoder(&Default::default());
    let mut copy = |target, dst, offset, stride, layout| {
        denter.copy_target_into(&mut encoder, target, dst, offset, stride, layout)
    };
    let error = copy(0, &dst, 2, 40, pn).unwrap_err();
    assert!(matches!(error, InterleaveError::Misaligned { what: "offset", value: 2 }), "{error}");
    let error = copy(0, &dst, 0, 42, pn).unwrap_err();
    assert!(matches!(error, InterleaveError::Misaligned { what: "stride", .. }), "{error}");
    let error = copy(0, &dst, 0, 20, pn).unwrap_err();
    assert!(matches!(error, InterleaveError::BadLayout { what: "normal", at: 12, stride: 20 }), "{error}");
    let error = copy(0, &dst, 0, 40, VertexLayout { position: 0, normal: Some(8) }).unwrap_err();
    assert!(matches!(error, InterleaveError::BadLayout { .. }), "overlapping fields: {error}");
    let error = copy(0, &dst, 96, 40, pn).unwrap_err();
    assert!(matches!(error, InterleaveError::TooSmall { .. }), "{error}");
    let error = copy(0, &vertex_only, 0, 40, pn).unwrap_err();
    assert!(matches!(error, InterleaveError::NotStorage(_)), "{error}");
    let error = copy(1, &dst, 0, 40, pn).unwrap_err();
    assert!(matches!(error, InterleaveError::UnknownTarget { target: 1, count: 1 }), "{error}");
    context.queue.submit([encoder.finish()]);
    let after: Vec<u32> = buffers::read_back(context, &dst, bytes / 4).unwrap();
    assert_eq!(after, words(&pattern(bytes)), "a refused copy wrote to the destination");
}

gpu_test_main! {
    gpu: [an_interleaved_copy_matches_the_cpu_twin_byte_for_byte, bad_layouts_are_typed_errors_and_record_nothing],
}
