//! Repeats a closure and reports the median wall time.

use std::time::{Duration, Instant};

/// Median seconds of `f` over at least `min_reps` runs and at least `min_total` of wall time
/// (capped at 10 000 runs), after one untimed warm-up run.
pub fn median_seconds(min_reps: usize, min_total: Duration, mut f: impl FnMut()) -> f64 {
    f();
    let mut samples = Vec::new();
    let start = Instant::now();
    while samples.len() < min_reps || (start.elapsed() < min_total && samples.len() < 10_000) {
        let t = Instant::now();
        f();
        samples.push(t.elapsed().as_secs_f64());
    }
    samples.sort_by(f64::total_cmp);
    samples[samples.len() / 2]
}
