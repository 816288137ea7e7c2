//! The resident GPU path with every stage (`GpuDenter::dent_batch`): the game dent (refinement,
//! volume rim, guard) on a game asset split at its hard edges gives the CPU batch's topology and
//! positions, keeps the asset closed, and reads back only the vertices the kernels moved; a target
//! that outgrows its slice of the device buffers is laid out again without disturbing the
//! others; a recorded batch refuses the host stages it cannot run; a refined target past the
//! device's buffer limits and a device lost between stages are errors that change nothing.

#[macro_use]
mod common;

use std::sync::{Arc, Once};

use common::seams::unpaired_edges;
use dentbend::dent::{BatchOutcome, DentJob, Refine, VolumeMode, dent_batch, dent_batch_tracked};
use dentbend::glam::{Affine3A, Vec3};
use dentbend::gpu::{GpuBatchError, GpuContext, GpuDenter, GpuError};
use dentbend::mesh::{self, TriMesh};
use dentbend::{Attenuation, DentParams, Impact, Resolution};

/// Steps of the guard's bisection: its scale is found to 2⁻¹² (src/dent/guard.rs).
const GUARD_STEP: f32 = 1.0 / 4096.0;

/// The parity tolerance of tests/parity_pipeline.rs for `dents` dents of distance `d` on a
/// target whose coordinates reach `scale`: the map's 2e-5·d plus a few ulps per dent.
fn parity_tolerance(dents: f32, d: f32, scale: f32) -> f32 {
    dents * (2e-5 * d + 8.0 * f32::EPSILON * scale.max(1.0))
}

/// The game dent: refinement where needed, the guard, the volume kept as a rim.
fn game(d: f32) -> DentParams {
    DentParams { volume: VolumeMode::Preserve, ..DentParams::new(d) }
}

/// A ball of `radius` touching `point` from above.
fn ball_above(point: Vec3, radius: f32) -> TriMesh {
    let mut ball = mesh::builtin("sphere").unwrap();
    let to_world =
        Affine3A::from_scale_rotation_translation(Vec3::splat(radius), Default::default(), point + radius * Vec3::Y);
    ball.transform(to_world).unwrap();
    ball
}

/// `ball` falling head-on on target `target` at `point`.
fn drop_on(target: usize, ball: &TriMesh, point: Vec3, params: DentParams) -> DentJob<'_> {
    DentJob { target, projectile: ball, impact: Impact::head_on(point, -Vec3::Y), params }
}

/// The GPU's host copy against the CPU's mesh and outcome of dents of distance at most `d`: the
/// same triangles (the same refinement), vertices within `tol` plus what a bisection step of
/// `limited_to` moves (that fraction of d), the same moved vertices and refinement; and the
/// device holds the host copy bit for bit, with normals within 1e-3 per component of the host
/// copy's (both recomputed around what moved from the same positions, in another order: the
/// agreement tests/parity_pipeline.rs states).
fn assert_matches_cpu(
    denter: &mut GpuDenter,
    t: usize,
    (cpu, cpu_out): (&TriMesh, &BatchOutcome),
    gpu_out: &BatchOutcome,
    (d, tol): (f32, f32),
) {
    let device = denter.read_positions(t).unwrap();
    let device_normals = denter.read_normals(t).unwrap();
    let gpu = denter.mesh(t).unwrap();
    let normal_error =
        device_normals.iter().zip(gpu.normals()).map(|(a, b)| (*a - *b).abs().max_element()).fold(0.0, f32::max);
    assert!(normal_error <= 1e-3, "target {t}: device normals differ from the host copy's by {normal_error}");
    assert_eq!(gpu.faces(), cpu.faces(), "target {t}: the same refinement on both paths");
    let mut slack = 0.0;
    for (c, g) in cpu_out.reports.iter().zip(&gpu_out.reports) {
        match (c.limited_to, g.limited_to) {
            (Some(a), Some(b)) => {
                assert!((a - b).abs() <= GUARD_STEP, "limited to {b} on the GPU, {a} on the CPU");
                slack += (a - b).abs() * d;
            }
            (a, b) => assert_eq!(a, b, "the guard decided differently"),
        }
        assert_eq!((g.refined_vertices, g.refined_triangles), (c.refined_vertices, c.refined_triangles));
    }
    let err = gpu.positions().iter().zip(cpu.positions()).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
    assert!(err <= tol + slack, "target {t}: GPU and CPU vertices differ by {err} (allowed {})", tol + slack);
    assert_eq!(gpu_out.moved[t], cpu_out.moved[t], "target {t}: different vertices moved");
    assert_eq!(gpu_out.topology_changed(t), cpu_out.topology_changed(t));
    assert_eq!(device, gpu.positions(), "target {t}: the device and the host copy differ");
}

