//! `moved` on the GPU: the vertices a batch moved, compacted on the GPU and read back alone, are
//! the CPU dent path's moved vertices (same indices, positions within the pipeline's parity
//! tolerance), equal the CPU twin's list exactly, and cover only the last batch.

mod common;

use common::sphere_at;
use dentbend::cpu::{self, MovedParams};
use dentbend::dent::{DentJob, DentParams, Impact, dent_batch};
use dentbend::glam::Vec3;
use dentbend::gpu::{GpuContext, GpuDenter, MovedVertices, buffers};
use dentbend::{TriMesh, mesh};

fn drop_on_block(ball: &TriMesh, x: f32, d: f32) -> DentJob<'_> {
    DentJob {
        target: 0,
        projectile: ball,
        impact: Impact { point: Vec3::new(x, 0.5, 0.0), normal: -Vec3::Y, relative_velocity: -Vec3::Y },
        params: DentParams::new(d),
    }
}

/// Tolerance as tests/parity_pipeline.rs: each dent moves a vertex by at most d with the map's
/// 2e-5·d error, plus a few ulps of the coordinate (tests/parity_displace.rs), margin 3.
fn the_moved_vertices_are_the_cpu_dents_moved_vertices(context: &'static GpuContext) {
    let ball = sphere_at(Vec3::new(0.0, 5.0, 0.0), 0.6);
    let original = vec![mesh::builtin("block").unwrap()];
    let jobs = [drop_on_block(&ball, 0.0, 0.2)];
    let mut denter = GpuDenter::new(context, &original).unwrap();
    denter.dent_batch(&jobs).unwrap();
    let gpu = denter.read_moved(0).unwrap();

    let mut cpu = original.clone();
    dent_batch(&mut cpu, &jobs).unwrap();
    let (before, after) = (original[0].positions(), cpu[0].positions());
    let cpu_moved: Vec<u32> = (0..before.len() as u32).filter(|&v| before[v as usize] != after[v as usize]).collect();
    assert!(!cpu_moved.is_empty(), "the CPU dent moved nothing");
    assert_eq!(gpu.indices, cpu_moved, "GPU and CPU moved different vertices");
    let tol = 3.0 * (2e-5 * 0.2 + 8.0 * f32::EPSILON * 1.5);
    for (v, p) in gpu.indices.iter().zip(&gpu.positions) {
        let err = p.distance(after[*v as usize]);
        assert!(err <= tol, "vertex {v}: GPU {p} vs CPU {} ({err} > {tol})", after[*v as usize]);
    }

    // The CPU twin on the resident buffer gives the same list, bit for bit.
    let n = before.len();
    let resident: Vec<[f32; 4]> = buffers::read_back(context, denter.vertex_buffer(), n).unwrap();
    let mut slots = Vec::new();
    cpu::moved(&MovedParams { vertex_offset: 0, vertex_count: n as u32, _pad: [0; 2] }, &resident, &mut slots);
    assert_eq!(gpu, MovedVertices::from_slots(slots));
}

/// A second batch reports only what it moved: exactly the vertices whose resident position
/// changed between the two batches.
fn only_the_last_batch_counts(context: &'static GpuContext) {
    let (big, small) = (sphere_at(Vec3::new(0.0, 5.0, 0.0), 0.6), sphere_at(Vec3::new(1.0, 5.0, 0.0), 0.2));
    let mut denter = GpuDenter::new(context, &[mesh::builtin("block").unwrap()]).unwrap();
    denter.dent_batch(&[drop_on_block(&big, 0.0, 0.2)]).unwrap();
    let first = denter.read_positions(0).unwrap();
    let first_moved = denter.read_moved(0).unwrap();
    denter.dent_batch(&[drop_on_block(&small, 1.0, 0.1)]).unwrap();
    let second = denter.read_positions(0).unwrap();
    let moved = denter.read_moved(0).unwrap();
    let changed: Vec<u32> = (0..first.len() as u32).filter(|&v| first[v as usize] != second[v as usize]).collect();
    assert!(!changed.is_empty(), "the second dent moved nothing");
    assert_eq!(moved.indices, changed);
    assert_ne!(moved.indices, first_moved.indices);
    assert!(moved.indices.iter().zip(&moved.positions).all(|(v, p)| second[*v as usize] == *p));
}

/// The non-blocking read-back (recorded into the caller's encoder with the batch, mapped after
/// the caller's submission, polled) returns exactly what the blocking one does, once, having read
/// 4 bytes of count and 16 per moved vertex; an undented target reads its count only.
fn the_frame_loop_read_back_equals_the_blocking_one(context: &'static GpuContext) {
    let ball = sphere_at(Vec3::new(0.0, 5.0, 0.0), 0.6);
    let targets = [mesh::builtin("block").unwrap(), mesh::builtin("block").unwrap()];
    let mut denter = GpuDenter::new(context, &targets).unwrap();
    let mut encoder = context.device.create_command_encoder(&Default::default());
    let job = drop_on_block(&ball, 0.0, 0.2);
    let kernels = DentJob { params: job.params.clone().without_host_stages(), ..job };
    denter.record_batch(&mut encoder, &[kernels]).unwrap();
    let mut dented = denter.record_moved(&mut encoder, 0).unwrap();
    let mut untouched = denter.record_moved(&mut encoder, 1).unwrap();
    // Not submitted yet: polling finds nothing and reads nothing.
    assert_eq!(dented.poll().unwrap(), None);
    context.queue.submit([encoder.finish()]);
    dented.submitted();
    untouched.submitted();

    let (mut got, mut empty) = (None, None);
    for _ in 0..100 {
        got = got.or(dented.poll().unwrap());
        empty = empty.or(untouched.poll().unwrap());
        if got.is_some() && empty.is_some() {
            break;
        }
        context.wait().unwrap();
    }
    let got = got.expect("the read-back never finished");
    assert_eq!(got, denter.read_moved(0).unwrap());
    assert!(!got.indices.is_empty(), "the dent moved nothing");
    assert_eq!(dented.bytes_read(), 4 + 16 * got.indices.len() as u64);
    assert_eq!(empty, Some(MovedVertices::default()));
    assert_eq!(untouched.bytes_read(), 4);
    // Handed out once.
    assert!(dented.is_done());
    assert_eq!(dented.poll().unwrap(), None);
}

gpu_test_main! {
    gpu: [
        the_moved_vertices_are_the_cpu_dents_moved_vertices,
        only_the_last_batch_counts,
        the_frame_loop_read_back_equals_the_blocking_one,
    ],
}
