//! Parity of `shaders/envelope_rows.wgsl` with its CPU twin `cpu::envelope_rows` (the first pass
//! of the exact Gaussian envelope) on random dense and sparse, degenerate and real (bunny)
//! profiles, widths σ from 0.1 to 1000 cells, resolutions 1 to 400, and batches mixing
//! resolutions in one dispatch.
//!
//! Tolerance: rows without a source are `+∞` on both sides, bit for bit; elsewhere
//! |V_gpu − V_cpu| ≤ 1e-5·max(1, |V|). The shader runs the twin's f32 operations in the same order
//! (the reciprocal 1/(c·Δ) is formed in place instead of read from a table, the same operations),
//! so the one source of difference is the GPU's `log`: WGSL allows an absolute error of 2⁻²¹ on
//! [0.5, 2] and 3 ulp elsewhere, and lavapipe's LLVM polynomial is not Rust's libm. The envelope
//! is a minimum of parabola values, 1-Lipschitz in the offsets −ln P, so V moves by no more than
//! the offsets do (a near-tie may switch parabolas, at the same value to that error). An error δ
//! in V = −ln E is a relative error δ in E, so this is the relative 1e-5 on E that the f64
//! exactness test (tests/exact_envelope.rs) allows; where |V| > 1 it is relative to V, whose own
//! rounding is an ulp of V. Measured on lavapipe: ≤ 5e-7 (printed by the tests). Binary profiles
//! (P ∈ {0, 1}, so −ln P = 0 up to the log's error at 1) isolate the hull logic: there the two
//! sides agree to that error, 2⁻²¹, bit for bit on lavapipe.

mod common;

use common::SplitMix64;
use common::envelope::{cpu_rows, random_profile};
use dentbend::cpu::EnvelopeParams;
use dentbend::dent::dent_map_stages;
use dentbend::gpu::GpuContext;
use dentbend::gpu::envelope_rows::EnvelopeRows;
use dentbend::{DentParams, Impact, Resolution, glam::Vec3, mesh};

/// Widths σ tested, cells.
const SIGMAS: [f32; 7] = [0.1, 0.5, 1.5, 4.0, 20.0, 100.0, 1000.0];

/// Resolutions tested, cells per side.
const RESOLUTIONS: [u32; 6] = [1, 2, 17, 64, 200, 400];

fn kernel(context: &GpuContext) -> EnvelopeRows {
    EnvelopeRows::new(context).expect("envelope_rows compiles")
}

/// Runs `dents` as one GPU batch and checks every dent against the CPU twin. Returns the largest
/// |ΔV|/max(1, |V|) seen.
#[track_caller]
fn check_batch(kernel: &EnvelopeRows, context: &GpuContext, dents: &[(EnvelopeParams, Vec<f32>)], what: &str) -> f32 {
    let refs: Vec<(EnvelopeParams, &[f32])> = dents.iter().map(|(p, g)| (*p, g.as_slice())).collect();
    let got = kernel.run_batch(context, &refs).expect("envelope_rows runs");
    assert_eq!(got.len(), dents.len());
    let mut worst = 0.0f32;
    for (d, ((params, profile), gpu)) in dents.iter().zip(&got).enumerate() {
        let cpu = cpu_rows(params, profile);
        assert_eq!(gpu.len(), cpu.len(), "{what}: dent {d}: length");
        for (k, (&g, &c)) in gpu.iter().zip(&cpu).enumerate() {
            let at = format!("{what}: dent {d} (res {}, c {}), cell {k}: GPU {g} vs CPU {c}", params.res, params.c);
            if c.is_infinite() {
                assert_eq!(g.to_bits(), c.to_bits(), "{at}: +∞ must match exactly");
                continue;
            }
            assert!(g.is_finite(), "{at}");
            let err = (g - c).abs() / c.abs().max(1.0);
            assert!(err <= 1e-5, "{at}: relative error {err:e}");
            worst = worst.max(err);
        }
    }
    worst
}

fn random_profiles_match_the_cpu_twin(context: &'static GpuContext) {
    let kernel = kernel(context);
    let mut rng = SplitMix64::new(11);
    let mut worst = 0.0f32;
    for sigma in SIGMAS {
        for density in [1.0, 0.3, 0.02, 0.002] {
            // One batch per (σ, density): every resolution in one dispatch.
            let dents: Vec<_> = RESOLUTIONS
                .iter()
                .map(|&res| (EnvelopeParams::new(res, sigma), random_profile(&mut rng, res, density, 0.7)))
                .collect();
            worst = worst.max(check_batch(&kernel, context, &dents, &format!("σ {sigma} density {density}")));
        }
    }
    eprintln!("envelope_rows random: worst relative |ΔV| = {worst:e}");
}