/// A 0.25 m ball 0.1 m from the top edge of the built-in crate (24 vertices, split at its hard
/// edges), d = 0.15 m, the game dent: refined on both sides of the edge, as on the CPU, and still
/// closed once welded by position.
fn the_game_dent_on_a_split_crate_matches_the_cpu(context: &'static GpuContext) {
    let crate_mesh = mesh::builtin("crate").unwrap();
    assert_eq!((crate_mesh.vertex_count(), unpaired_edges(&crate_mesh)), (24, 0));
    let top = crate_mesh.bounds().1;
    let point = Vec3::new(top.x - 0.1, top.y, 0.1);
    let ball = ball_above(point, 0.25);
    let d = 0.15;
    let jobs = [drop_on(0, &ball, point, game(d))];
    let mut cpu = vec![crate_mesh.clone()];
    let cpu_out = dent_batch_tracked(&mut cpu, &jobs).unwrap();
    let mut denter = GpuDenter::new(context, std::slice::from_ref(&crate_mesh)).unwrap();
    let gpu_out = denter.dent_batch(&jobs).unwrap();
    assert!(gpu_out.reports[0].refined_triangles > 0, "the coarse crate is refined");
    let tol = parity_tolerance(1.0, d, top.abs().max_element());
    assert_matches_cpu(&mut denter, 0, (&cpu[0], &cpu_out), &gpu_out, (d, tol));
    let dented = denter.mesh(0).unwrap();
    assert_eq!(unpaired_edges(dented), 0, "the crate's seams cracked on the GPU path");
    let made = gpu_out.reports[0].max_displacement;
    assert!(made > 0.5 * d, "the dent made {made} of its {d}");
}

/// On the 12,290-vertex block a dent reads back only what the kernels moved: fewer vertices than
/// the dent moved in all (the rim's ring moves on the host), a small part of the target.
fn only_the_moved_vertices_come_back(context: &'static GpuContext) {
    let block = mesh::builtin("block").unwrap();
    let point = Vec3::new(0.3, block.bounds().1.y, -0.2);
    let ball = ball_above(point, 0.3);
    let jobs = [drop_on(0, &ball, point, game(0.1))];
    let mut cpu = vec![block.clone()];
    let cpu_out = dent_batch_tracked(&mut cpu, &jobs).unwrap();
    let mut denter = GpuDenter::new(context, std::slice::from_ref(&block)).unwrap();
    let gpu_out = denter.dent_batch(&jobs).unwrap();
    assert_matches_cpu(&mut denter, 0, (&cpu[0], &cpu_out), &gpu_out, (0.1, parity_tolerance(1.0, 0.1, 1.5)));
    let (read, moved) = (denter.vertices_read_back(), gpu_out.moved[0].len());
    assert!(read > 0 && read <= moved, "read back {read} vertices, {moved} moved");
    assert!(moved < block.vertex_count() / 4, "the dent moved {moved} of {} vertices", block.vertex_count());
}

