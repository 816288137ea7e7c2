//! The whole dent pipeline on the GPU (`GpuDenter`) against the CPU: every stage of the bunny's
//! dent maps, then dented targets after a multi-target batch, a bad dent failing the batch with
//! nothing changed, and the buffers kept between batches changing nothing.

mod common;

use common::sphere_at;
use dentbend::dent::dent_map_stages;
use dentbend::dent::{DentJob, dent_batch};
use dentbend::glam::Vec3;
use dentbend::gpu::{GpuBatchError, GpuContext, GpuDenter};
use dentbend::{DentParams, Impact, Resolution, TriMesh, mesh};

/// Largest |a − b| over two slices.
fn worst(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f32::max)
}

fn bunny_jobs(bunny: &TriMesh) -> Vec<DentJob<'_>> {
    let job = |dir: Vec3, velocity: Vec3, res: Option<u32>, d: f32| {
        let point = bunny.support_point(velocity.normalize());
        DentJob {
            target: 0,
            projectile: bunny,
            impact: Impact { point, normal: dir, relative_velocity: velocity },
            params: DentParams {
                resolution: res.map_or(Resolution::default(), Resolution::Fixed),
                sigma: Some(0.4),
                ..DentParams::new(d)
            },
        }
    };
    vec![
        job(Vec3::Y, Vec3::Y, Some(100), 3.0),
        job(-Vec3::Z, Vec3::new(0.5, 0.0, -1.0), Some(64), 1.5),
        job(Vec3::X, Vec3::X, None, 2.0),
        job(-Vec3::Y, Vec3::new(1.0, -1.0, 0.3), Some(37), 0.8),
        job(Vec3::Z, Vec3::Z, Some(150), 2.5),
    ]
}

/// Every stage of five bunny dent maps of different sizes, built in one GPU batch.
///
/// Tolerances, relative to each dent's d: profiles are bit-identical on lavapipe and within
/// 2e-6 elsewhere (FMA, 2.5-ulp division: see tests/parity_zbuffer.rs); the envelope differs
/// only by the GPU's `log`/`exp` (≤ 3e-6 relative, tests/parity_envelope_*.rs), which the
/// linear heat steps and the rescale to d carry through unchanged; glance adds its `exp` and
/// bilinear weights (a few ulps). 2e-5·d bounds them all with margin.
fn every_stage_matches_the_cpu_pipeline(context: &'static GpuContext) {
    let bunny = mesh::builtin("bunny").unwrap();
    let target = mesh::builtin("sphere").unwrap();
    let jobs = bunny_jobs(&bunny);
    let denter = GpuDenter::new(context, std::slice::from_ref(&target)).unwrap();
    let gpu = denter.dent_map_stages(&jobs).unwrap();
    assert_eq!(gpu.len(), jobs.len());
    for (job, stages) in jobs.iter().zip(&gpu) {
        let cpu = dent_map_stages(job.projectile, &job.impact, &job.params, Some(target.mean_edge_length())).unwrap();
        let d = job.params.dent_distance;
        assert_eq!(stages.plan.zbuffer_grid, cpu.zbuffer_grid);
        assert_eq!(stages.plan.map_grid, cpu.map.grid);
        assert!(worst(&stages.zbuffer, &cpu.zbuffer) <= 2e-6 * d, "zbuffer");
        assert!(
            worst(&stages.envelope, &cpu.envelope) <= 2e-5 * d,
            "envelope {}",
            worst(&stages.envelope, &cpu.envelope)
        );
        assert!(
            worst(&stages.smoothed, &cpu.smoothed) <= 2e-5 * d,
            "smoothed {}",
            worst(&stages.smoothed, &cpu.smoothed)
        );
        let flat = |cells: &[[f32; 4]]| cells.iter().flatten().copied().collect::<Vec<f32>>();
        let map_err = worst(&flat(&stages.map), &flat(&cpu.map.cells));
        assert!(map_err <= 2e-5 * d, "map {map_err}");
    }
}

fn targets() -> Vec<TriMesh> {
    vec![mesh::builtin("block").unwrap(), mesh::builtin("bunny-dense").unwrap(), mesh::builtin("box").unwrap()]
}

/// A big ball above everything, a small one above the bunny, one in front of the box (+z).
fn balls() -> [TriMesh; 3] {
    [
        sphere_at(Vec3::new(0.0, 5.0, 0.0), 1.0),
        sphere_at(Vec3::new(3.0, 12.0, 0.0), 0.5),
        sphere_at(Vec3::new(0.0, 0.0, 3.0), 0.8),
    ]
}

fn target_jobs<'a>(balls: &'a [TriMesh], targets: &[TriMesh]) -> Vec<DentJob<'a>> {
    let bunny_top = targets[1].support_point(Vec3::Y);
    let hit = |target, point: Vec3, normal: Vec3, velocity: Vec3, ball: usize, d: f32| DentJob {
        target,
        projectile: &balls[ball],
        impact: Impact { point, normal, relative_velocity: velocity },
        // The kernels' parity: the host stages (refinement, intersection guard) stay off here;
        // tests/gpu_host_stages.rs compares them.
        params: DentParams::new(d).without_host_stages(),
    };
    vec![
        hit(0, Vec3::new(0.0, 0.5, 0.0), -Vec3::Y, -Vec3::Y, 0, 0.2),
        hit(1, bunny_top, -Vec3::Y, Vec3::new(0.4, -1.0, 0.0), 1, 0.5),
        hit(0, Vec3::new(0.3, 0.5, 0.2), -Vec3::Y, Vec3::new(1.0, -1.0, 0.0), 1, 0.15),
        hit(2, Vec3::new(0.0, 0.0, 1.0), -Vec3::Z, -Vec3::Z, 2, 0.1),
        hit(0, Vec3::new(-1.0, 0.5, -1.0), -Vec3::Y, -Vec3::Y, 0, 0.25),
    ]
}

