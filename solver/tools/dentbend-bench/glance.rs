//! `dentbend-bench glance`: per-dent wall times of head-on dents next to steep glancing ones
//! (θ uniform in [`STEEP_MIN_DEG`]..=[`STEEP_MAX_DEG`]) on one target, in the same run and
//! interleaved, through the same damage API and the same hits as `soak` (a ball of
//! [`PROJECTILE_FRACTION`] of the diagonal, a dent distance of [`DENT_FRACTION`] of it times
//! cos θ, at seeded random points of the current surface).

use dentbend::damage::CpuBackend;
use dentbend::glam::Vec3;
use dentbend::mesh;
use serde::Serialize;

use crate::soak::{DENT_FRACTION, PROJECTILE_FRACTION, nearest_rank};
use crate::soak_target::{HitSizes, SPEED, SoakBackend, SoakTarget};
use crate::surface_sample::{Rng, sample_surface};

/// Smallest angle of a steep dent, degrees.
pub const STEEP_MIN_DEG: f32 = 60.0;
/// Largest angle of a steep dent, degrees (the default `min_cos` = 0.1 clamps at 84.3°).
pub const STEEP_MAX_DEG: f32 = 84.0;

/// Wall times of one group of dents, ms.
#[derive(Debug, Clone, Serialize)]
pub struct Group {
    /// Dents in the group.
    pub dents: usize,
    /// Dents the API refused (the target is unchanged then).
    pub errors: usize,
    /// Median, ms.
    pub median_ms: f64,
    /// 99th percentile (nearest rank), ms.
    pub p99_ms: f64,
    /// Slowest, ms.
    pub max_ms: f64,
    /// Vertices moved, mean per dent.
    pub moved_vertices_mean: f64,
}

/// The report; the keys are the interface.
#[derive(Debug, Serialize)]
pub struct Report {
    /// The target's spec (built-in name or path).
    pub target: String,
    /// Seed of the hit sequence.
    pub seed: u64,
    /// Rayon threads the dents could use.
    pub threads: usize,
    /// θ = 0.
    pub head_on: Group,
    /// θ uniform in [60°, 84°].
    pub steep: Group,
    /// steep.p99_ms / head_on.median_ms.
    pub steep_p99_over_head_on_median: f64,
    /// steep.p99_ms / head_on.p99_ms.
    pub steep_p99_over_head_on_p99: f64,
}

/// Dents `target` `dents` times per group, alternating head-on and steep hits.
pub fn run(target: &str, dents: usize, seed: u64) -> Result<Report, String> {
    if !(1..=1_000_000).contains(&dents) {
        return Err(format!("--dents {dents} is outside 1..=1000000"));
    }
    let mesh = mesh::load(target).map_err(|e| e.to_string())?;
    let (lo, hi) = mesh.bounds();
    let diagonal = (hi - lo).length();
    let sizes = HitSizes {
        radius: PROJECTILE_FRACTION * diagonal,
        dent_distance: DENT_FRACTION * diagonal,
        draw_radius: false,
        draw_distance: false,
    };
    let mut body = SoakTarget::new(mesh, sizes, 0.0, SoakBackend::Cpu(CpuBackend))?;
    let mut rng = Rng::new(seed);
    let mut samples: [Vec<(f64, Option<usize>)>; 2] = [Vec::with_capacity(dents), Vec::with_capacity(dents)];
    for k in 0..2 * dents {
        let steep = k % 2 == 1;
        let at = sample_surface(body.mesh(), &mut rng).ok_or("the target's surface has no area left")?;
        let theta = if steep {
            (STEEP_MIN_DEG + (STEEP_MAX_DEG - STEEP_MIN_DEG) * rng.unit() as f32).to_radians()
        } else {
            0.0
        };
        let phi = std::f32::consts::TAU * rng.unit() as f32;
        let inward = -at.normal;
        let (x, y) = inward.any_orthonormal_pair();
        let direction: Vec3 = inward * theta.cos() + (x * phi.cos() + y * phi.sin()) * theta.sin();
        let outcome = body.hit_at(at, SPEED * direction.normalize(), k as u64);
        let moved = outcome.result.ok().map(|(_, moved)| moved);
        samples[usize::from(steep)].push((outcome.elapsed.as_secs_f64() * 1e3, moved));
    }
    let [head_on, steep] = samples.map(|s| group(&s));
    Ok(Report {
        target: target.to_owned(),
        seed,
        threads: rayon::current_num_threads(),
        steep_p99_over_head_on_median: steep.p99_ms / head_on.median_ms,
        steep_p99_over_head_on_p99: steep.p99_ms / head_on.p99_ms,
        head_on,
        steep,
    })
}

fn group(samples: &[(f64, Option<usize>)]) -> Group {
    let mut times: Vec<f64> = samples.iter().map(|s| s.0).collect();
    times.sort_by(f64::total_cmp);
    let moved: usize = samples.iter().filter_map(|s| s.1).sum();
    Group {
        dents: samples.len(),
        errors: samples.iter().filter(|s| s.1.is_none()).count(),
        median_ms: nearest_rank(&times, 0.5),
        p99_ms: nearest_rank(&times, 0.99),
        max_ms: times[times.len() - 1],
        moved_vertices_mean: moved as f64 / samples.len() as f64,
    }
}

/// The report as a few lines of text.
pub fn render(r: &Report) -> String {
    let line = |name: &str, g: &Group| {
        format!(
            "  {name}: {} dents ({} errors), median {:.3} ms, p99 {:.3} ms, max {:.3} ms, {:.0} vertices moved\n",
            g.dents, g.errors, g.median_ms, g.p99_ms, g.max_ms, g.moved_vertices_mean
        )
    };
    format!(
        "glance {} (seed {}, {} threads):\n{}{}  steep p99 / head-on median = {:.2}, steep p99 / head-on p99 = {:.2}\n",
        r.target,
        r.seed,
        r.threads,
        line("head-on      θ = 0     ", &r.head_on),
        line(&format!("steep θ {STEEP_MIN_DEG}–{STEEP_MAX_DEG}°"), &r.steep),
        r.steep_p99_over_head_on_median,
        r.steep_p99_over_head_on_p99,
    )
}