/// Four dents in turn on a crate beside a block, each batch refining the crate further: the first
/// outgrows the crate's slice (every target is laid out again), later ones may grow in place.
/// Every batch matches the CPU, and the block, never dented, stays bit for bit as it was.
fn a_target_outgrowing_its_slice_is_laid_out_again(context: &'static GpuContext) {
    let (crate_mesh, block) = (mesh::builtin("crate").unwrap(), mesh::builtin("block").unwrap());
    let top = crate_mesh.bounds().1.y;
    let mut cpu = vec![crate_mesh.clone(), block.clone()];
    let mut denter = GpuDenter::new(context, &cpu).unwrap();
    let mut layouts = Vec::new();
    for k in 0..4 {
        let point = Vec3::new(-0.6 + 0.4 * k as f32, top, 0.1 * k as f32);
        let ball = ball_above(point, 0.15);
        let jobs = [drop_on(0, &ball, point, game(0.08))];
        let cpu_out = dent_batch_tracked(&mut cpu, &jobs).unwrap();
        let gpu_out = denter.dent_batch(&jobs).unwrap();
        let tol = parity_tolerance(k as f32 + 1.0, 0.08, 1.0);
        assert_matches_cpu(&mut denter, 0, (&cpu[0], &cpu_out), &gpu_out, (0.08, tol));
        assert_eq!(denter.read_positions(1).unwrap(), block.positions(), "batch {k} disturbed the block");
        assert_eq!(denter.mesh(1).unwrap().positions(), block.positions());
        layouts.push(denter.vertex_range(1).start);
    }
    assert_ne!(layouts[0], 0, "the block sits after the crate");
}

/// Targets added, replaced and removed after the denter is built: each keeps its own vertices on
/// the device and on the host (a removed target's successors move down one index), a replaced
/// target larger than its slice lays the others out again without disturbing them, an unknown
/// index is an error that changes nothing, and the game dent still matches the CPU afterwards.
fn targets_come_and_go(context: &'static GpuContext) {
    let (block, crate_mesh, bunny) =
        (mesh::builtin("block").unwrap(), mesh::builtin("crate").unwrap(), mesh::builtin("bunny").unwrap());
    let mut denter = GpuDenter::new(context, std::slice::from_ref(&crate_mesh)).unwrap();
    assert_eq!(denter.add_target(block.clone()).unwrap(), 1);
    assert_eq!(denter.add_target(crate_mesh.clone()).unwrap(), 2);
    denter.replace_target(0, bunny.clone()).unwrap();
    let expect = [&bunny, &block, &crate_mesh];
    for (t, mesh) in expect.iter().enumerate() {
        assert_eq!(denter.read_positions(t).unwrap(), mesh.positions(), "target {t} on the device");
        assert_eq!(denter.mesh(t).unwrap().faces(), mesh.faces(), "target {t} on the host");
    }
    assert!(matches!(denter.replace_target(3, block.clone()), Err(GpuError::OverLimit { .. })));
    assert!(matches!(denter.remove_target(3), Err(GpuError::OverLimit { .. })));
    assert_eq!(denter.remove_target(0).unwrap().positions(), bunny.positions());
    assert_eq!(denter.target_count(), 2);
    assert_eq!(denter.read_positions(0).unwrap(), block.positions());
    assert_eq!(denter.read_positions(1).unwrap(), crate_mesh.positions());

    let top = crate_mesh.bounds().1;
    let point = Vec3::new(top.x - 0.2, top.y, 0.3);
    let ball = ball_above(point, 0.2);
    let jobs = [drop_on(1, &ball, point, game(0.1))];
    let mut cpu = vec![block.clone(), crate_mesh.clone()];
    let cpu_out = dent_batch_tracked(&mut cpu, &jobs).unwrap();
    let gpu_out = denter.dent_batch(&jobs).unwrap();
    let tol = parity_tolerance(1.0, 0.1, top.abs().max_element());
    assert_matches_cpu(&mut denter, 1, (&cpu[1], &cpu_out), &gpu_out, (0.1, tol));
    assert_eq!(denter.read_positions(0).unwrap(), block.positions());
}