/// Five dents over three targets (three on the block, overlapping, in order) give the CPU
/// batch's vertices. Tolerance: each dent moves a vertex by at most d, with the map's 2e-5·d
/// error from the stage test plus a few ulps of the coordinate per dent (tests/parity_displace.rs).
fn a_gpu_batch_dents_targets_like_the_cpu_batch(context: &'static GpuContext) {
    let balls = balls();
    let mut cpu = targets();
    let jobs = target_jobs(&balls, &cpu);
    let mut denter = GpuDenter::new(context, &cpu).unwrap();
    let outcome = denter.dent_batch(&jobs).unwrap();
    assert_eq!(outcome.reports.len(), jobs.len());
    dent_batch(&mut cpu, &jobs).unwrap();
    for (t, target) in cpu.iter().enumerate() {
        let gpu = denter.read_positions(t).unwrap();
        let scale = target.bounds().1.abs().max_element().max(1.0);
        let tol = 3.0 * (2e-5 * 0.5 + 8.0 * f32::EPSILON * scale);
        let err = gpu.iter().zip(target.positions()).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
        assert!(err <= tol, "target {t}: GPU and CPU vertices differ by {err} (allowed {tol})");
        // Normals refreshed on the GPU around the moved vertices, as `recompute_normals_near`
        // does on the CPU: unit vectors from sums of a few face normals whose corners agree to
        // `tol`, so 1e-3 per component covers the positions' difference on the smallest faces.
        let normals = denter.read_normals(t).unwrap();
        let worst =
            normals.iter().zip(target.normals()).map(|(a, b)| (*a - *b).abs().max_element()).fold(0.0, f32::max);
        assert!(worst <= 1e-3, "target {t}: normals differ by {worst}");
    }
    // Timing the same batch names every stage with a non-negative time.
    let times = denter.dent_batch_timed(&jobs).unwrap();
    let stages = ["displace", "envelope_cols", "envelope_rows", "glance", "heat", "normals", "zbuffer"];
    assert_eq!(times.keys().copied().collect::<Vec<_>>(), stages);
    assert!(times.values().all(|t| t.is_finite() && *t >= 0.0), "{times:?}");
    // The resident buffer holds every target's vertices as vec4.
    let vertices: usize = cpu.iter().map(TriMesh::vertex_count).sum();
    assert!(denter.vertex_buffer().size() >= (vertices * 16) as u64);
    assert_eq!(denter.vertex_range(1).end - denter.vertex_range(1).start, (cpu[1].vertex_count() * 16) as u64);
}

fn one_bad_dent_fails_the_gpu_batch_and_changes_nothing(context: &'static GpuContext) {
    let balls = balls();
    let original = targets();
    let mut jobs = target_jobs(&balls, &original);
    jobs[3].impact.normal = Vec3::ZERO;
    let mut denter = GpuDenter::new(context, &original).unwrap();
    let err = denter.dent_batch(&jobs).unwrap_err();
    assert!(matches!(err, GpuBatchError::Job(ref e) if e.job == 3), "{err}");
    for (t, target) in original.iter().enumerate() {
        assert_eq!(denter.read_positions(t).unwrap(), target.positions());
    }
}

/// The map-building buffers a denter keeps between batches change no result: after a batch of
/// larger grids has filled them, a batch gives bit for bit what a fresh denter gives (no kernel
/// reads a cell it has not written, so nothing is cleared), both as stages and as dented targets;
/// the memory is reused when the batch repeats and given back on request.
fn kept_buffers_change_no_result(context: &'static GpuContext) {
    let (bunny, balls, original) = (mesh::builtin("bunny").unwrap(), balls(), targets());
    let (big, jobs) = (bunny_jobs(&bunny), target_jobs(&balls, &original));
    let mut fresh = GpuDenter::new(context, &original).unwrap();
    let expected_stages = fresh.dent_map_stages(&jobs).unwrap();
    fresh.dent_batch(&jobs).unwrap();
    let expected: Vec<_> = (0..original.len()).map(|t| fresh.read_positions(t).unwrap()).collect();

    let mut kept = GpuDenter::new(context, &original).unwrap();
    assert_eq!(kept.scratch_bytes(), 0, "nothing is kept before the first batch");
    kept.dent_map_stages(&big).unwrap();
    let held = kept.scratch_bytes();
    assert!(held > 0);
    let stages = kept.dent_map_stages(&jobs).unwrap();
    for (k, (a, b)) in stages.iter().zip(&expected_stages).enumerate() {
        assert_eq!((&a.zbuffer, &a.envelope), (&b.zbuffer, &b.envelope), "dent {k}: profile or envelope");
        assert_eq!((&a.smoothed, &a.map), (&b.smoothed, &b.map), "dent {k}: heights or map");
    }
    kept.dent_map_stages(&big).unwrap();
    assert_eq!(kept.scratch_bytes(), held, "a repeated batch reuses the buffers");
    kept.release_scratch();
    assert_eq!(kept.scratch_bytes(), 0);
    kept.dent_map_stages(&big).unwrap();
    kept.dent_batch(&jobs).unwrap();
    for (t, expected) in expected.iter().enumerate() {
        assert_eq!(&kept.read_positions(t).unwrap(), expected, "target {t}");
    }
}

gpu_test_main! {
    gpu: [
        every_stage_matches_the_cpu_pipeline,
        a_gpu_batch_dents_targets_like_the_cpu_batch,
        one_bad_dent_fails_the_gpu_batch_and_changes_nothing,
        kept_buffers_change_no_result,
    ],
}
