//! GPU `heat` (shaders/heat.wgsl) against its CPU twin `cpu::heat_step` / `cpu::heat`: single
//! steps, the whole smoothing (plain steps, rescale to d, clamped steps) with per-dent counts in
//! one batch, counts above the batch's cut to it, and the bunny's real envelopes.
//!
//! Tolerances. A step is the CPU's expression with the same operations in the same order, so it
//! is bit-exact unless the driver contracts `s + α·L` into a fused multiply-add (SPIR-V without
//! `NoContraction` allows it; `−4·s` is exact, so fusing it changes nothing). A fused step differs
//! by at most ½ ulp of α·L plus one final rounding, under 4 ulps of the grid's largest magnitude
//! M (|α·L| ≤ 2M for α ≤ ¼), and the step is non-expansive in the max norm, so errors add up over
//! the steps. The rescale divides (WGSL's `/` is only 2.5-ulp accurate) and multiplies: 4 ulps
//! of d. Lavapipe (the CI adapter) neither fuses nor approximates `/` (measured), so there the
//! bound is zero: the GPU result is asserted bit for bit. Each test prints the largest error seen
//! (0 on lavapipe).

mod common;

use common::SplitMix64;
use dentbend::cpu::{HeatParams, heat, heat_step};
use dentbend::dent::dent_map_stages;
use dentbend::glam::Vec3;
use dentbend::gpu::heat::{FUSED_STEPS, HeatBatch, HeatBuffers, HeatDent, HeatJob, HeatKernel};
use dentbend::gpu::{GpuContext, buffers};
use dentbend::{DentParams, Impact, Resolution, mesh};

/// ε = 2⁻²³, one ulp at 1.
const EPS: f32 = f32::EPSILON;

fn random_grid(rng: &mut SplitMix64, res: u32, lo: f32, hi: f32) -> Vec<f32> {
    (0..res * res).map(|_| rng.range_f32(lo, hi)).collect()
}

/// A few Gaussian bumps of heights up to `peak`, like a broadened envelope.
fn bumps(rng: &mut SplitMix64, res: u32, peak: f32) -> Vec<f32> {
    let n = res as f32;
    let centres: Vec<(f32, f32, f32, f32)> = (0..3)
        .map(|_| (rng.range_f32(0.0, n), rng.range_f32(0.0, n), rng.range_f32(0.05, 0.3) * n, rng.range_f32(0.2, peak)))
        .collect();
    (0..res * res)
        .map(|k| {
            let (x, y) = ((k % res) as f32, (k / res) as f32);
            centres
                .iter()
                .map(|&(cx, cy, s, h)| h * (-((x - cx).powi(2) + (y - cy).powi(2)) / (s * s)).exp())
                .fold(0.0, f32::max)
        })
        .collect()
}

/// 0 on Mesa's lavapipe, which evaluates the shader's f32 arithmetic exactly as written (the
/// parity is then bit for bit); 1 elsewhere, where the rounding bounds apply.
fn rounding_slack() -> f32 {
    let exact = common::context().info.name.contains("llvmpipe");
    if exact { 0.0 } else { 1.0 }
}