/// An empty batch does nothing; a batch with one bad dent (a NaN impact, an unknown target) is
/// refused naming it, and even the good dent before it changes nothing, on the host or on the
/// device.
fn bad_batches_change_nothing(context: &'static GpuContext) {
    let block = mesh::builtin("block").unwrap();
    let point = Vec3::new(0.0, block.bounds().1.y, 0.0);
    let ball = ball_above(point, 0.3);
    let mut denter = GpuDenter::new(context, std::slice::from_ref(&block)).unwrap();
    let empty = denter.dent_batch(&[]).unwrap();
    assert!(empty.reports.is_empty() && empty.moved.iter().all(Vec::is_empty));
    let good = drop_on(0, &ball, point, game(0.1));
    let mut nan = drop_on(0, &ball, point, game(0.1));
    nan.impact.point.x = f32::NAN;
    let unknown = drop_on(1, &ball, point, game(0.1));
    for (bad, name) in [(nan, "a NaN impact"), (unknown, "an unknown target")] {
        let error = denter.dent_batch(&[good.clone(), bad]).unwrap_err();
        assert!(matches!(error, GpuBatchError::Job(ref e) if e.job == 1), "{name}: {error}");
        assert_eq!(denter.mesh(0).unwrap().positions(), block.positions(), "{name}");
        assert_eq!(denter.read_positions(0).unwrap(), block.positions(), "{name}");
    }
    // A dent that would push the block past the coordinate range (±10⁶; the block moved 4·10⁵
    // down, the dent 9·10⁵ deep, unguarded) fails in its own round, after two rounds of good
    // dents on the same block went to the device: those are undone too.
    let far: Vec<Vec3> = block.positions().iter().map(|p| *p - Vec3::Y * 4.0e5).collect();
    let far = TriMesh::new(far, block.faces().to_vec()).unwrap();
    denter.replace_target(0, far.clone()).unwrap();
    let point = point - Vec3::Y * 4.0e5;
    let ball = ball_above(point, 0.3);
    let good = drop_on(0, &ball, point, game(0.1));
    let unguarded = DentParams { refine: Refine::Off, guard_crossings: false, ..game(9.0e5) };
    let deep = drop_on(0, &ball, point, unguarded);
    let Err(error) = denter.dent_batch(&[good.clone(), good, deep]) else { panic!("the dent past the range was made") };
    assert!(matches!(error, GpuBatchError::Job(ref e) if e.job == 2), "{error}");
    assert_eq!(denter.mesh(0).unwrap().positions(), far.positions());
    assert_eq!(denter.read_positions(0).unwrap(), far.positions(), "the first rounds were not undone");
}

/// `record_batch` cannot wait for the GPU, so a dent asking for host stages is refused by name
/// (nothing recorded, the target unchanged); the paper's dent is recorded, and the next
/// `dent_batch` starts from the host copy read back once: kernel dent then game dent as on the
/// CPU.
fn recorded_batches_take_only_the_papers_dent(context: &'static GpuContext) {
    let block = mesh::builtin("block").unwrap();
    let point = Vec3::new(0.0, block.bounds().1.y, 0.0);
    let ball = ball_above(point, 0.4);
    let mut denter = GpuDenter::new(context, std::slice::from_ref(&block)).unwrap();
    let mut encoder = context.device.create_command_encoder(&Default::default());
    let refused = denter.record_batch(&mut encoder, &[drop_on(0, &ball, point, game(0.1))]).unwrap_err();
    drop(encoder);
    let GpuBatchError::HostStages { job: 0, ref stages } = refused else { panic!("{refused}") };
    for stage in ["refinement", "intersection guard", "volume rim"] {
        assert!(stages.contains(stage), "{stages}");
    }
    let message = refused.to_string();
    assert!(message.contains("dent_batch") && message.contains("without_host_stages"), "{message}");
    assert_eq!(denter.read_positions(0).unwrap(), block.positions());

    let paper = [drop_on(0, &ball, point, DentParams::new(0.1).without_host_stages())];
    let mut encoder = context.device.create_command_encoder(&Default::default());
    denter.record_batch(&mut encoder, &paper).unwrap();
    context.queue.submit([encoder.finish()]);
    let device = denter.read_positions(0).unwrap();
    assert_ne!(device, block.positions(), "the recorded dent moved nothing");
    assert_eq!(denter.mesh(0).unwrap().positions(), &device[..], "the host copy caught up");

    let side = Vec3::new(0.8, point.y, 0.5);
    let small = ball_above(side, 0.2);
    let jobs = [drop_on(0, &small, side, game(0.08))];
    let mut cpu = vec![block.clone()];
    dent_batch(&mut cpu, &paper).unwrap();
    let cpu_out = dent_batch_tracked(&mut cpu, &jobs).unwrap();
    let gpu_out = denter.dent_batch(&jobs).unwrap();
    assert_matches_cpu(&mut denter, 0, (&cpu[0], &cpu_out), &gpu_out, (0.1, parity_tolerance(2.0, 0.1, 1.5)));
}

