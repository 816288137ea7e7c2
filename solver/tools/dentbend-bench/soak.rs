//! `dentbend-bench soak`: dents one target thousands of times at seeded random points of its
//! surface through the world-free damage API (`Damage::plan` on the CPU or the GPU backend, then
//! `TargetSet::apply`, as an engine would; see [`SoakTarget`]), and reports failures, per-dent
//! wall times, how the mesh wears (triangle quality, volume, faces turned over) and whether
//! memory grows.
//!
//! Each dent: a point drawn uniformly by area over the target's current (dented) surface and
//! the interpolated vertex normal there; the built-in sphere scaled to a radius of
//! [`PROJECTILE_FRACTION`] of the target's bounding-box diagonal (or, with a projectile scale
//! F, drawn uniformly from (0, F·size], size the bounding box's largest side), touching the
//! surface at that point; a velocity inside a cone of half-angle [`CONE_DEG`] (or the one asked
//! for) about the inward normal; a dent distance of [`DENT_FRACTION`] of the diagonal (or, with
//! a depth F, drawn uniformly from (0, F·thickness], thickness the bounding box's smallest side)
//! times the cosine of the incidence (threshold 0, gain and cap chosen so a head-on hit gets the
//! full distance). Sizes are those of the undented target.

use std::time::Instant;

use dentbend::glam::Vec3;
use dentbend::{TriMesh, mesh};
use serde::Serialize;

use crate::memory::{peak_resident_mb, resident_mb};
use crate::soak_target::{HitSizes, SoakBackend, SoakTarget};
use crate::surface_sample::Rng;
use crate::triangle_quality::{QualityStats, quality_stats};

/// Projectile radius as a fraction of the target's bounding-box diagonal.
pub const PROJECTILE_FRACTION: f32 = 0.03;
/// Head-on dent distance as a fraction of the target's bounding-box diagonal.
pub const DENT_FRACTION: f32 = 0.003;
/// Half-angle of the cone of incidence about the inward normal, degrees.
pub const CONE_DEG: f32 = 30.0;
/// Dents in each of the two windows (first and last) whose peak memory is compared.
pub const MEMORY_WINDOW: usize = 1000;
/// Most dents one run takes: each dent's time is kept (8 bytes) for the percentiles.
pub const MAX_DENTS: usize = 10_000_000;
/// Dents in each of the two windows (first and last) whose median times are compared.
pub const TIME_WINDOW: usize = 100;
/// Largest projectile scale and depth fraction accepted.
pub const MAX_FRACTION: f32 = 10.0;
/// Largest cone half-angle accepted, degrees (a hit along the surface makes no dent).
pub const MAX_CONE_DEG: f32 = 89.0;

/// What a soak run does.
#[derive(Debug, Clone)]
pub struct Options {
    /// Built-in mesh name or mesh path.
    pub target: String,
    /// Dents to make.
    pub dents: usize,
    /// Seed of the hit sequence.
    pub seed: u64,
    /// Projectile radius drawn up to this times the target's size (largest bounding-box side);
    /// `None`: every ball [`PROJECTILE_FRACTION`] of the diagonal.
    pub projectile_scale: Option<f32>,
    /// Head-on dent distance drawn up to this times the target's thickness (smallest
    /// bounding-box side); `None`: every dent [`DENT_FRACTION`] of the diagonal.
    pub depth: Option<f32>,
    /// Half-angle of the cone of incidence, degrees.
    pub cone_deg: f32,
    /// `cpu` or `gpu`.
    pub backend: String,
}

impl Options {
    /// The defaults of the command line for `target`, `dents` and `seed`.
    pub fn new(target: &str, dents: usize, seed: u64) -> Self {
        Self {
            target: target.to_owned(),
            dents,
            seed,
            projectile_scale: None,
            depth: None,
            cone_deg: CONE_DEG,
            backend: "cpu".to_owned(),
        }
    }

    fn check(&self) -> Result<(), String> {
        if !(1..=MAX_DENTS).contains(&self.dents) {
            return Err(format!("--dents {} is outside 1..={MAX_DENTS}", self.dents));
        }
        for (flag, value) in [("--projectile-scale", self.projectile_scale), ("--depth", self.depth)] {
            if let Some(v) = value.filter(|v| !(*v > 0.0 && *v <= MAX_FRACTION)) {
                return Err(format!("{flag} {v} is outside (0, {MAX_FRACTION}]"));
            }
        }
        if !(0.0..=MAX_CONE_DEG).contains(&self.cone_deg) {
            return Err(format!("--cone-deg {} is outside 0..={MAX_CONE_DEG}", self.cone_deg));
        }
        Ok(())
    }
}

