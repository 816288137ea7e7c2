//! Guards the exact Gaussian envelope (`envelope_rows` then `envelope_cols`, ARCHITECTURE.md §4
//! "Broadening") against the f64 brute force `envelope_brute` on random, sparse and degenerate
//! profiles and a range of widths.
//!
//! Tolerance: max |E − E_brute| ≤ 1e-5·d, d = max P. The kernels work in f32 in the log domain:
//! the value V = −ln E of a cell and the offsets −ln P it comes from carry a few ulps each, so E
//! is off by a relative few 1e-7·(V + |ln d|), and V·e^(−V) < 1 wherever E is a noticeable
//! fraction of d. Measured: ≤ 1.3e-6·d (at d = 1e6, where |ln d| ≈ 14), typically 1e-7·d.
//! Mutated kernels (a breakpoint moved by half a cell, b scaled by 1.001, a column of a block
//! dropped, an offset of 0.01 cell) all fail it.

mod common;

use common::SplitMix64;
use dentbend::cpu::{EnvelopeParams, envelope_cols, envelope_rows, reference::envelope_brute};

/// `c = 1/(2σ²)` for σ in cells.
fn c_of(sigma: f64) -> f64 {
    0.5 / (sigma * sigma)
}

/// Both passes of the kernel.
fn envelope(res: u32, c: f32, profile: &[f32]) -> Vec<f32> {
    let params = EnvelopeParams { res, c, cell_offset: 0, _pad: 0 };
    let n = (res * res) as usize;
    let mut rows = vec![f32::NAN; n];
    let mut env = vec![f32::NAN; n];
    envelope_rows(&params, profile, &mut rows);
    envelope_cols(&params, &rows, &mut env);
    env
}

/// Runs the kernel and the brute force and checks them against each other and the envelope's
/// bounds `P ≤ E ≤ max P`. Returns the kernel's envelope.
#[track_caller]
fn check(res: u32, sigma: f64, profile: &[f32], what: &str) -> Vec<f32> {
    let c = c_of(sigma);
    let got = envelope(res, c as f32, profile);
    // The kernel sees c rounded to f32: compare against the brute force at that c.
    let want = envelope_brute(res, f64::from(c as f32), profile);
    let d = profile.iter().fold(0.0f32, |m, &p| m.max(p));
    let mut worst = (0.0f64, 0);
    for (k, (&e, &w)) in got.iter().zip(&want).enumerate() {
        assert!(e.is_finite(), "{what}: res {res} σ {sigma}: cell {k} is {e}");
        let err = (f64::from(e) - w).abs();
        if err > worst.0 {
            worst = (err, k);
        }
    }
    let (err, k) = worst;
    assert!(
        err <= 1e-5 * f64::from(d),
        "{what}: res {res} σ {sigma}: |E − brute| = {err:e} at cell {k} (row {}, col {}): {} vs {}, d = {d}",
        k / res as usize,
        k % res as usize,
        got[k],
        want[k]
    );
    // Each cell is its own source, so E ≥ P (up to the f32 rounding of ln/exp), and no Gaussian
    // exceeds its peak.
    for (k, (&e, &p)) in got.iter().zip(profile).enumerate() {
        assert!(e >= p * (1.0 - 1e-6), "{what}: E < P at cell {k}: {e} < {p}");
        assert!(e <= d * (1.0 + 1e-6), "{what}: E > max P at cell {k}: {e} > {d}");
    }
    got
}

fn random_profile(rng: &mut SplitMix64, res: u32, density: f32, d: f32) -> Vec<f32> {
    (0..res * res).map(|_| if rng.next_f32() < density { d * rng.range_f32(0.01, 1.0) } else { 0.0 }).collect()
}

const SIGMAS: [f64; 7] = [0.05, 0.3, 0.7, 1.5, 4.0, 20.0, 1e4];

#[test]
fn dense_random_profiles_match_brute_force() {
    let mut rng = SplitMix64::new(1);
    for res in [1, 2, 3, 5, 17, 64] {
        for sigma in SIGMAS {
            let p = random_profile(&mut rng, res, 1.0, 0.2);
            check(res, sigma, &p, "dense");
        }
    }
}

#[test]
fn sparse_random_profiles_match_brute_force() {
    let mut rng = SplitMix64::new(2);
    for res in [2, 3, 17, 33, 64] {
        for sigma in SIGMAS {
            for density in [0.002, 0.02, 0.1] {
                let p = random_profile(&mut rng, res, density, 1.5);
                check(res, sigma, &p, "sparse");
            }
        }
    }
}

#[test]
fn dent_distances_far_from_one_match_brute_force() {
    // −ln P ranges over large positive (tiny d) and negative (huge d) offsets.
    let mut rng = SplitMix64::new(3);
    for d in [1e-6, 1e-3, 1.0, 1e3, 1e6] {
        for sigma in [0.5, 3.0, 30.0] {
            let p = random_profile(&mut rng, 31, 0.3, d);
            check(31, sigma, &p, "scaled");
        }
    }
}

