//! GPU `glance` (shaders/glance.wgsl) against its CPU twin `cpu::glance`: random heights and
//! frames, and the bunny's smoothed profiles from `dent_map_stages`, head-on and glancing (30°,
//! 60°, 84°), without and with widening, source grids of 1, 7, 64 and 200 cells a side, all
//! dents of a test in one dispatch.
//!
//! Tolerances, per dent, with H its largest height and ε = 2⁻²³:
//! - The sample coordinates use `/`, which WGSL only requires to be 2.5-ulp accurate, so x and y
//!   may move by 2.5 ulps of the largest coordinate (< src_res + 1); the bilinear value then moves
//!   by at most the largest difference between neighbouring heights times that.
//! - The bilinear weights and Δ = D₂·cos θ·n̂ + shear·D₂·t̂ may be contracted into fused
//!   multiply-adds: a few ulps of H (8εH).
//! - `exp(−t·u)` is only required to be (3 + 2·|t·u|)-ulp accurate, and the shear factor adds a
//!   division: with |Δ along t̂| ≤ 2·H the tangential part may be off by 2·(6 + 2·|t·u|)·ε·H.
//!
//! Lavapipe (the CI adapter) neither fuses nor approximates `/` (measured), so there only the
//! `exp` term is allowed: the heights are compared bit for bit, and so is Δ without widening.
//! Each test prints the largest error seen in units of its bound.

mod common;

use common::SplitMix64;
use dentbend::cpu::{GlanceParams, glance};
use dentbend::dent::dent_map_stages;
use dentbend::dent::{GLANCE_RESOLUTION_FLOOR, GLANCE_STRETCH_CAP, MAX_RESOLUTION};
use dentbend::glam::Vec3;
use dentbend::gpu::GpuContext;
use dentbend::gpu::glance::GlanceKernel;
use dentbend::{DentParams, Impact, Resolution, mesh};

/// ε = 2⁻²³, one ulp at 1.
const EPS: f32 = f32::EPSILON;

/// A dent of the batch: its parameters and heights.
struct Dent {
    params: GlanceParams,
    heights: Vec<f32>,
}

/// Parameters of the dent-map grid for `src_res` heights of `src_cell_size` at the angle of
/// `(sin θ, cos θ)`, sized as the dent pipeline sizes it (`src/dent/pipeline.rs`, `glance`: the
/// heights' cell size kept, side `res/cos θ`).
fn frame_params(
    src_res: u32,
    src_cell_size: f32,
    (sin_theta, cos_theta): (f32, f32),
    widen: f32,
    normal: Vec3,
    tangent: Vec3,
) -> GlanceParams {
    let stretch = 1.0 / cos_theta;
    // The pipeline's rule (`plan::map_grid`): the heights' cell size kept along the stretch, up
    // to GLANCE_STRETCH_CAP·res cells (at least GLANCE_RESOLUTION_FLOOR, at most MAX_RESOLUTION).
    let cap = (GLANCE_STRETCH_CAP * src_res).clamp(GLANCE_RESOLUTION_FLOOR, MAX_RESOLUTION);
    let dst_res = ((src_res as f32 * stretch).ceil() as u32).clamp(src_res, cap.max(src_res));
    let dst_cell_size = src_cell_size * src_res as f32 * stretch / dst_res as f32;
    GlanceParams {
        src_res,
        src_cell_size,
        dst_res,
        dst_cell_size,
        cos_theta,
        sin_theta,
        widen,
        src_offset: 0,
        normal: normal.to_array(),
        dst_offset: 0,
        tangent: tangent.to_array(),
        _pad: 0,
    }
}

/// True on Mesa's lavapipe, which evaluates the shader's f32 arithmetic exactly as written.
fn exact_arithmetic() -> bool {
    common::context().info.name.contains("llvmpipe")
}