/// On a device whose storage bindings hold 64 KiB, refining the crate to 5 mm edges under a dent
/// (thousands of vertices, past 4,096 × 16 bytes) is an over-limit error, and the crate stays as
/// it was on the host and on the device; the CPU refines the same dent.
fn a_refined_target_past_the_buffer_limits_changes_nothing(_: &'static GpuContext) {
    let limit: u64 = 64 << 10;
    let limits = wgpu::Limits {
        max_storage_buffer_binding_size: limit,
        max_buffer_size: limit,
        ..wgpu::Limits::downlevel_defaults()
    };
    let (device, queue) = common::gpu::own_device(limits);
    let context = GpuContext::from_device(device, queue).unwrap();
    let crate_mesh = mesh::builtin("crate").unwrap();
    let point = Vec3::new(0.0, crate_mesh.bounds().1.y, 0.0);
    let ball = ball_above(point, 0.25);
    let fine = DentParams { refine: Refine::MaxEdge(0.005), resolution: Resolution::Fixed(32), ..game(0.1) };
    let jobs = [drop_on(0, &ball, point, fine)];
    let mut cpu = vec![crate_mesh.clone()];
    dent_batch(&mut cpu, &jobs).unwrap();
    assert!(cpu[0].vertex_count() * 16 > limit as usize, "the CPU refines past the limit");
    let mut denter = GpuDenter::new(&context, std::slice::from_ref(&crate_mesh)).unwrap();
    let error = denter.dent_batch(&jobs).unwrap_err();
    assert!(matches!(error, GpuBatchError::Gpu(GpuError::OverLimit { .. })), "{error}");
    let kept = denter.mesh(0).unwrap();
    assert_eq!((kept.positions(), kept.faces()), (crate_mesh.positions(), crate_mesh.faces()));
    assert_eq!(denter.read_positions(0).unwrap(), crate_mesh.positions());
}

/// A device lost while the batch runs its host stages (here by the falloff, which planning
/// samples on the host), before the refined crate goes to the device: a typed `DeviceLost`, and
/// the host copy of the crate is the crate as it was (its refinement undone).
fn a_device_lost_between_stages_changes_nothing(_: &'static GpuContext) {
    let (device, queue) = common::gpu::own_device(wgpu::Limits::downlevel_defaults());
    let context = GpuContext::from_device(device.clone(), queue).unwrap();
    let crate_mesh = mesh::builtin("crate").unwrap();
    let point = Vec3::new(0.0, crate_mesh.bounds().1.y, 0.0);
    let ball = ball_above(point, 0.25);
    let lose = Once::new();
    // Moves everything above depth 0.12 rigidly: steep enough that the host fits it.
    let step = Attenuation::Custom(Arc::new(move |z: f32, _d: f32| {
        lose.call_once(|| device.destroy());
        if z < 0.12 { 1.0 } else { 0.0 }
    }));
    let jobs = [drop_on(0, &ball, point, DentParams { attenuation: step, ..game(0.1) })];
    let mut denter = GpuDenter::new(&context, std::slice::from_ref(&crate_mesh)).unwrap();
    let error = denter.dent_batch(&jobs).unwrap_err();
    assert!(matches!(error, GpuBatchError::Gpu(GpuError::DeviceLost(_))), "{error}");
    let kept = denter.mesh(0).unwrap();
    assert_eq!((kept.positions(), kept.faces()), (crate_mesh.positions(), crate_mesh.faces()));
}

gpu_test_main! {
    gpu: [
        the_game_dent_on_a_split_crate_matches_the_cpu,
        only_the_moved_vertices_come_back,
        a_target_outgrowing_its_slice_is_laid_out_again,
        targets_come_and_go,
        bad_batches_change_nothing,
        recorded_batches_take_only_the_papers_dent,
        a_refined_target_past_the_buffer_limits_changes_nothing,
        a_device_lost_between_stages_changes_nothing,
    ],
}
