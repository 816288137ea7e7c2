//! Step-time statistics: exact over a slice of steps ([`StepStats::of`]), or accumulated one
//! step at a time in constant memory ([`StepStatsStream`]) for runs of any length.

use serde::Serialize;

use super::StepTiming;

/// Step-time statistics of a run (or part of one), ms.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct StepStats {
    /// Steps summarized.
    pub steps: usize,
    /// Mean dynamics time per step (broad phase, contacts, impulses), ms.
    pub dynamics_mean: f64,
    /// Mean denting time per step (dent batch, collider refits), ms.
    pub denting_mean: f64,
    /// Mean skinning time per step (0 without skinning every step), ms.
    pub skinning_mean: f64,
    /// Mean of the three, ms.
    pub total_mean: f64,
    /// Median dynamics time, ms.
    pub dynamics_median: f64,
    /// Median denting time, ms.
    pub denting_median: f64,
    /// Median skinning time, ms.
    pub skinning_median: f64,
    /// Median of the three, ms.
    pub total_median: f64,
    /// Mean dents per step.
    pub dents_per_step_mean: f64,
    /// Denting time per dent (the batched pipeline's per-dent cost), ms; 0 without dents.
    pub denting_per_dent: f64,
}

impl StepStats {
    /// Means and exact medians of `steps` (all zero for none); the upper middle value for an
    /// even count.
    pub fn of(steps: &[StepTiming]) -> Self {
        let n = steps.len().max(1) as f64;
        let sum = |f: fn(&StepTiming) -> f64| steps.iter().map(f).sum::<f64>();
        let median = |f: fn(&StepTiming) -> f64| {
            let mut values: Vec<f64> = steps.iter().map(f).collect();
            values.sort_by(f64::total_cmp);
            values.get(values.len() / 2).copied().unwrap_or(0.0)
        };
        let dents = sum(|t| t.dents as f64);
        Self {
            steps: steps.len(),
            dynamics_mean: sum(|t| t.dynamics_ms) / n,
            denting_mean: sum(|t| t.denting_ms) / n,
            skinning_mean: sum(|t| t.skinning_ms) / n,
            total_mean: sum(StepTiming::total_ms) / n,
            dynamics_median: median(|t| t.dynamics_ms),
            denting_median: median(|t| t.denting_ms),
            skinning_median: median(|t| t.skinning_ms),
            total_median: median(StepTiming::total_ms),
            dents_per_step_mean: dents / n,
            denting_per_dent: if dents > 0.0 { sum(|t| t.denting_ms) / dents } else { 0.0 },
        }
    }
}

/// [`StepStats`] accumulated one step at a time in constant memory (about 180 KB), for runs of
/// any length: sums are exact; medians come from logarithmic histograms whose bins are 0.5 %
/// wide, so each median is within 0.25 % of the exact one (values between 1 ns and 10⁶ ms; a
/// zero time has its own bin, values outside the range land in the end bins).
#[derive(Debug, Clone)]
pub struct StepStatsStream {
    steps: usize,
    dynamics: Series,
    denting: Series,
    skinning: Series,
    total: Series,
    dents: f64,
}

impl Default for StepStatsStream {
    fn default() -> Self {
        Self {
            steps: 0,
            dynamics: Series::new(),
            denting: Series::new(),
            skinning: Series::new(),
            total: Series::new(),
            dents: 0.0,
        }
    }
}

impl StepStatsStream {
    /// Adds one step.
    pub fn push(&mut self, timing: &StepTiming) {
        self.steps += 1;
        self.dynamics.push(timing.dynamics_ms);
        self.denting.push(timing.denting_ms);
        self.skinning.push(timing.skinning_ms);
        self.total.push(timing.total_ms());
        self.dents += timing.dents as f64;
    }

    /// The statistics of every step pushed so far (all zero for none).
    pub fn stats(&self) -> StepStats {
        let n = self.steps.max(1) as f64;
        StepStats {
            steps: self.steps,
            dynamics_mean: self.dynamics.sum / n,
            denting_mean: self.denting.sum / n,
            skinning_mean: self.skinning.sum / n,
            total_mean: self.total.sum / n,
            dynamics_median: self.dynamics.median(),
            denting_median: self.denting.median(),
            skinning_median: self.skinning.median(),
            total_median: self.total.median(),
            dents_per_step_mean: self.dents / n,
            denting_per_dent: if self.dents > 0.0 { self.denting.sum / self.dents } else { 0.0 },
        }
    }
}