#[test]
fn all_zero_grid_gives_zero() {
    for res in [1, 4, 17] {
        for sigma in SIGMAS {
            let p = vec![0.0; (res * res) as usize];
            let e = check(res, sigma, &p, "zero");
            assert!(e.iter().all(|&v| v == 0.0), "all-zero profile must give E = 0 exactly");
        }
    }
}

#[test]
fn single_source_gives_the_gaussian() {
    let res = 23;
    let d = 0.3f32;
    for (row, col) in [(11, 11), (0, 0), (0, 22), (22, 0), (22, 22), (0, 7), (5, 22)] {
        for sigma in SIGMAS {
            let mut p = vec![0.0; (res * res) as usize];
            p[row * res as usize + col] = d;
            let e = check(res, sigma, &p, "single");
            // Also against the closed form directly.
            let c = f64::from(c_of(sigma) as f32);
            for (k, &v) in e.iter().enumerate() {
                let (dy, dx) = ((k / res as usize) as f64 - row as f64, (k % res as usize) as f64 - col as f64);
                let g = f64::from(d) * (-c * (dx * dx + dy * dy)).exp();
                assert!((f64::from(v) - g).abs() <= 1e-5 * f64::from(d), "Gaussian off at {k}: {v} vs {g}");
            }
        }
    }
}

#[test]
fn ties_and_equal_distances() {
    let res = 15u32;
    let n = res as usize;
    for sigma in [0.4, 1.0, 2.5, 50.0] {
        // Plateau of equal heights.
        let mut p = vec![0.0; n * n];
        for r in 4..9 {
            for c in 3..12 {
                p[r * n + c] = 0.7;
            }
        }
        check(res, sigma, &p, "plateau");
        // Two equal sources an even distance apart: the midpoint cell is equidistant.
        let mut p = vec![0.0; n * n];
        p[7 * n + 3] = 0.5;
        p[7 * n + 11] = 0.5;
        check(res, sigma, &p, "pair");
        // Four equal sources at the corners of a square, and its centre equidistant.
        let mut p = vec![0.0; n * n];
        for (r, c) in [(2, 2), (2, 12), (12, 2), (12, 12)] {
            p[r * n + c] = 1.0;
        }
        check(res, sigma, &p, "square");
        // Unequal heights placed so that breakpoints land exactly on cells.
        let mut p = vec![0.0; n * n];
        p[7 * n + 4] = 1.0;
        p[7 * n + 10] = (-(c_of(sigma) * 12.0)).exp() as f32;
        p[3 * n + 7] = 0.25;
        check(res, sigma, &p, "breakpoints on cells");
        // Checkerboard of two heights.
        let p: Vec<f32> = (0..n * n).map(|k| if (k / n + k % n).is_multiple_of(2) { 1.0 } else { 0.5 }).collect();
        check(res, sigma, &p, "checkerboard");
    }
}

#[test]
fn sources_on_the_border() {
    let mut rng = SplitMix64::new(4);
    for res in [2u32, 3, 16, 41] {
        let n = res as usize;
        for sigma in SIGMAS {
            let p: Vec<f32> = (0..n * n)
                .map(|k| {
                    let (r, c) = (k / n, k % n);
                    let border = r == 0 || c == 0 || r == n - 1 || c == n - 1;
                    if border && rng.next_f32() < 0.5 { rng.range_f32(0.1, 1.0) } else { 0.0 }
                })
                .collect();
            check(res, sigma, &p, "border");
        }
    }
}

#[test]
fn spherical_cap_profile() {
    // What the Z-buffer gives for a sphere of radius R: P = max(0, d − (R − sqrt(R² − r²))), in
    // world units with a 64² grid of cell side h.
    let res = 64u32;
    let n = res as usize;
    let (radius, d, h) = (1.0f64, 0.25f64, 2.0 / 64.0);
    let p: Vec<f32> = (0..n * n)
        .map(|k| {
            let x = ((k % n) as f64 + 0.5 - 32.0) * h;
            let y = ((k / n) as f64 + 0.5 - 32.0) * h;
            let r2 = x * x + y * y;
            if r2 >= radius * radius {
                return 0.0;
            }
            (d - (radius - (radius * radius - r2).sqrt())).max(0.0) as f32
        })
        .collect();
    for sigma_world in [0.02, 0.1, 0.3, 1.0] {
        check(res, sigma_world / h, &p, "cap");
    }
}

#[test]
fn brute_force_is_the_plain_formula() {
    // The oracle itself, on a tiny grid, against a literal transcription of the definition.
    let mut rng = SplitMix64::new(5);
    let res = 6u32;
    let n = res as usize;
    let p = random_profile(&mut rng, res, 0.6, 1.0);
    let c = 0.3f64;
    let e = envelope_brute(res, c, &p);
    for (x, &got) in e.iter().enumerate() {
        let mut want = 0.0f64;
        for (k, &pk) in p.iter().enumerate() {
            let dx = (x % n) as f64 - (k % n) as f64;
            let dy = (x / n) as f64 - (k / n) as f64;
            want = want.max(f64::from(pk) * (-c * (dx * dx + dy * dy)).exp());
        }
        assert!((got - want).abs() <= 1e-14 * want.max(1e-300), "cell {x}: {got} vs {want}");
    }
}
