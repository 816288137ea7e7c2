//! The GPU backend (`gpu::GpuBackend`) honours the same `DentParams` as the CPU batch: the
//! falloff fitted to a thin wall (with the thin-wall warning), the intersection guard limiting a
//! dent that would push one body into another (the same `limited_to`), the volume rim of
//! `VolumeMode::Preserve` (volume kept within 2 % of the cavity), the volume reports, and several
//! dents on one target in one batch, each on what the earlier ones left.

#[macro_use]
mod common;

use std::sync::Arc;

use dentbend::damage::{CpuBackend, DentBackend};
use dentbend::dent::{BatchOutcome, DentJob, VolumeMode};
use dentbend::glam::Vec3;
use dentbend::gpu::{GpuBackend, GpuContext};
use dentbend::mesh::{self, TriMesh};
use dentbend::{Attenuation, DentParams, Impact, Resolution};

use common::enclosed_volume as volume;

/// Steps of the guard's bisection: its scale is found to 2⁻¹² (src/dent/guard.rs).
const GUARD_STEP: f32 = 1.0 / 4096.0;

/// The same batch on the CPU and on the GPU: each side's targets and outcome.
fn both(
    context: &'static GpuContext,
    targets: &[TriMesh],
    jobs: &[DentJob<'_>],
) -> ((Vec<TriMesh>, BatchOutcome), (Vec<TriMesh>, BatchOutcome)) {
    let keys: Vec<usize> = (0..targets.len()).collect();
    let mut cpu = targets.to_vec();
    let cpu_outcome = CpuBackend.dent_batch(&keys, &mut cpu, jobs).unwrap();
    let mut gpu = targets.to_vec();
    let gpu_outcome = GpuBackend::new(context).dent_batch(&keys, &mut gpu, jobs).unwrap();
    ((cpu, cpu_outcome), (gpu, gpu_outcome))
}

/// Largest vertex distance between two meshes with the same faces.
fn worst(a: &TriMesh, b: &TriMesh) -> f32 {
    assert_eq!(a.faces(), b.faces(), "the same refinement on both backends");
    a.positions().iter().zip(b.positions()).map(|(p, q)| p.distance(*q)).fold(0.0, f32::max)
}

/// The parity tolerance of tests/parity_pipeline.rs for `dents` dents of distance `d` on a
/// target whose coordinates reach `scale`: the map's 2e-5·d plus a few ulps per dent.
fn parity_tolerance(dents: f32, d: f32, scale: f32) -> f32 {
    dents * (2e-5 * d + 8.0 * f32::EPSILON * scale.max(1.0))
}

/// Two 0.1-thick slabs 0.05 apart in one mesh, and a ball on the top one's centre.
fn two_slabs() -> (TriMesh, TriMesh, Impact) {
    let slab = mesh::subdivided_box(Vec3::new(1.0, 0.1, 1.0), [20, 2, 20]).unwrap();
    let lower: Vec<Vec3> = slab.positions().iter().map(|p| *p - Vec3::new(0.0, 0.15, 0.0)).collect();
    let n = slab.vertex_count() as u32;
    let positions = [slab.positions(), &lower].concat();
    let faces = [slab.faces().to_vec(), slab.faces().iter().map(|f| f.map(|v| v + n)).collect()].concat();
    let two = TriMesh::new(positions, faces).unwrap();
    let ball = common::sphere_at(Vec3::new(0.0, 0.25, 0.0), 0.2);
    (two, ball, Impact::head_on(Vec3::new(0.0, 0.05, 0.0), -Vec3::Y))
}

/// A falloff that moves everything above depth 0.12 rigidly and nothing below pushes the top slab
/// into the lower one: the guard limits it, on the GPU as on the CPU, to the same fraction (the
/// bisection's last step may differ by one: the two maps differ by 2e-5·d), and the dented
/// meshes agree within the parity tolerance plus what that step moves.
fn the_guard_limits_a_gpu_dent_as_on_the_cpu(context: &'static GpuContext) {
    let (two, ball, impact) = two_slabs();
    let step = Attenuation::Custom(Arc::new(|z: f32, _d: f32| if z < 0.12 { 1.0 } else { 0.0 }));
    let d = 0.2;
    let params = DentParams { attenuation: step, resolution: Resolution::Fixed(64), ..DentParams::new(d) };
    let jobs = [DentJob { target: 0, projectile: &ball, impact, params: params.clone() }];
    let ((cpu, cpu_out), (gpu, gpu_out)) = both(context, std::slice::from_ref(&two), &jobs);
    let (c, g) = (&cpu_out.reports[0], &gpu_out.reports[0]);
    let kept = c.limited_to.expect("the CPU limits this dent");
    assert!(kept > 0.0 && kept < 1.0, "{kept}");
    let gpu_kept = g.limited_to.expect("the GPU limits this dent too");
    assert!((gpu_kept - kept).abs() <= GUARD_STEP, "limited to {gpu_kept} on the GPU, {kept} on the CPU");
    assert!(g.warnings.iter().any(|w| w.contains("limited")), "{:?}", g.warnings);
    let all = vec![true; gpu[0].vertex_count()];
    assert_eq!(common::self_intersections(&gpu[0], &all), vec![], "the guarded GPU dent crosses no faces");
    let tol = parity_tolerance(1.0, d, 1.0) + (gpu_kept - kept).abs() * d;
    let err = worst(&cpu[0], &gpu[0]);
    assert!(err <= tol, "GPU and CPU vertices differ by {err} (allowed {tol})");
    assert!((g.max_displacement - c.max_displacement).abs() <= tol, "{g:?} vs {c:?}");
    assert_eq!(gpu_out.moved, cpu_out.moved);
    // Unguarded, the same GPU dent does cross: the check above can fail.
    let off = DentParams { guard_crossings: false, ..params };
    let jobs = [DentJob { target: 0, projectile: &ball, impact, params: off }];
    let mut unguarded = vec![two];
    let out = GpuBackend::new(context).dent_batch(&[0], &mut unguarded, &jobs).unwrap();
    assert_eq!(out.reports[0].limited_to, None);
    let all = vec![true; unguarded[0].vertex_count()];
    assert!(!common::self_intersections(&unguarded[0], &all).is_empty());
}

/// A linear falloff of scale 1 with d = 0.3 would fold the 0.25-thick plank: the GPU fits it to
/// the plank as the CPU does (stretched, with the thin-wall warning), and the dents agree within
/// the parity tolerance.
fn a_thin_plank_gets_the_fitted_falloff_on_the_gpu(context: &'static GpuContext) {
    let plank = mesh::builtin("plank").unwrap();
    let ball = common::sphere_at(Vec3::new(0.0, 0.125 + 0.1, 0.0), 0.1);
    let impact = Impact::head_on(Vec3::new(0.0, 0.125, 0.0), -Vec3::Y);
    let d = 0.3;
    let linear = Attenuation::Linear { scale: 1.0 };
    let params = DentParams { attenuation: linear, resolution: Resolution::Fixed(64), ..DentParams::new(d) };
    let jobs = [DentJob { target: 0, projectile: &ball, impact, params }];
    let ((cpu, cpu_out), (gpu, gpu_out)) = both(context, std::slice::from_ref(&plank), &jobs);
    let (c, g) = (&cpu_out.reports[0], &gpu_out.reports[0]);
    let fold = |w: &Vec<String>| w.iter().any(|w| w.contains("would fold"));
    assert!(fold(&c.warnings), "{:?}", c.warnings);
    assert!(fold(&g.warnings), "the thin-wall warning on the GPU too: {:?}", g.warnings);
    let scale = plank.bounds().1.abs().max_element();
    let tol = parity_tolerance(1.0, d, scale);
    let err = worst(&cpu[0], &gpu[0]);
    assert!(err <= tol, "GPU and CPU vertices differ by {err} (allowed {tol})");
    assert_eq!(g.limited_to, c.limited_to);
    assert_eq!((g.sigma, g.resolution, g.map_resolution), (c.sigma, c.resolution, c.map_resolution));
    // Half of the plank's 0.25 remains under the dent's centre, less the few % the peak cell under
    // the nearest vertex differs from the sampled rays (as in tests/dent_no_crossings.rs).
    let left = thickness_at_centre(&plank, &gpu[0]);
    assert!(left > 0.5 * 0.25 * 0.95 && left < 0.25, "wall left {left}");
}

/// Thickness of `dented` (the plank `plank` dented) along y under the dent's centre: the top
/// vertex nearest the axis minus the bottom one.
fn thickness_at_centre(plank: &TriMesh, dented: &TriMesh) -> f32 {
    let nearest = |top: bool| {
        let p = plank.positions();
        let v = (0..p.len())
            .filter(|&v| (p[v].y > 0.0) == top)
            .min_by(|&a, &b| p[a].with_y(0.0).length().total_cmp(&p[b].with_y(0.0).length()))
            .expect("a vertex on each side");
        dented.positions()[v].y
    };
    nearest(true) - nearest(false)
}

/// `Preserve` on the GPU: the block keeps its volume within 2 % of the cavity (measured on the
/// meshes, f64), both reports agree with that measurement and with each other, and `Free`
/// reports the cavity it leaves.
fn preserve_keeps_the_volume_on_the_gpu(context: &'static GpuContext) {
    let block = mesh::builtin("block").unwrap();
    let top = block.bounds().1.y;
    let ball = common::sphere_at(Vec3::new(0.0, top + 0.3, 0.0), 0.3);
    let impact = Impact::head_on(Vec3::new(0.0, top, 0.0), -Vec3::Y);
    let d = 0.2;
    let free = DentParams::new(d);
    let kept = DentParams { volume: VolumeMode::Preserve, ..free.clone() };
    let start = volume(&block);

    let jobs = [DentJob { target: 0, projectile: &ball, impact, params: free }];
    let ((_, cpu_free), (gpu, gpu_free)) = both(context, std::slice::from_ref(&block), &jobs);
    let cavity = start - volume(&gpu[0]);
    assert!(cavity > 1e-3, "the dent takes volume: {cavity}");
    let r = &gpu_free.reports[0];
    // The report sums the same tetrahedra (of the faces that moved, about another origin): equal
    // to the f64 rounding of sums of terms the size of the block's volume.
    assert!((r.volume_change + cavity).abs() <= 1e-10 * start, "{} vs {}", r.volume_change, -cavity);
    assert!((r.cavity_volume - cavity).abs() <= 1e-10 * start, "{} vs {cavity}", r.cavity_volume);
    // The vertices agree within the parity tolerance (8e-6 m here) over a dented area under
    // 1 m²: the cavities within 8e-6 m³, 1.6e-4 of the cavity; 1e-3 leaves margin.
    let same_cavity = |a: f64, b: f64| (a - b).abs() <= 1e-3 * b;
    assert!(same_cavity(r.cavity_volume, cpu_free.reports[0].cavity_volume), "{r:?}");

    let jobs = [DentJob { target: 0, projectile: &ball, impact, params: kept }];
    let ((cpu, cpu_kept), (gpu, gpu_kept)) = both(context, std::slice::from_ref(&block), &jobs);
    let change = volume(&gpu[0]) - start;
    assert!(change.abs() <= 0.02 * cavity, "GPU: volume change {change:.3e} of a {cavity:.3e} cavity");
    let r = &gpu_kept.reports[0];
    assert!(r.volume_change.abs() <= 0.02 * r.cavity_volume, "{r:?}");
    assert!(same_cavity(r.cavity_volume, cavity), "the rim's report names the same cavity: {r:?}");
    assert!(same_cavity(r.cavity_volume, cpu_kept.reports[0].cavity_volume), "{:?}", cpu_kept.reports[0]);
    assert!(!r.warnings.iter().any(|w| w.contains("volume")), "no volume warning: {:?}", r.warnings);
    // The rim moved vertices the dent alone did not, as on the CPU.
    assert!(gpu_kept.moved[0].len() > gpu_free.moved[0].len());
    // Two moves of each vertex, the dent and the rim (whose height is solved from positions that
    // agree to the first): twice the parity tolerance.
    let scale = block.bounds().1.abs().max_element();
    let tol = parity_tolerance(2.0, d, scale);
    let err = worst(&cpu[0], &gpu[0]);
    assert!(err <= tol, "GPU and CPU vertices differ by {err} (allowed {tol})");
}

/// Two overlapping dents on one block in one batch, with `Preserve`: the GPU runs them in two
/// rounds, each dent's host stages on what the first left, and ends where the CPU batch does.
fn several_dents_on_one_target_apply_in_order(context: &'static GpuContext) {
    let block = mesh::builtin("block").unwrap();
    let top = block.bounds().1.y;
    let ball = common::sphere_at(Vec3::new(0.0, top + 0.3, 0.0), 0.3);
    let params = DentParams { volume: VolumeMode::Preserve, ..DentParams::new(0.15) };
    let job = |x: f32| DentJob {
        target: 0,
        projectile: &ball,
        impact: Impact::head_on(Vec3::new(x, top, 0.0), -Vec3::Y),
        params: params.clone(),
    };
    // The ball's tip sits at x = 0; the impact point moves the map there.
    let jobs = [job(0.0), job(0.1)];
    let start = volume(&block);
    let ((cpu, cpu_out), (gpu, gpu_out)) = both(context, std::slice::from_ref(&block), &jobs);
    // Two dents, each with its rim: four moves' parity tolerance.
    let tol = parity_tolerance(4.0, 0.15, block.bounds().1.abs().max_element());
    let err = worst(&cpu[0], &gpu[0]);
    assert!(err <= tol, "GPU and CPU vertices differ by {err} (allowed {tol})");
    let cavities: f64 = gpu_out.reports.iter().map(|r| r.cavity_volume).sum();
    assert!(gpu_out.reports.iter().all(|r| r.cavity_volume > 0.0), "{:?}", gpu_out.reports);
    assert!((volume(&gpu[0]) - start).abs() <= 0.02 * cavities);
    for (g, c) in gpu_out.reports.iter().zip(&cpu_out.reports) {
        // As in the single dent's test: the cavities agree to far better than 1e-3.
        assert!((g.cavity_volume - c.cavity_volume).abs() <= 1e-3 * c.cavity_volume, "{g:?} vs {c:?}");
    }
    assert_eq!(gpu_out.moved, cpu_out.moved);
}

gpu_test_main! {
    gpu: [
        the_guard_limits_a_gpu_dent_as_on_the_cpu,
        a_thin_plank_gets_the_fitted_falloff_on_the_gpu,
        preserve_keeps_the_volume_on_the_gpu,
        several_dents_on_one_target_apply_in_order,
    ],
}