/// A value at the start of the run and at its end.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct FirstLast<T> {
    /// Before the first dent (memory: the peak over the first [`MEMORY_WINDOW`] dents).
    pub first: T,
    /// After the last dent (memory: the peak over the last [`MEMORY_WINDOW`] dents).
    pub last: T,
}

/// The mesh's state every tenth of the run.
#[derive(Debug, Clone, Serialize)]
pub struct Checkpoint {
    /// Dents done so far.
    pub dents: usize,
    /// Triangles of the dented mesh now (refinement adds them).
    pub triangles: usize,
    /// Worst triangle quality (see `triangle_quality`).
    pub min_triangle_quality: f64,
    /// Mean triangle quality.
    pub mean_triangle_quality: f64,
    /// Enclosed volume, cubic world units.
    pub volume: f32,
    /// Resident memory now, MiB (`null` off Linux).
    pub rss_mb: Option<f64>,
}

/// The soak's report; the keys are the interface.
#[derive(Debug, Serialize)]
pub struct Report {
    /// The target's spec (built-in name or path).
    pub target: String,
    /// Its vertices.
    pub vertices: usize,
    /// Its triangles.
    pub triangles: usize,
    /// Seed of the hit sequence.
    pub seed: u64,
    /// Where the dents ran: `cpu` or `gpu`.
    pub backend: String,
    /// Dents attempted.
    pub dents: usize,
    /// Dents that changed the surface.
    pub dented: usize,
    /// Dents the API returned `Err` for (the target is unchanged then).
    pub errors: usize,
    /// The first few errors' messages.
    pub error_messages: Vec<String>,
    /// Dents after which some vertex position or normal was not finite.
    pub non_finite: usize,
    /// Median wall time of one dent (plan and apply), ms.
    pub median_ms: f64,
    /// 99th percentile (nearest rank), ms.
    pub p99_ms: f64,
    /// Median wall time of the first [`TIME_WINDOW`] dents (all of them in a shorter run), ms.
    pub median_first_ms: f64,
    /// Median wall time of the last [`TIME_WINDOW`] dents (all of them in a shorter run), ms.
    pub median_last_ms: f64,
    /// Slowest dent, ms.
    pub max_ms: f64,
    /// Mean, ms.
    pub mean_ms: f64,
    /// Wall time of the whole run, sampling and checks included, s.
    pub total_s: f64,
    /// Rayon threads the dents could use.
    pub threads: usize,
    /// Projectile radius, world units: every ball's, or with a projectile scale the largest
    /// drawn from.
    pub projectile_radius: f32,
    /// Head-on dent distance, world units: every dent's, or with a depth the largest drawn from.
    pub dent_distance: f32,
    /// The target's size: its bounding box's largest side, world units (before any dent).
    pub target_size: f32,
    /// The target's thickness: its bounding box's smallest side, world units (before any dent).
    pub target_thickness: f32,
    /// Radius drawn uniformly from (0, projectile_scale·target_size] (`null`: fixed radius).
    pub projectile_scale: Option<f32>,
    /// Head-on dent distance drawn uniformly from (0, depth·target_thickness] (`null`: fixed).
    pub depth: Option<f32>,
    /// Half-angle of the cone of incidence, degrees.
    pub cone_deg: f32,
    /// Vertices moved, mean per dent.
    pub moved_vertices_mean: f64,
    /// Median vertices moved per dent over the first and the last [`TIME_WINDOW`] dents (a
    /// failed dent counts 0): how much work each dent had, beside `median_first_ms` and
    /// `median_last_ms`.
    pub moved_vertices_median: FirstLast<f64>,
    /// Faces turned over by the dents, summed over the run: the normal reversed beyond
    /// `dentbend::mesh::SHAPE_TOLERANCE` (`mesh::turned_over_faces`; refined faces compared with
    /// where refinement made them).
    pub flipped_faces: usize,
    /// Worst triangle quality q = 4√3·area / (sum of squared edge lengths), 1 = equilateral.
    pub min_triangle_quality: FirstLast<f64>,
    /// Mean triangle quality.
    pub mean_triangle_quality: FirstLast<f64>,
    /// Enclosed volume, cubic world units.
    pub volume: FirstLast<f32>,
    /// (last − first) / first volume.
    pub volume_change: f64,
    /// Peak resident memory over the first and the last [`MEMORY_WINDOW`] dents, MiB (sampled
    /// after every dent; `null` off Linux).
    pub peak_rss_mb: Option<FirstLast<f64>>,
    /// The process's high-water mark of resident memory at the end, MiB (`null` off Linux).
    pub peak_rss_hwm_mb: Option<f64>,
    /// The mesh every tenth of the run.
    pub checkpoints: Vec<Checkpoint>,
}