fn heights_far_from_one_match_the_cpu_twin(context: &'static GpuContext) {
    // −ln P spans large positive (tiny P) and negative (huge P) offsets.
    let kernel = kernel(context);
    let mut rng = SplitMix64::new(12);
    let dents: Vec<_> = [1e-30, 1e-6, 1e-3, 1.0, 1e3, 1e6, 1e30]
        .iter()
        .zip([0.3, 2.0, 30.0].iter().cycle())
        .map(|(&d, &sigma)| (EnvelopeParams::new(31, sigma), random_profile(&mut rng, 31, 0.3, d)))
        .collect();
    let worst = check_batch(&kernel, context, &dents, "scaled");
    eprintln!("envelope_rows scaled: worst relative |ΔV| = {worst:e}");
}

fn binary_profiles_give_the_same_squared_distances(context: &'static GpuContext) {
    // P ∈ {0, 1}: every offset is −ln 1 = 0 and V = c·(distance to the nearest source in the
    // row)², so the hull logic alone decides each value. WGSL bounds log's error at 1 by 2⁻²¹.
    let kernel = kernel(context);
    let mut rng = SplitMix64::new(15);
    let dents: Vec<_> = RESOLUTIONS
        .iter()
        .zip(SIGMAS)
        .flat_map(|(&res, sigma)| {
            [0.5, 0.05, 0.005].map(|density| {
                let profile: Vec<f32> = random_profile(&mut rng, res, density, 1.0).iter().map(|&p| p.ceil()).collect();
                (EnvelopeParams::new(res, sigma), profile)
            })
        })
        .collect();
    let refs: Vec<(EnvelopeParams, &[f32])> = dents.iter().map(|(p, g)| (*p, g.as_slice())).collect();
    let mut identical = true;
    for ((params, profile), gpu) in dents.iter().zip(kernel.run_batch(context, &refs).unwrap()) {
        for (k, (&g, &c)) in gpu.iter().zip(&cpu_rows(params, profile)).enumerate() {
            assert!(g == c || (g - c).abs() <= 2f32.powi(-21), "res {} cell {k}: GPU {g} vs CPU {c}", params.res);
            identical &= g.to_bits() == c.to_bits();
        }
    }
    eprintln!("envelope_rows binary profiles: bit for bit identical: {identical}");
}

fn all_zero_grids_give_infinity(context: &'static GpuContext) {
    let kernel = kernel(context);
    let dents: Vec<_> =
        [1, 2, 17, 64].iter().map(|&res| (EnvelopeParams::new(res, 1.5), vec![0.0; (res * res) as usize])).collect();
    check_batch(&kernel, context, &dents, "zero");
    let refs: Vec<(EnvelopeParams, &[f32])> = dents.iter().map(|(p, g)| (*p, g.as_slice())).collect();
    for rows in kernel.run_batch(context, &refs).unwrap() {
        assert!(rows.iter().all(|&v| v == f32::INFINITY), "an all-zero grid must give +∞ everywhere");
    }
}

fn cells_that_are_not_sources_are_skipped(context: &'static GpuContext) {
    // Zero, negative, NaN and ±∞ cells among sources as small as 1e-30 and as large as 3e38:
    // only 0 < P < ∞ is a source. (Subnormal P are left out: a GPU may flush them to zero.)
    let kernel = kernel(context);
    let res = 9u32;
    let specials = [0.0, -1.0, f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 0.5, 1e-30, 3.0e38];
    let mut rng = SplitMix64::new(13);
    let dents: Vec<_> = SIGMAS
        .iter()
        .map(|&sigma| {
            let profile =
                (0..res * res).map(|_| specials[rng.below(specials.len() as u64) as usize]).collect::<Vec<f32>>();
            (EnvelopeParams::new(res, sigma), profile)
        })
        .collect();
    check_batch(&kernel, context, &dents, "specials");
}

