//! Parity of `shaders/envelope_cols.wgsl` with its CPU twin `cpu::envelope_cols` (the second
//! pass of the exact Gaussian envelope), and of both GPU passes together with the CPU pipeline
//! and the f64 brute force `envelope_brute`, on random dense and sparse, degenerate and real
//! (bunny) profiles, σ from 0.1 to 1000 cells, resolutions 1 to 400, mixed-resolution batches.
//!
//! Tolerances:
//! - Against the CPU passes: |E_gpu − E_cpu| ≤ E·(1e-5 + 4·ε·V) + f32::MIN_POSITIVE, with
//!   E = E_cpu, V = −ln E (the log-domain value the kernel computes) and ε = f32::EPSILON. The
//!   shaders run the twins' f32 operations in the same order; what differs is the GPU's `log` (rows
//!   pass: a few 1e-7 on the offsets −ln P, see tests/parity_envelope_rows.rs) and `exp` (WGSL
//!   allows 3 + 2·|x| ulp). A change of δ in V is a relative change δ in E: 1e-5 covers the log
//!   and exp errors near the peak (V ≈ 0), and 4·ε·V a few ulps of V itself, which the two sides
//!   may round apart once an offset differs in its last bit; that term only matters far down the
//!   tails (V ≈ 70 at E ≈ 1e-31·P gives relative 1e-5 per ulp). Below the smallest normal f32 a
//!   GPU may flush to zero, hence the absolute floor. Fed the same rows (the columns pass alone),
//!   V is the same on both sides and only `exp` differs.
//! - Both GPU passes against the f64 brute force: max |E − E_brute| ≤ 1e-5·max P, the bound of the
//!   CPU exactness test (tests/exact_envelope.rs), which the GPU's few-ulp log/exp keep.

mod common;

use common::SplitMix64;
use common::envelope::{cpu_rows, random_profile};
use dentbend::cpu::{self, EnvelopeParams, reference::envelope_brute};
use dentbend::dent::dent_map_stages;
use dentbend::gpu::envelope_cols::EnvelopeCols;
use dentbend::gpu::envelope_rows::{EnvelopeBuffers, EnvelopeRows, scratch_bytes};
use dentbend::gpu::{GpuContext, buffers};
use dentbend::{DentParams, Impact, Resolution, glam::Vec3, mesh};

/// Widths σ tested, cells.
const SIGMAS: [f32; 7] = [0.1, 0.5, 1.5, 4.0, 20.0, 100.0, 1000.0];

/// Resolutions tested, cells per side.
const RESOLUTIONS: [u32; 6] = [1, 2, 17, 64, 200, 400];

/// Both kernels, compiled once per test.
struct Kernels {
    rows: EnvelopeRows,
    cols: EnvelopeCols,
}

fn kernels(context: &GpuContext) -> Kernels {
    Kernels {
        rows: EnvelopeRows::new(context).expect("envelope_rows compiles"),
        cols: EnvelopeCols::new(context).expect("envelope_cols compiles"),
    }
}

/// The CPU columns pass on one dent.
fn cpu_cols(params: &EnvelopeParams, rows: &[f32]) -> Vec<f32> {
    let mut out = vec![f32::NAN; rows.len()];
    cpu::envelope_cols(params, rows, &mut out);
    out
}

/// Both GPU passes over a batch, recorded in one encoder sharing one scratch buffer, as the
/// batched pipeline records them. Returns each dent's envelope.
fn gpu_envelope(kernels: &Kernels, context: &GpuContext, dents: &[(EnvelopeParams, Vec<f32>)]) -> Vec<Vec<f32>> {
    let mut params = Vec::new();
    let mut profile = Vec::new();
    for (p, grid) in dents {
        params.push(EnvelopeParams { cell_offset: profile.len() as u32, ..*p });
        profile.extend_from_slice(grid);
    }
    let cells = profile.len() as u64;
    let max_res = dents.iter().map(|(p, _)| p.res).max().unwrap_or(0);
    let params_buf = buffers::storage(context, "params", &params);
    let profile_buf = buffers::storage(context, "profile", &profile);
    let rows_buf = buffers::storage_zeroed(context, "rows", cells * 4);
    let envelope_buf = buffers::storage_zeroed(context, "envelope", cells * 4);
    let scratch = buffers::storage_zeroed(context, "hull", scratch_bytes(cells));
    let mut encoder = context.device.create_command_encoder(&Default::default());
    let batch = dents.len() as u32;
    let first = EnvelopeBuffers { params: &params_buf, input: &profile_buf, output: &rows_buf, scratch: &scratch };
    kernels.rows.encode(context, &mut encoder, &first, batch, max_res).unwrap();
    let second = EnvelopeBuffers { params: &params_buf, input: &rows_buf, output: &envelope_buf, scratch: &scratch };
    kernels.cols.encode(context, &mut encoder, &second, batch, max_res).unwrap();
    context.queue.submit([encoder.finish()]);
    let flat: Vec<f32> = buffers::read_back(context, &envelope_buf, profile.len()).unwrap();
    params.iter().map(|p| flat[p.cell_offset as usize..][..(p.res * p.res) as usize].to_vec()).collect()
}