/// Running maxima of resident memory over the first and the last window of dents.
struct MemoryWindows {
    dents: usize,
    first: Option<f64>,
    last: Option<f64>,
}

impl MemoryWindows {
    fn record(&mut self, dent: usize, mb: Option<f64>) {
        let window = MEMORY_WINDOW.min(self.dents);
        if dent < window {
            self.first = max_of(self.first, mb);
        }
        if dent >= self.dents - window {
            self.last = max_of(self.last, mb);
        }
    }
}

fn max_of(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.max(b)),
        (a, b) => a.or(b),
    }
}

/// Dents `options.target` `options.dents` times with hits drawn from `options.seed`.
pub fn run(options: &Options) -> Result<Report, String> {
    options.check()?;
    let Options { target, dents, seed, .. } = options.clone();
    let (target, dents) = (target.as_str(), dents);
    let started = Instant::now();
    let mesh = mesh::load(target).map_err(|e| e.to_string())?;
    let (lo, hi) = mesh.bounds();
    let diagonal = (hi - lo).length();
    let (target_size, target_thickness) = ((hi - lo).max_element(), (hi - lo).min_element());
    let sizes = HitSizes {
        radius: options.projectile_scale.map_or(PROJECTILE_FRACTION * diagonal, |f| f * target_size),
        dent_distance: options.depth.map_or(DENT_FRACTION * diagonal, |f| f * target_thickness),
        draw_radius: options.projectile_scale.is_some(),
        draw_distance: options.depth.is_some(),
    };
    if !(sizes.radius > 0.0 && sizes.dent_distance > 0.0) {
        return Err(format!("the target {target} is flat: no projectile size or depth can be drawn from it"));
    }
    let (vertices, triangles) = (mesh.vertex_count(), mesh.face_count());
    let quality_first = quality_stats(&mesh);
    let volume_first = mesh.volume();
    let backend = SoakBackend::parse(&options.backend)?;
    let backend_name = backend.name().to_owned();
    let mut target_body = SoakTarget::new(mesh, sizes, options.cone_deg.to_radians(), backend)?;

    let mut rng = Rng::new(seed);
    // Every page of the times written now, so that filling them in does not read as growth in
    // the memory windows.
    let mut times_ms = vec![f64::NAN; dents];
    let mut moved_counts = vec![0.0f64; dents];
    let (mut dented, mut errors, mut non_finite, mut moved_total, mut flipped) = (0, 0, 0, 0usize, 0);
    let mut error_messages = Vec::new();
    let mut memory = MemoryWindows { dents, first: None, last: None };
    let mut checkpoints = Vec::new();
    let checkpoint_every = (dents / 10).max(1);
    for (k, (time_ms, moved_count)) in times_ms.iter_mut().zip(&mut moved_counts).enumerate() {
        let outcome = target_body.hit(&mut rng, k as u64)?;
        *time_ms = outcome.elapsed.as_secs_f64() * 1e3;
        flipped += outcome.flipped_faces;
        match outcome.result {
            Ok((made, moved)) => {
                dented += usize::from(made > 0);
                moved_total += moved;
                *moved_count = moved as f64;
            }
            Err(message) => {
                errors += 1;
                if error_messages.len() < 5 {
                    error_messages.push(format!("dent {k}: {message}"));
                }
            }
        }
        let surface = target_body.mesh();
        let finite = |v: &[Vec3]| v.iter().all(|p| p.is_finite());
        non_finite += usize::from(!(finite(surface.positions()) && finite(surface.normals())));
        memory.record(k, resident_mb());
        if (k + 1) % checkpoint_every == 0 || k + 1 == dents {
            checkpoints.push(checkpoint(k + 1, surface));
        }
    }

    let last = target_body.mesh();
    let quality_last = quality_stats(last);
    let volume_last = last.volume();
    let peak_rss_mb = match (memory.first, memory.last) {
        (Some(first), Some(last)) => Some(FirstLast { first, last }),
        _ => None,
    };
    let window = TIME_WINDOW.min(dents);
    let median_first_ms = median(&times_ms[..window]);
    let median_last_ms = median(&times_ms[dents - window..]);
    let moved_vertices_median =
        FirstLast { first: median(&moved_counts[..window]), last: median(&moved_counts[dents - window..]) };
    let mut sorted = times_ms;
    sorted.sort_by(f64::total_cmp);
    Ok(Report {
        target: target.to_owned(),
        vertices,
        triangles,
        seed,
        backend: backend_name,
        dents,
        dented,
        errors,
        error_messages,
        non_finite,
        median_ms: nearest_rank(&sorted, 0.5),
        p99_ms: nearest_rank(&sorted, 0.99),
        median_first_ms,
        median_last_ms,
        max_ms: sorted[sorted.len() - 1],
        mean_ms: sorted.iter().sum::<f64>() / sorted.len() as f64,
        total_s: started.elapsed().as_secs_f64(),
        threads: rayon::current_num_threads(),
        projectile_radius: sizes.radius,
        dent_distance: sizes.dent_distance,
        target_size,
        target_thickness,
        projectile_scale: options.projectile_scale,
        depth: options.depth,
        cone_deg: options.cone_deg,
        moved_vertices_mean: moved_total as f64 / dents as f64,
        moved_vertices_median,
        flipped_faces: flipped,
        min_triangle_quality: FirstLast { first: quality_first.min, last: quality_last.min },
        mean_triangle_quality: FirstLast { first: quality_first.mean, last: quality_last.mean },
        volume: FirstLast { first: volume_first, last: volume_last },
        volume_change: (f64::from(volume_last) - f64::from(volume_first)) / f64::from(volume_first),
        peak_rss_mb,
        peak_rss_hwm_mb: peak_resident_mb(),
        checkpoints,
    })
}