fn single_sources_ties_and_borders_match_the_cpu_twin(context: &'static GpuContext) {
    let kernel = kernel(context);
    let res = 23u32;
    let n = res as usize;
    let mut dents = Vec::new();
    for sigma in SIGMAS {
        let params = EnvelopeParams::new(res, sigma);
        // One source, at the centre, corners and borders.
        for (row, col) in [(11, 11), (0, 0), (0, 22), (22, 0), (22, 22), (0, 7), (5, 22)] {
            let mut p = vec![0.0; n * n];
            p[row * n + col] = 0.3;
            dents.push((params, p));
        }
        // A plateau of equal heights: every breakpoint between neighbours is a tie.
        let mut p = vec![0.0; n * n];
        for r in 4..19 {
            for c in 3..12 {
                p[r * n + c] = 0.7;
            }
        }
        dents.push((params, p));
        // Equal sources at equal distances from the cells between them (breakpoints on cells
        // and half cells), and a third one exactly as high in the middle.
        let mut p = vec![0.0; n * n];
        for r in 0..n {
            p[r * n + 2] = 0.5;
            p[r * n + 12] = 0.5;
            p[r * n + 20] = 0.5;
            if r % 2 == 0 {
                p[r * n + 7] = 0.5;
            }
        }
        dents.push((params, p));
        // Sources on the border only: the first and last cell of every row, the first and last row.
        let mut p = vec![0.0; n * n];
        for k in 0..n {
            for cell in [k, k * n, k * n + n - 1, (n - 1) * n + k] {
                p[cell] = 0.2 + 0.01 * (k % 3) as f32;
            }
        }
        dents.push((params, p));
        // Every cell the same height: a full row of ties.
        dents.push((params, vec![0.4; n * n]));
    }
    let worst = check_batch(&kernel, context, &dents, "structured");
    eprintln!("envelope_rows structured: worst relative |ΔV| = {worst:e}");
}

/// Real Z-buffer profiles of the bunny hit from several directions, as the dent pipeline makes
/// them, with the pipeline's envelope parameters.
fn bunny_profiles(resolutions: &[u32]) -> Vec<(EnvelopeParams, Vec<f32>)> {
    let bunny = mesh::builtin("bunny").unwrap();
    let mut dents = Vec::new();
    for (k, &res) in resolutions.iter().enumerate() {
        for (j, dir) in [Vec3::Y, Vec3::X, -Vec3::Z, Vec3::new(1.0, 1.0, 0.5).normalize()].into_iter().enumerate() {
            let impact = Impact::head_on(bunny.support_point(dir), dir);
            let d = [3.0, 1.0, 6.0][(k + j) % 3];
            let params = DentParams { resolution: Resolution::Fixed(res), ..DentParams::new(d) };
            let stages = dent_map_stages(&bunny, &impact, &params, None).unwrap();
            let envelope = EnvelopeParams::new(res, stages.sigma / stages.zbuffer_grid.cell_size);
            dents.push((envelope, stages.zbuffer));
        }
    }
    dents
}

fn bunny_profiles_match_the_cpu_twin(context: &'static GpuContext) {
    let kernel = kernel(context);
    let dents = bunny_profiles(&[17, 64, 200]);
    let worst = check_batch(&kernel, context, &dents, "bunny");
    eprintln!("envelope_rows bunny: worst relative |ΔV| = {worst:e}");
}

fn a_batch_equals_its_dents_run_one_by_one(context: &'static GpuContext) {
    // Offsets: each dent of a mixed batch sees only its own cells and parameters.
    let kernel = kernel(context);
    let mut rng = SplitMix64::new(14);
    let dents: Vec<_> = [64u32, 1, 200, 17, 2, 65, 7]
        .iter()
        .zip(SIGMAS)
        .map(|(&res, sigma)| (EnvelopeParams::new(res, sigma), random_profile(&mut rng, res, 0.2, 1.0)))
        .collect();
    check_batch(&kernel, context, &dents, "mixed batch");
    let refs: Vec<(EnvelopeParams, &[f32])> = dents.iter().map(|(p, g)| (*p, g.as_slice())).collect();
    let batched = kernel.run_batch(context, &refs).unwrap();
    for (dent, batched) in refs.iter().zip(&batched) {
        let alone = kernel.run_batch(context, std::slice::from_ref(dent)).unwrap();
        assert!(
            alone[0].iter().zip(batched).all(|(a, b)| a.to_bits() == b.to_bits()),
            "res {}: batched result differs from the dent run alone",
            dent.0.res
        );
    }
    assert!(kernel.run_batch(context, &[]).unwrap().is_empty());
}

gpu_test_main! {
    gpu: [
        random_profiles_match_the_cpu_twin,
        heights_far_from_one_match_the_cpu_twin,
        binary_profiles_give_the_same_squared_distances,
        all_zero_grids_give_infinity,
        cells_that_are_not_sources_are_skipped,
        single_sources_ties_and_borders_match_the_cpu_twin,
        bunny_profiles_match_the_cpu_twin,
        a_batch_equals_its_dents_run_one_by_one,
    ],
}