/// Bound on |GPU − CPU| of each component of `dent` (see the file's comment): (Δ, height).
fn tolerance(dent: &Dent) -> (f32, f32) {
    let p = &dent.params;
    let n = p.src_res as usize;
    let h = dent.heights.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    let mut slope = 0.0f32;
    for j in 0..n {
        for i in 0..n {
            let at = |i: usize, j: usize| if i < n && j < n { dent.heights[j * n + i] } else { 0.0 };
            let here = at(i, j);
            // Neighbours right and below, the border's zeros included (left and above are
            // covered from the other side; the zeros past the first row and column by `here`).
            slope = slope.max((here - at(i + 1, j)).abs()).max((here - at(i, j + 1)).abs()).max(here.abs());
        }
    }
    let exact = exact_arithmetic();
    let height = if exact { 0.0 } else { slope * 2.5 * EPS * (p.src_res + 1) as f32 + 8.0 * EPS * h };
    // |t·u| is largest at the map's border; without widening e^{−0} = 1 is exact on lavapipe.
    let tu = p.widen * 0.5 * p.dst_res as f32 * p.dst_cell_size;
    let shear = if exact && p.widen == 0.0 { 0.0 } else { 2.0 * (6.0 + 2.0 * tu) * EPS * h };
    (height + shear, height)
}

/// Runs `dents` as one GPU batch and compares every cell with `cpu::glance`.
fn check_batch(kernel: &GlanceKernel, what: &str, dents: &[Dent]) {
    let context = common::context();
    let batch: Vec<(GlanceParams, &[f32])> = dents.iter().map(|d| (d.params, d.heights.as_slice())).collect();
    let gpu = kernel.run_batch(context, &batch).unwrap();
    assert_eq!(gpu.len(), dents.len());
    let mut worst = 0.0f32;
    for (k, (dent, got)) in dents.iter().zip(&gpu).enumerate() {
        let p = &dent.params;
        let mut want = vec![[0.0; 4]; (p.dst_res as usize).pow(2)];
        glance(p, &dent.heights, &mut want);
        assert_eq!(got.len(), want.len(), "{what}, dent {k}: cells");
        let (delta_tolerance, height_tolerance) = tolerance(dent);
        for (cell, (g, c)) in got.iter().zip(&want).enumerate() {
            for axis in 0..4 {
                let bound = if axis == 3 { height_tolerance } else { delta_tolerance };
                let error = (g[axis] - c[axis]).abs();
                assert!(
                    error <= bound,
                    "{what}, dent {k} (src {} dst {} cos θ {} t {}): cell {cell} axis {axis}: gpu {} vs cpu {} (|Δ| {error} > {bound})",
                    p.src_res,
                    p.dst_res,
                    p.cos_theta,
                    p.widen,
                    g[axis],
                    c[axis]
                );
                if error > 0.0 {
                    worst = worst.max(error / bound);
                }
            }
        }
        assert!(
            want.iter().any(|c| c[3] != 0.0) || dent.heights.iter().all(|&h| h == 0.0),
            "{what}, dent {k}: empty map"
        );
    }
    eprintln!("{what}: largest error {worst:.3} of the bound");
}

/// A random orthonormal (normal, tangent) pair.
fn random_frame(rng: &mut SplitMix64) -> (Vec3, Vec3) {
    let mut unit =
        || Vec3::new(rng.range_f32(-1.0, 1.0), rng.range_f32(-1.0, 1.0), rng.range_f32(-1.0, 1.0)).normalize();
    let normal = unit();
    let tangent = normal.cross(unit()).normalize();
    (normal, tangent)
}

fn random_heights_and_frames_match_the_cpu_in_one_batch(context: &'static GpuContext) {
    let kernel = GlanceKernel::new(context).unwrap();
    let mut rng = SplitMix64::new(0x61a9ce);
    // (src_res, θ in degrees, widening in units of 1/half-extent): every size, angle and both
    // widenings, ten dents of different sizes in one dispatch.
    let shapes = [
        (1u32, 0.0f32, 0.0f32),
        (1, 60.0, 3.0),
        (7, 30.0, 2.0),
        (7, 84.0, 0.0),
        (64, 0.0, 1.0),
        (64, 60.0, 0.0),
        (64, 84.0, 4.0),
        (200, 0.0, 0.0),
        (200, 30.0, 2.5),
        (200, 84.0, 1.5),
    ];
    let dents: Vec<Dent> = shapes
        .iter()
        .map(|&(src_res, theta_deg, widen_units)| {
            let cell = rng.range_f32(0.001, 0.1);
            let (normal, tangent) = random_frame(&mut rng);
            let mut params = frame_params(src_res, cell, theta_deg.to_radians().sin_cos(), 0.0, normal, tangent);
            params.widen = widen_units / (0.5 * params.dst_res as f32 * params.dst_cell_size);
            let heights = (0..src_res * src_res).map(|_| rng.range_f32(0.0, 2.0)).collect();
            Dent { params, heights }
        })
        .collect();
    check_batch(&kernel, "random heights, batch of 10", &dents);
    check_batch(&kernel, "random heights, batch of one", &dents[8..9]);
}