/// Checks `gpu` against `cpu` cell by cell: |ΔE| ≤ E·(1e-5 + 4·ε·V) + f32::MIN_POSITIVE with
/// E = E_cpu, V = −ln E and ε = f32::EPSILON (see the module comment). Returns the largest
/// |ΔE|/E over the cells with E ≥ 1e-6·max E, where the envelope is visible in f32 next to its
/// peak.
#[track_caller]
fn check_close(gpu: &[f32], cpu: &[f32], what: &str) -> f32 {
    assert_eq!(gpu.len(), cpu.len(), "{what}: length");
    let peak = cpu.iter().fold(0.0f32, |m, &e| m.max(e));
    let mut worst = 0.0f32;
    for (k, (&g, &c)) in gpu.iter().zip(cpu).enumerate() {
        let err = (g - c).abs();
        let v = if c > 0.0 { -c.ln().min(0.0) } else { 0.0 };
        let allowed = c * (1e-5 + 4.0 * f32::EPSILON * v) + f32::MIN_POSITIVE;
        assert!(err <= allowed, "{what}: cell {k}: GPU {g} vs CPU {c}: |ΔE|/E = {:e}", err / c);
        if c >= 1e-6 * peak {
            worst = worst.max(err / c);
        }
    }
    worst
}

/// Runs the columns pass alone on the CPU's rows pass of `dents` (one batch) and checks it
/// against the CPU columns pass.
#[track_caller]
fn check_cols(kernels: &Kernels, context: &GpuContext, dents: &[(EnvelopeParams, Vec<f32>)], what: &str) -> f32 {
    let rows: Vec<(EnvelopeParams, Vec<f32>)> = dents.iter().map(|(p, g)| (*p, cpu_rows(p, g))).collect();
    let refs: Vec<(EnvelopeParams, &[f32])> = rows.iter().map(|(p, r)| (*p, r.as_slice())).collect();
    let got = kernels.cols.run_batch(context, &refs).expect("envelope_cols runs");
    assert_eq!(got.len(), dents.len());
    let mut worst = 0.0f32;
    for (d, ((params, rows), gpu)) in rows.iter().zip(&got).enumerate() {
        let cpu = cpu_cols(params, rows);
        worst = worst.max(check_close(gpu, &cpu, &format!("{what}: dent {d} (res {}, c {})", params.res, params.c)));
    }
    worst
}

/// Runs both GPU passes on `dents` (one batch) and checks them against both CPU passes and,
/// where `brute` says so, against the f64 brute force.
#[track_caller]
fn check_both(
    kernels: &Kernels,
    context: &GpuContext,
    dents: &[(EnvelopeParams, Vec<f32>)],
    brute: impl Fn(&EnvelopeParams, &[f32]) -> bool,
    what: &str,
) -> f32 {
    let got = gpu_envelope(kernels, context, dents);
    let mut worst = 0.0f32;
    for (d, ((params, profile), gpu)) in dents.iter().zip(&got).enumerate() {
        let at = format!("{what}: dent {d} (res {}, c {})", params.res, params.c);
        let cpu = cpu_cols(params, &cpu_rows(params, profile));
        worst = worst.max(check_close(gpu, &cpu, &at));
        if brute(params, profile) {
            let want = envelope_brute(params.res, f64::from(params.c), profile);
            let peak = profile.iter().fold(0.0f32, |m, &p| m.max(p));
            for (k, (&g, &w)) in gpu.iter().zip(&want).enumerate() {
                let err = (f64::from(g) - w).abs();
                assert!(err <= 1e-5 * f64::from(peak), "{at}: cell {k}: GPU {g} vs brute force {w}, max P {peak}");
            }
        }
    }
    worst
}

/// Whether the O(sources·cells) brute force is quick enough for this profile.
fn brute_is_cheap(params: &EnvelopeParams, profile: &[f32]) -> bool {
    let sources = profile.iter().filter(|&&p| p > 0.0).count() as u64;
    sources * u64::from(params.res).pow(2) <= 50_000_000
}