/// Smallest positive time with its own bin, ms (1 ns).
const LOWEST_MS: f64 = 1e-6;
/// Ratio between the edges of neighbouring bins.
const BIN_RATIO: f64 = 1.005;
/// Bins from [`LOWEST_MS`] up to 10⁶ ms.
const BINS: usize = 5_541; // ⌈ln(10¹²) / ln(1.005)⌉

/// The sum and a logarithmic histogram of one timing series.
#[derive(Debug, Clone)]
struct Series {
    sum: f64,
    zeros: u64,
    bins: Vec<u64>,
}

impl Series {
    fn new() -> Self {
        Self { sum: 0.0, zeros: 0, bins: vec![0; BINS] }
    }

    fn push(&mut self, ms: f64) {
        self.sum += ms;
        if ms > 0.0 {
            let bin = ((ms / LOWEST_MS).ln() / BIN_RATIO.ln()).floor().clamp(0.0, (BINS - 1) as f64);
            self.bins[bin as usize] += 1;
        } else {
            // Zero (a step without skinning or dents); negative or NaN cannot come from a clock.
            self.zeros += 1;
        }
    }

    /// The value at rank `count / 2` (as [`StepStats::of`]): the geometric centre of its bin.
    fn median(&self) -> f64 {
        let count = self.zeros + self.bins.iter().sum::<u64>();
        if count == 0 {
            return 0.0;
        }
        let mut below = count / 2 + 1; // values up to and including the median
        if below <= self.zeros {
            return 0.0;
        }
        below -= self.zeros;
        let mut bin = 0;
        for (k, &n) in self.bins.iter().enumerate() {
            if below <= n {
                bin = k;
                break;
            }
            below -= n;
        }
        LOWEST_MS * BIN_RATIO.powf(bin as f64 + 0.5)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn timing(step: u64, dynamics_ms: f64, denting_ms: f64, dents: usize) -> StepTiming {
        StepTiming { step, dynamics_ms, denting_ms, skinning_ms: 0.0, events: 0, dents, fractures: 0 }
    }

    #[test]
    fn the_stream_matches_the_exact_statistics() {
        // Times spread over five decades, as a run's first heavy steps and quiet tail are.
        let steps: Vec<StepTiming> = (0..10_001u64)
            .map(|k| {
                let x = (k * 7919 % 10_001) as f64 / 10_001.0;
                timing(k + 1, 0.01 * 10f64.powf(5.0 * x), if k % 3 == 0 { 0.0 } else { 2.0 + x }, (k % 3 != 0) as usize)
            })
            .collect();
        let exact = StepStats::of(&steps);
        let mut stream = StepStatsStream::default();
        steps.iter().for_each(|t| stream.push(t));
        let streamed = stream.stats();
        assert_eq!(streamed.steps, exact.steps);
        // Sums are exact up to the order of f64 additions.
        for (a, b) in [
            (streamed.dynamics_mean, exact.dynamics_mean),
            (streamed.denting_mean, exact.denting_mean),
            (streamed.total_mean, exact.total_mean),
            (streamed.denting_per_dent, exact.denting_per_dent),
            (streamed.dents_per_step_mean, exact.dents_per_step_mean),
        ] {
            assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} vs {b}");
        }
        // Medians: within half a bin, 0.25 %.
        for (a, b) in [
            (streamed.dynamics_median, exact.dynamics_median),
            (streamed.denting_median, exact.denting_median),
            (streamed.total_median, exact.total_median),
        ] {
            assert!((a / b - 1.0).abs() <= 0.0025, "median {a} vs {b}");
        }
        assert_eq!(streamed.skinning_median, 0.0);
    }

    #[test]
    fn no_steps_give_zeros() {
        assert_eq!(StepStatsStream::default().stats(), StepStats::default());
    }
}