fn max_abs(values: &[f32]) -> f32 {
    values.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// Largest |gpu − cpu|, asserting that it is within `tolerance`.
#[track_caller]
fn compare(what: &str, gpu: &[f32], cpu: &[f32], tolerance: f32) -> f32 {
    assert_eq!(gpu.len(), cpu.len(), "{what}: length");
    let mut worst = 0.0f32;
    for (k, (g, c)) in gpu.iter().zip(cpu).enumerate() {
        let error = (g - c).abs();
        assert!(error <= tolerance, "{what}: cell {k}: gpu {g} vs cpu {c} (|Δ| {error} > {tolerance})");
        worst = worst.max(error);
    }
    worst
}

/// Bound on |GPU − CPU| of `heat(values, res, rate, k₁, k₂, d)` (see the file's comment):
/// k₁ steps of 4 ulps of M_in, amplified by the rescale d/peak₁ and counted twice (the peak itself
/// moves by as much), 4 ulps of d for the rescale, then k₂ steps of 4 ulps of d (the clamped steps
/// stay within [0, d]).
fn heat_tolerance(job: &HeatJob<'_>) -> f32 {
    let n = (job.res * job.res) as usize;
    let (mut grid, mut other) = (job.values[..n].to_vec(), vec![0.0; n]);
    let plain = HeatParams { res: job.res, rate: job.rate, clamped: 0, cell_offset: 0 };
    for _ in 0..job.heat_iters {
        heat_step(&plain, &grid, &mut other);
        std::mem::swap(&mut grid, &mut other);
    }
    let peak = grid.iter().fold(0.0f32, |m, &v| m.max(v));
    let d = job.dent_distance;
    let amplification = if peak > 0.0 { d / peak } else { 1.0 };
    rounding_slack()
        * EPS
        * (8.0 * job.heat_iters as f32 * max_abs(&job.values[..n]) * amplification
            + 4.0 * d
            + 4.0 * job.clamp_iters as f32 * d)
}

fn cpu_heat(job: &HeatJob<'_>) -> Vec<f32> {
    let mut values = job.values[..(job.res * job.res) as usize].to_vec();
    heat(&mut values, job.res, job.rate, job.heat_iters, job.clamp_iters, job.dent_distance);
    values
}

/// Step dispatches a batch of `jobs` records: the largest k₁ and the largest k₂, each in
/// dispatches of `FUSED_STEPS` steps.
fn passes(jobs: &[HeatJob<'_>]) -> u32 {
    let most = |count: fn(&HeatJob<'_>) -> u32| jobs.iter().map(count).max().unwrap_or(0).div_ceil(FUSED_STEPS);
    most(|job| job.heat_iters) + most(|job| job.clamp_iters)
}

/// Runs `jobs` as one GPU batch and compares every dent with `cpu::heat`.
fn check_batch(kernel: &HeatKernel, what: &str, jobs: &[HeatJob<'_>]) {
    let context = common::context();
    let gpu = kernel.run_batch(context, jobs).unwrap();
    assert_eq!(gpu.len(), jobs.len());
    let mut worst = 0.0f32;
    for (k, (job, got)) in jobs.iter().zip(&gpu).enumerate() {
        let label = format!(
            "{what}, dent {k} (res {}, α {}, k₁ {}, k₂ {})",
            job.res, job.rate, job.heat_iters, job.clamp_iters
        );
        worst = worst.max(compare(&label, got, &cpu_heat(job), heat_tolerance(job)));
    }
    eprintln!("{what}: largest |GPU − CPU| {worst:e}");
}

fn single_steps_match_heat_step_bit_for_bit_or_within_fma_rounding(context: &'static GpuContext) {
    let kernel = HeatKernel::new(context).unwrap();
    let mut rng = SplitMix64::new(0x4ea7);
    // Plain and clamped steps of grids of mixed sign, twelve dents of six sizes in one dispatch.
    let mut grids = Vec::new();
    for res in [1u32, 2, 7, 64, 200, 33] {
        for clamped in [0, 1] {
            let rate = rng.range_f32(0.01, 0.25);
            grids.push((HeatParams { res, rate, clamped, cell_offset: 0 }, random_grid(&mut rng, res, -1.0, 1.0)));
        }
    }
    let batch: Vec<(HeatParams, &[f32])> = grids.iter().map(|(p, g)| (*p, g.as_slice())).collect();
    let gpu = kernel.run_step_batch(context, &batch).unwrap();
    let mut worst = 0.0f32;
    for ((params, src), got) in grids.iter().zip(&gpu) {
        let mut want = vec![0.0; src.len()];
        heat_step(params, src, &mut want);
        let label = format!("step res {} α {} clamped {}", params.res, params.rate, params.clamped);
        worst = worst.max(compare(&label, got, &want, rounding_slack() * 4.0 * EPS * max_abs(src)));
    }
    eprintln!("single steps: largest |GPU − CPU| {worst:e}");
    // A batch of one.
    let src = random_grid(&mut rng, 7, 0.0, 1.0);
    let params = HeatParams { res: 7, rate: 0.25, clamped: 0, cell_offset: 0 };
    let got = kernel.run_step_batch(context, &[(params, &src)]).unwrap();
    let mut want = vec![0.0; 49];
    heat_step(&params, &src, &mut want);
    compare("single step, batch of one", &got[0], &want, rounding_slack() * 4.0 * EPS);
}

fn whole_smoothing_matches_heat_with_per_dent_counts_in_one_batch(context: &'static GpuContext) {
    let kernel = HeatKernel::new(context).unwrap();
    let mut rng = SplitMix64::new(0x5300);
    let grids: Vec<Vec<f32>> = [1u32, 7, 64, 200, 33, 2, 64, 7]
        .iter()
        .enumerate()
        .map(|(k, &res)| if k % 2 == 0 { bumps(&mut rng, res, 2.0) } else { random_grid(&mut rng, res, 0.0, 1.0) })
        .collect();
    // (res, α, k₁, k₂, d): different sizes, rates, counts (zero included) and dent distances.
    let shapes = [
        (1u32, 0.2f32, 3u32, 2u32, 0.5f32),
        (7, 0.25, 8, 16, 3.0),
        (64, 0.2, 8, 16, 0.02),
        (200, 0.1, 10, 7, 1.0),
        (33, 0.15, 0, 4, 2.0),
        (2, 0.05, 4, 0, 1.5),
        (64, 0.25, 0, 0, 0.7),
        (7, 0.2, 1, 1, 10.0),
    ];
    let jobs: Vec<HeatJob<'_>> = shapes
        .iter()
        .zip(&grids)
        .map(|(&(res, rate, heat_iters, clamp_iters, dent_distance), values)| HeatJob {
            values,
            res,
            rate,
            heat_iters,
            clamp_iters,
            dent_distance,
        })
        .collect();
    // The batch runs 10 + 16 steps in 3 + 4 dispatches (odd: a final copy brings the result back
    // to the caller's grid); the 200² grid sets a 29-cell tile, which the 64² ones take three of
    // a side; the 200² dent's 10 and 7 steps stop inside a later dispatch of each phase ...
    assert_eq!(passes(&jobs), 7);
    check_batch(&kernel, "batch of 8, odd pass count", &jobs);
    // ... and with the two 8 + 16 dents left out, 10 + 7 steps in 3 + 2 dispatches.
    let odd: Vec<HeatJob<'_>> = jobs.iter().copied().filter(|job| job.clamp_iters != 16).collect();
    assert_eq!((odd.len(), passes(&odd)), (6, 5));
    check_batch(&kernel, "batch of 6, odd pass count", &odd);
    // Batches of one, odd and even (even: the last dispatch writes the caller's grid).
    assert_eq!((passes(&jobs[3..4]), passes(&jobs[1..2])), (5, 6));
    check_batch(&kernel, "batch of one, odd", &jobs[3..4]);
    check_batch(&kernel, "batch of one, even", &jobs[1..2]);
}

fn all_zero_grids_stay_zero_beside_others(context: &'static GpuContext) {
    let kernel = HeatKernel::new(context).unwrap();
    let mut rng = SplitMix64::new(7);
    let zeros = vec![0.0f32; 64 * 64];
    let other = bumps(&mut rng, 64, 1.0);
    let job = |values, res| HeatJob { values, res, rate: 0.2, heat_iters: 8, clamp_iters: 16, dent_distance: 1.0 };
    let jobs = [job(&zeros, 64), job(&other, 64), job(&zeros[..1], 1)];
    let gpu = kernel.run_batch(context, &jobs).unwrap();
    assert!(gpu[0].iter().chain(&gpu[2]).all(|&v| v == 0.0), "an all-zero grid must stay zero");
    let peak = gpu[1].iter().fold(0.0f32, |m, &v| m.max(v));
    // The clamped steps never raise the peak above d; rounding stays within a few ulps.
    assert!((peak - 1.0).abs() <= 8.0 * EPS, "peak {peak} after the rescale to d = 1");
    check_batch(&kernel, "zeros beside a dent", &jobs);
}

fn bunny_envelopes_smooth_like_the_cpu(context: &'static GpuContext) {
    let kernel = HeatKernel::new(context).unwrap();
    let bunny = mesh::builtin("bunny").unwrap();
    let top = bunny.support_point(Vec3::Y);
    // Head-on and glancing views of the ears, at four resolutions, default and custom smoothing.
    let mut envelopes = Vec::new();
    for (res, theta_deg, rate, heat_iters, clamp_iters) in [
        (64u32, 0.0f32, 0.2f32, 8u32, 16u32),
        (200, 0.0, 0.25, 11, 5),
        (7, 60.0, 0.2, 8, 16),
        (1, 0.0, 0.2, 8, 16),
        (96, 30.0, 0.1, 3, 20),
    ] {
        let theta = theta_deg.to_radians();
        let impact =
            Impact { point: top, normal: Vec3::Y, relative_velocity: Vec3::new(theta.sin(), theta.cos(), 0.0) };
        let params = DentParams {
            resolution: Resolution::Fixed(res),
            heat_rate: rate,
            heat_iters,
            clamp_iters,
            ..DentParams::new(3.0)
        };
        let stages = dent_map_stages(&bunny, &impact, &params, None).unwrap();
        envelopes.push((params, stages));
    }
    let jobs: Vec<HeatJob<'_>> = envelopes
        .iter()
        .map(|(params, stages)| HeatJob {
            values: &stages.envelope,
            res: stages.zbuffer_grid.res,
            rate: params.heat_rate,
            heat_iters: params.heat_iters,
            clamp_iters: params.clamp_iters,
            dent_distance: params.dent_distance,
        })
        .collect();
    // 11 + 20 steps in 3 + 5 dispatches.
    assert_eq!(passes(&jobs), 8);
    // The pipeline's own smoothed stage is the CPU reference.
    for ((_, stages), job) in envelopes.iter().zip(&jobs) {
        assert_eq!(cpu_heat(job), stages.smoothed);
    }
    check_batch(&kernel, "bunny envelopes", &jobs);
}

/// `HeatKernel::encode` cuts a dent's counts above the batch's to the batch's: a dent asking for
/// 8 + 16 steps in a batch recorded for 6 + 3 (neither a multiple of the fused passes' four
/// steps) smooths like `cpu::heat` with 6 + 3.
fn counts_above_the_batchs_are_cut_to_it(context: &'static GpuContext) {
    let kernel = HeatKernel::new(context).unwrap();
    let mut rng = SplitMix64::new(0xc07);
    let res = 40;
    let values = bumps(&mut rng, res, 1.0);
    let params = [HeatParams { res, rate: 0.2, clamped: 0, cell_offset: 0 }];
    let dents = [HeatDent { dent_distance: 0.5, heat_iters: 8, clamp_iters: 16, peak_bits: 0 }];
    let (params, dents) = (buffers::storage(context, "params", &params), buffers::storage(context, "dents", &dents));
    let (grid, scratch) = (buffers::storage(context, "grid", &values), buffers::storage(context, "scratch", &values));
    let bound = HeatBuffers { params: &params, dents: &dents, grid: &grid, scratch: &scratch };
    let batch = HeatBatch { dents: 1, max_cells: res * res, heat_iters: 6, clamp_iters: 3 };
    let mut encoder = context.device.create_command_encoder(&Default::default());
    kernel.encode(context, &mut encoder, &bound, batch).unwrap();
    context.queue.submit([encoder.finish()]);
    let gpu: Vec<f32> = buffers::read_back(context, &grid, values.len()).unwrap();
    let asked = HeatJob { values: &values, res, rate: 0.2, heat_iters: 6, clamp_iters: 3, dent_distance: 0.5 };
    let worst = compare("counts cut to the batch's", &gpu, &cpu_heat(&asked), heat_tolerance(&asked));
    eprintln!("counts cut to the batch's: largest |GPU − CPU| {worst:e}");
}

gpu_test_main! {
    gpu: [
        single_steps_match_heat_step_bit_for_bit_or_within_fma_rounding,
        whole_smoothing_matches_heat_with_per_dent_counts_in_one_batch,
        all_zero_grids_stay_zero_beside_others,
        bunny_envelopes_smooth_like_the_cpu,
        counts_above_the_batchs_are_cut_to_it,
    ],
}