fn random_profiles_match_the_cpu_twin(context: &'static GpuContext) {
    let kernels = kernels(context);
    let mut rng = SplitMix64::new(21);
    let mut worst = 0.0f32;
    for sigma in SIGMAS {
        for density in [1.0, 0.3, 0.02, 0.002] {
            let dents: Vec<_> = RESOLUTIONS
                .iter()
                .map(|&res| (EnvelopeParams::new(res, sigma), random_profile(&mut rng, res, density, 0.7)))
                .collect();
            worst = worst.max(check_cols(&kernels, context, &dents, &format!("σ {sigma} density {density}")));
        }
    }
    eprintln!("envelope_cols random: worst relative |ΔE| = {worst:e}");
}

fn both_passes_match_the_cpu_and_the_brute_force(context: &'static GpuContext) {
    let kernels = kernels(context);
    let mut rng = SplitMix64::new(22);
    let mut worst = 0.0f32;
    for sigma in SIGMAS {
        for density in [1.0, 0.1, 0.002] {
            let dents: Vec<_> = RESOLUTIONS
                .iter()
                .map(|&res| (EnvelopeParams::new(res, sigma), random_profile(&mut rng, res, density, 1.5)))
                .collect();
            worst = worst.max(check_both(&kernels, context, &dents, brute_is_cheap, &format!("σ {sigma} d {density}")));
        }
    }
    // Heights far from one: −ln P spans large positive and negative offsets.
    let dents: Vec<_> = [1e-6, 1e-3, 1.0, 1e3, 1e6]
        .iter()
        .zip([0.3, 2.0, 30.0].iter().cycle())
        .map(|(&d, &sigma)| (EnvelopeParams::new(31, sigma), random_profile(&mut rng, 31, 0.3, d)))
        .collect();
    worst = worst.max(check_both(&kernels, context, &dents, |_, _| true, "scaled"));
    eprintln!("envelope both passes random: worst relative |ΔE| vs CPU = {worst:e}");
}

fn all_zero_grids_give_zero(context: &'static GpuContext) {
    let kernels = kernels(context);
    let dents: Vec<_> =
        [1, 2, 17, 64].iter().map(|&res| (EnvelopeParams::new(res, 4.0), vec![0.0; (res * res) as usize])).collect();
    for envelope in gpu_envelope(&kernels, context, &dents) {
        assert!(envelope.iter().all(|&e| e.to_bits() == 0), "an all-zero profile must give E = +0 exactly");
    }
}

fn empty_rows_and_columns_give_zero_exactly(context: &'static GpuContext) {
    // Rows-pass output with whole rows at +∞, and columns where every row is +∞: those columns
    // are exactly 0, the others as on the CPU.
    let kernels = kernels(context);
    let res = 19u32;
    let n = res as usize;
    let mut profile = vec![0.0; n * n];
    for (row, col) in [(3, 4), (3, 9), (12, 0), (18, 18)] {
        profile[row * n + col] = 0.9;
    }
    let dents: Vec<_> = SIGMAS.iter().map(|&sigma| (EnvelopeParams::new(res, sigma), profile.clone())).collect();
    check_cols(&kernels, context, &dents, "sparse rows");
    check_both(&kernels, context, &dents, |_, _| true, "sparse rows");
    // A rows input built by hand: +∞ except in column 5 (every row finite there), so every other
    // column has no source.
    let mut rows = vec![f32::INFINITY; n * n];
    for j in 0..n {
        rows[j * n + 5] = 0.25 * j as f32;
    }
    let params = EnvelopeParams::new(res, 1.5);
    let got = kernels.cols.run_batch(context, &[(params, rows.as_slice())]).unwrap().remove(0);
    check_close(&got, &cpu_cols(&params, &rows), "hand-made rows");
    for (k, &e) in got.iter().enumerate() {
        assert_eq!(e.to_bits() == 0, k % n != 5, "cell {k}: {e}");
    }
}