fn maps_reaching_past_the_heights_on_every_side_fade_to_zero_like_the_cpu(context: &'static GpuContext) {
    let kernel = GlanceKernel::new(context).unwrap();
    let mut rng = SplitMix64::new(0xb0de);
    // Map grids not sized by the pipeline: wider than the stretched heights in both directions,
    // so samples fall in the half cell past every border (bilinear fade to zero) and beyond.
    // (src_res, dst_res, dst cell / src cell, θ in degrees, widening in 1/half-extent)
    let shapes = [
        (1u32, 9u32, 0.4f32, 60.0f32, 0.0f32),
        (7, 13, 1.3, 30.0, 2.0),
        (64, 50, 1.7, 0.0, 0.0),
        (64, 90, 1.1, 84.0, 1.0),
        (200, 257, 0.9, 0.0, 3.0),
    ];
    let dents: Vec<Dent> = shapes
        .iter()
        .map(|&(src_res, dst_res, ratio, theta_deg, widen_units)| {
            let cell = rng.range_f32(0.001, 0.1);
            let (normal, tangent) = random_frame(&mut rng);
            let mut params = frame_params(src_res, cell, theta_deg.to_radians().sin_cos(), 0.0, normal, tangent);
            params.dst_res = dst_res;
            params.dst_cell_size = ratio * cell;
            params.widen = widen_units / (0.5 * dst_res as f32 * params.dst_cell_size);
            let heights = (0..src_res * src_res).map(|_| rng.range_f32(0.5, 2.0)).collect();
            Dent { params, heights }
        })
        .collect();
    check_batch(&kernel, "maps past the borders, batch of 5", &dents);
}

fn bunny_profiles_map_like_the_pipeline(context: &'static GpuContext) {
    let kernel = GlanceKernel::new(context).unwrap();
    let bunny = mesh::builtin("bunny").unwrap();
    let top = bunny.support_point(Vec3::Y);
    let d = 3.0;
    let mut dents = Vec::new();
    // Head-on and glancing views of the ears at four resolutions, without and with widening
    // (t = 0.1/world unit turns e^{−t·u} from ~e^{−3} to ~e^{3} across a map).
    for (res, theta_deg, widen) in [
        (64u32, 0.0f32, 0.0f32),
        (64, 30.0, 0.1),
        (7, 60.0, 0.0),
        (200, 30.0, 0.0),
        (1, 0.0, 0.0),
        (64, 84.0, 0.1),
        (48, 60.0, 0.1),
    ] {
        let theta = f32::to_radians(theta_deg);
        let impact =
            Impact { point: top, normal: Vec3::Y, relative_velocity: Vec3::new(theta.sin(), theta.cos(), 0.0) };
        let params = DentParams { resolution: Resolution::Fixed(res), widen, ..DentParams::new(d) };
        let stages = dent_map_stages(&bunny, &impact, &params, None).unwrap();
        let (z, frame) = (&stages.zbuffer_grid, &stages.frame);
        let angle = (frame.sin_theta, frame.cos_theta);
        let params = frame_params(z.res, z.cell_size, angle, widen, frame.normal, frame.tangent);
        let dent = Dent { params, heights: stages.smoothed.clone() };
        // These are the pipeline's own parameters: the CPU twin gives back its map exactly.
        let mut cells = vec![[0.0; 4]; stages.map.cells.len()];
        glance(&dent.params, &dent.heights, &mut cells);
        assert_eq!(dent.params.dst_res, stages.map.grid.res);
        assert_eq!(cells, stages.map.cells, "θ {theta_deg}°: parameters differ from the pipeline's");
        dents.push(dent);
    }
    check_batch(&kernel, "bunny profiles, batch of 7", &dents);
}

gpu_test_main! {
    gpu: [
        random_heights_and_frames_match_the_cpu_in_one_batch,
        maps_reaching_past_the_heights_on_every_side_fade_to_zero_like_the_cpu,
        bunny_profiles_map_like_the_pipeline,
    ],
}