fn checkpoint(dents: usize, mesh: &TriMesh) -> Checkpoint {
    let QualityStats { min, mean } = quality_stats(mesh);
    Checkpoint {
        dents,
        triangles: mesh.face_count(),
        min_triangle_quality: min,
        mean_triangle_quality: mean,
        volume: mesh.volume(),
        rss_mb: resident_mb(),
    }
}

/// The median (nearest rank) of `times` (non-empty, any order).
fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    nearest_rank(&sorted, 0.5)
}

/// The `p`-quantile of ascending `sorted` (non-empty) by the nearest-rank rule.
pub fn nearest_rank(sorted: &[f64], p: f64) -> f64 {
    let rank = (p * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

/// The report as a few lines of text.
pub fn render(r: &Report) -> String {
    let rss = match &r.peak_rss_mb {
        Some(m) => {
            format!("peak RSS {:.1} MiB over the first {MEMORY_WINDOW} dents, {:.1} over the last", m.first, m.last)
        }
        None => "RSS not available on this platform".to_owned(),
    };
    format!(
        "soak {}: {} dents ({} dented, {} errors, {} non-finite) on {} triangles in {:.1} s\n  \
         per dent: median {:.3} ms (first {TIME_WINDOW}: {:.3}, last {TIME_WINDOW}: {:.3}), p99 {:.3} ms, max {:.3} ms\n  \
         vertices moved per dent, median: {:.0} over the first {TIME_WINDOW}, {:.0} over the last\n  \
         min triangle quality {:.4} → {:.4}, volume change {:+.2} %, {} faces turned over\n  {rss}\n",
        r.target,
        r.dents,
        r.dented,
        r.errors,
        r.non_finite,
        r.triangles,
        r.total_s,
        r.median_ms,
        r.median_first_ms,
        r.median_last_ms,
        r.p99_ms,
        r.max_ms,
        r.moved_vertices_median.first,
        r.moved_vertices_median.last,
        r.min_triangle_quality.first,
        r.min_triangle_quality.last,
        100.0 * r.volume_change,
        r.flipped_faces,
    )
}