fn single_sources_ties_and_borders_match(context: &'static GpuContext) {
    let kernels = kernels(context);
    let res = 23u32;
    let n = res as usize;
    let mut dents = Vec::new();
    for sigma in SIGMAS {
        let params = EnvelopeParams::new(res, sigma);
        for (row, col) in [(11, 11), (0, 0), (0, 22), (22, 0), (22, 22), (0, 7), (5, 22)] {
            let mut p = vec![0.0; n * n];
            p[row * n + col] = 0.3;
            dents.push((params, p));
        }
        // A plateau of equal heights, equal sources at equal distances, sources on the border
        // only, and a uniform grid: ties everywhere.
        let mut plateau = vec![0.0; n * n];
        let mut equal = vec![0.0; n * n];
        let mut border = vec![0.0; n * n];
        for r in 0..n {
            for c in 0..n {
                if (4..19).contains(&r) && (3..12).contains(&c) {
                    plateau[r * n + c] = 0.7;
                }
                if (r % 5 == 1 || r % 5 == 3) && (c % 6 == 2 || c % 6 == 4) {
                    equal[r * n + c] = 0.5;
                }
                if r == 0 || c == 0 || r == n - 1 || c == n - 1 {
                    border[r * n + c] = 0.2 + 0.01 * ((r + c) % 3) as f32;
                }
            }
        }
        dents.extend([(params, plateau), (params, equal), (params, border), (params, vec![0.4; n * n])]);
    }
    let worst = check_both(&kernels, context, &dents, |_, _| true, "structured");
    check_cols(&kernels, context, &dents, "structured");
    eprintln!("envelope both passes structured: worst relative |ΔE| vs CPU = {worst:e}");
}

fn bunny_profiles_match_the_pipeline_and_the_brute_force(context: &'static GpuContext) {
    let kernels = kernels(context);
    let bunny = mesh::builtin("bunny").unwrap();
    let mut dents = Vec::new();
    let mut envelopes = Vec::new();
    for (k, res) in [17u32, 64, 200].into_iter().enumerate() {
        for (j, dir) in [Vec3::Y, Vec3::X, -Vec3::Z, Vec3::new(1.0, 1.0, 0.5).normalize()].into_iter().enumerate() {
            let impact = Impact::head_on(bunny.support_point(dir), dir);
            let d = [3.0, 1.0, 6.0][(k + j) % 3];
            let params = DentParams { resolution: Resolution::Fixed(res), ..DentParams::new(d) };
            let stages = dent_map_stages(&bunny, &impact, &params, None).unwrap();
            dents.push((EnvelopeParams::new(res, stages.sigma / stages.zbuffer_grid.cell_size), stages.zbuffer));
            envelopes.push(stages.envelope);
        }
    }
    // Against both CPU passes, the brute force where cheap, and the pipeline's own envelope stage.
    let worst = check_both(&kernels, context, &dents, brute_is_cheap, "bunny");
    check_cols(&kernels, context, &dents, "bunny");
    for (d, (gpu, cpu)) in gpu_envelope(&kernels, context, &dents).iter().zip(&envelopes).enumerate() {
        check_close(gpu, cpu, &format!("bunny dent {d} vs dent_map_stages"));
    }
    eprintln!("envelope both passes bunny: worst relative |ΔE| vs CPU = {worst:e}");
}

fn a_batch_equals_its_dents_run_one_by_one(context: &'static GpuContext) {
    let kernels = kernels(context);
    let mut rng = SplitMix64::new(23);
    let dents: Vec<_> = [64u32, 1, 200, 17, 2, 65, 7]
        .iter()
        .zip(SIGMAS)
        .map(|(&res, sigma)| (EnvelopeParams::new(res, sigma), random_profile(&mut rng, res, 0.2, 1.0)))
        .collect();
    let batched = gpu_envelope(&kernels, context, &dents);
    for (dent, batched) in dents.iter().zip(&batched) {
        let alone = gpu_envelope(&kernels, context, std::slice::from_ref(dent));
        assert!(
            alone[0].iter().zip(batched).all(|(a, b)| a.to_bits() == b.to_bits()),
            "res {}: batched envelope differs from the dent run alone",
            dent.0.res
        );
    }
    check_both(&kernels, context, &dents, brute_is_cheap, "mixed batch");
    assert!(kernels.cols.run_batch(context, &[]).unwrap().is_empty());
}

fn the_largest_resolution_matches_the_cpu(context: &'static GpuContext) {
    // MAX_RESOLUTION = 2048: the hull scratch and grids at their largest for one dent.
    let kernels = kernels(context);
    let mut rng = SplitMix64::new(24);
    let res = dentbend::dent::MAX_RESOLUTION;
    let dents = [(EnvelopeParams::new(res, 6.0), random_profile(&mut rng, res, 0.01, 1.0))];
    check_both(&kernels, context, &dents, |_, _| false, "2048");
}

gpu_test_main! {
    gpu: [
        random_profiles_match_the_cpu_twin,
        both_passes_match_the_cpu_and_the_brute_force,
        all_zero_grids_give_zero,
        empty_rows_and_columns_give_zero_exactly,
        single_sources_ties_and_borders_match,
        bunny_profiles_match_the_pipeline_and_the_brute_force,
        a_batch_equals_its_dents_run_one_by_one,
        the_largest_resolution_matches_the_cpu,
    ],
}
