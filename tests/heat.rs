//! Guards the heat smoothing of the envelope (ARCHITECTURE.md §4 "Smoothing"): the 5-point step with
//! a zero border, its increase-only variant, and `heat` = k₁ plain steps, rescale to the dent
//! distance, k₂ clamped steps.

mod common;

use common::SplitMix64;
use dentbend::cpu::{HeatParams, heat, heat_step};

fn params(res: u32, rate: f32, clamped: u32) -> HeatParams {
    HeatParams { res, rate, clamped, cell_offset: 0 }
}

fn step(res: u32, rate: f32, clamped: u32, src: &[f32]) -> Vec<f32> {
    let mut dst = vec![f32::NAN; src.len()];
    heat_step(&params(res, rate, clamped), src, &mut dst);
    dst
}

fn random_grid(rng: &mut SplitMix64, res: u32) -> Vec<f32> {
    (0..res * res).map(|_| rng.range_f32(0.0, 1.0)).collect()
}

/// Images of cell (r, c) under the 8 symmetries of the square.
fn dihedral(n: usize, r: usize, c: usize) -> [(usize, usize); 8] {
    let (rr, rc) = (n - 1 - r, n - 1 - c);
    [(r, c), (c, rr), (rr, rc), (rc, r), (r, rc), (rr, c), (c, r), (rc, rr)]
}

/// Asserts that `g` is invariant, bit for bit, under the 8 symmetries of the square.
#[track_caller]
fn assert_square_symmetric(n: usize, g: &[f32], what: &str) {
    for r in 0..n {
        for c in 0..n {
            for (r2, c2) in dihedral(n, r, c) {
                assert_eq!(
                    g[r * n + c].to_bits(),
                    g[r2 * n + c2].to_bits(),
                    "{what}: ({r}, {c}) = {} but ({r2}, {c2}) = {}",
                    g[r * n + c],
                    g[r2 * n + c2]
                );
            }
        }
    }
}

#[test]
fn step_matches_a_per_cell_transcription() {
    // Independent f64 transcription of dst = src + α·Δsrc with zero outside the grid. The kernel
    // sums in f32 in another order: 1e-6 of the grid's range covers that rounding, while a wrong
    // neighbour, border or sign is off by ~α·(value) ≳ 1e-2.
    let mut rng = SplitMix64::new(11);
    for res in [1u32, 2, 3, 7, 32] {
        let n = res as usize;
        let src = random_grid(&mut rng, res);
        for rate in [0.05f32, 0.2, 0.25] {
            for clamped in [0, 1] {
                let got = step(res, rate, clamped, &src);
                let at = |r: isize, c: isize| {
                    if r < 0 || c < 0 || r >= n as isize || c >= n as isize {
                        0.0
                    } else {
                        f64::from(src[r as usize * n + c as usize])
                    }
                };
                for r in 0..n as isize {
                    for c in 0..n as isize {
                        let s = at(r, c);
                        let lap = at(r - 1, c) + at(r + 1, c) + at(r, c - 1) + at(r, c + 1) - 4.0 * s;
                        let mut want = s + f64::from(rate) * lap;
                        if clamped == 1 {
                            want = want.max(s);
                        }
                        let k = r as usize * n + c as usize;
                        assert!(
                            (f64::from(got[k]) - want).abs() <= 1e-6,
                            "res {res} α {rate} clamped {clamped} cell ({r}, {c}): {} vs {want}",
                            got[k]
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn clamped_step_never_lowers_a_cell() {
    let mut rng = SplitMix64::new(12);
    for res in [1u32, 2, 5, 33, 64] {
        for rate in [0.01f32, 0.1, 0.25] {
            let mut src = random_grid(&mut rng, res);
            // Some isolated spikes and zeros, where the plain step would lower or raise most.
            for _ in 0..res {
                let k = rng.below(u64::from(res * res)) as usize;
                src[k] = if rng.next_f32() < 0.5 { 10.0 } else { 0.0 };
            }
            for _ in 0..4 {
                let dst = step(res, rate, 1, &src);
                for (k, (&d, &s)) in dst.iter().zip(&src).enumerate() {
                    assert!(d >= s, "res {res} α {rate}: cell {k} lowered from {s} to {d}");
                }
                src = dst;
            }
        }
    }
}

#[test]
fn spike_spreads_with_exact_square_symmetry() {
    for res in [1u32, 3, 9, 16] {
        let n = res as usize;
        let rate = 0.2f32;
        let mut g = vec![0.0f32; n * n];
        // A centred spike: the centre cell for odd sizes, the central 2×2 block for even ones.
        let (lo, hi) = ((n - 1) / 2, n / 2);
        for r in lo..=hi {
            for c in lo..=hi {
                g[r * n + c] = 1.0;
            }
        }
        let first = step(res, rate, 0, &g);
        if n == 9 {
            // One step from a unit spike: 1 − 4α at the centre, α at its 4 neighbours.
            assert!((first[4 * n + 4] - (1.0 - 4.0 * rate)).abs() <= 1e-7);
            for k in [3 * n + 4, 5 * n + 4, 4 * n + 3, 4 * n + 5] {
                assert!((first[k] - rate).abs() <= 1e-7, "neighbour {k}: {}", first[k]);
            }
            assert!(first.iter().filter(|&&v| v != 0.0).count() == 5);
        }
        for clamped in [0, 1] {
            let mut g = g.clone();
            for s in 0..12 {
                g = step(res, rate, clamped, &g);
                assert_square_symmetric(n, &g, &format!("res {res} clamped {clamped} step {s}"));
            }
        }
    }
}

#[test]
fn heat_keeps_square_symmetric_input_symmetric() {
    let mut rng = SplitMix64::new(13);
    for res in [2u32, 5, 8, 31] {
        let n = res as usize;
        // Random values made invariant by giving each orbit of the square's symmetries one value.
        let mut g = vec![f32::NAN; n * n];
        for r in 0..n {
            for c in 0..n {
                if g[r * n + c].is_nan() {
                    let v = rng.range_f32(0.0, 2.0);
                    for (r2, c2) in dihedral(n, r, c) {
                        g[r2 * n + c2] = v;
                    }
                }
            }
        }
        assert_square_symmetric(n, &g, "input");
        heat(&mut g, res, 0.2, 8, 16, 0.3);
        assert_square_symmetric(n, &g, &format!("res {res} after heat"));
    }
}

#[test]
fn all_zero_grid_stays_zero() {
    for res in [1u32, 4, 17] {
        for (k1, k2) in [(0, 0), (8, 16), (3, 0), (0, 5)] {
            let mut g = vec![0.0f32; (res * res) as usize];
            heat(&mut g, res, 0.25, k1, k2, 0.2);
            assert!(g.iter().all(|&v| v == 0.0), "res {res} k₁ {k1} k₂ {k2}: {g:?}");
        }
    }
}

#[test]
fn heat_rescales_the_peak_to_the_dent_distance() {
    // Relative 1e-6: the rescale is one multiplication (½ ulp), and a clamped step cannot push a
    // cell above the peak for α ≤ ¼ except by rounding (a few ulps).
    let mut rng = SplitMix64::new(14);
    for res in [1u32, 2, 3, 16, 50] {
        for (k1, k2) in [(0, 0), (1, 0), (8, 16), (3, 7), (0, 4)] {
            for d in [1e-3f32, 0.25, 40.0] {
                let n = (res * res) as usize;
                let mut inputs = vec![random_grid(&mut rng, res)];
                let mut spike = vec![0.0; n];
                spike[rng.below(n as u64) as usize] = 3.0;
                inputs.push(spike);
                for mut g in inputs {
                    heat(&mut g, res, 0.2, k1, k2, d);
                    let peak = g.iter().fold(0.0f32, |m, &v| m.max(v));
                    assert!((peak - d).abs() <= 1e-6 * d, "res {res} k₁ {k1} k₂ {k2} d {d}: peak {peak}");
                }
            }
        }
    }
}

#[test]
fn heat_is_plain_steps_rescale_then_clamped_steps() {
    // The ping-pong between `values` and the scratch must hand back the last step's grid for
    // every parity of k₁ and k₂: compare bit for bit with the steps done one at a time.
    let mut rng = SplitMix64::new(15);
    let res = 12u32;
    let (rate, d) = (0.15f32, 0.7f32);
    for k1 in 0..4 {
        for k2 in 0..4 {
            let input = random_grid(&mut rng, res);
            let mut want = input.clone();
            for _ in 0..k1 {
                want = step(res, rate, 0, &want);
            }
            let peak = want.iter().fold(0.0f32, |m, &v| m.max(v));
            let scale = d / peak;
            want.iter_mut().for_each(|v| *v *= scale);
            for _ in 0..k2 {
                want = step(res, rate, 1, &want);
            }
            let mut got = input;
            heat(&mut got, res, rate, k1, k2, d);
            assert!(
                got.iter().zip(&want).all(|(a, b)| a.to_bits() == b.to_bits()),
                "k₁ {k1} k₂ {k2}: heat differs from its steps"
            );
        }
    }
}
