//! `dentbend-bench gpu`: batched dents per second on the GPU against the CPU twins on all
//! cores (rayon), and the time of each GPU kernel stage, for several grid sides and batch sizes.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use dentbend::dent::{DentJob, VolumeMode, dent_batch};
use dentbend::glam::{Affine3A, Vec3};
use dentbend::gpu::{GpuContext, GpuDenter};
use dentbend::{DentParams, Impact, Resolution, TriMesh, mesh};
use serde::Serialize;

/// Targets the batch's dents are spread over (round robin) unless told: built-in `block`s.
pub const TARGETS: usize = 16;
/// Most targets `--targets` takes: a `block` has 12,290 vertices, and the resident vertices of
/// all targets must fit one dispatch of 65,535 × 64 invocations (about 341 blocks).
pub const MAX_TARGETS: usize = 256;

/// Which stages a GPU batch runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Stages {
    /// The paper's dent: the kernels alone on resident targets, recorded and submitted
    /// (`GpuDenter::record_batch`).
    Kernels,
    /// The game dent: refinement, fitted falloff, volume rim and intersection guard around the
    /// kernels (`GpuDenter::dent_batch`), each batch on undented targets.
    All,
}

impl Stages {
    /// The name in the JSON.
    pub fn name(self) -> &'static str {
        match self {
            Self::Kernels => "kernels",
            Self::All => "all",
        }
    }
}

/// One row; keys are the JSON interface.
#[derive(Debug, Serialize)]
pub struct Row {
    pub res: u32,
    pub batch: usize,
    pub gpu_dents_per_s: f64,
    /// Median seconds per batch the host spends planning, recording and submitting it (inside
    /// `gpu_dents_per_s`'s time; the rest is waiting for the GPU). With `--stages all` the
    /// denter waits for its read-backs of the moved vertices between its stages: this is the
    /// batch's time less those waits (`GpuDenter::waited_seconds`), so the host stages, the
    /// refinement and the resetting of the targets are in it.
    pub gpu_host_s: f64,
    pub cpu_dents_per_s: f64,
    /// Seconds per batch of each kernel stage (GPU timestamps where the device has them, else
    /// submit-and-wait wall time).
    pub kernels_s: BTreeMap<&'static str, f64>,
}

/// The scene: `targets` blocks, a 0.3-radius ball dropped on each top face at a spread of
/// points, d = 0.1, the given fixed grid side.
struct Scene {
    targets: Vec<TriMesh>,
    ball: TriMesh,
}

impl Scene {
    fn new(targets: usize) -> Result<Self, String> {
        let block = mesh::builtin("block").map_err(|e| e.to_string())?;
        let mut ball = mesh::icosphere(0.3, 3).map_err(|e| e.to_string())?;
        ball.transform(Affine3A::from_translation(Vec3::new(0.0, 1.0, 0.0))).map_err(|e| e.to_string())?;
        Ok(Self { targets: vec![block; targets], ball })
    }

    fn jobs(&self, res: u32, batch: usize, stages: Stages) -> Vec<DentJob<'_>> {
        let base = match stages {
            Stages::Kernels => DentParams::new(0.1).without_host_stages(),
            Stages::All => DentParams { volume: VolumeMode::Preserve, ..DentParams::new(0.1) },
        };
        (0..batch)
            .map(|k| {
                let spread = |n: usize| ((n * 7919 % 97) as f32 / 97.0 - 0.5) * 3.0;
                let point = Vec3::new(spread(k), 0.5, spread(k + 31));
                DentJob {
                    target: k % self.targets.len(),
                    projectile: &self.ball,
                    impact: Impact { point, normal: -Vec3::Y, relative_velocity: Vec3::new(0.3, -1.0, 0.0) },
                    params: DentParams { resolution: Resolution::Fixed(res), ..base.clone() },
                }
            })
            .collect()
    }
}

/// Median of the seconds `f` measures (its timed part), over at least 3 runs and `min_time`,
/// after one run that is not counted.
fn median(min_time: Duration, mut f: impl FnMut() -> Result<f64, String>) -> Result<f64, String> {
    f()?;
    let mut samples = Vec::new();
    let start = Instant::now();
    while samples.len() < 3 || start.elapsed() < min_time {
        samples.push(f()?);
    }
    samples.sort_by(f64::total_cmp);
    Ok(samples[samples.len() / 2])
}

/// Measures every (res, batch) pair with `stages`.
pub fn run(
    context: &GpuContext,
    targets: usize,
    stages: Stages,
    sides: &[u32],
    batches: &[usize],
    min_time: Duration,
) -> Result<Vec<Row>, String> {
    let scene = Scene::new(targets)?;
    let mut denter = GpuDenter::new(context, &scene.targets).map_err(|e| e.to_string())?;
    let mut rows = Vec::new();
    for &res in sides {
        for &batch in batches {
            let jobs = scene.jobs(res, batch, stages);
            let mut host = Vec::new();
            let gpu_s = median(min_time, || {
                if stages == Stages::All {
                    // Every batch dents the undented blocks again, put back in their slices on
                    // the device (an upload, not timed).
                    for (t, block) in scene.targets.iter().enumerate() {
                        denter.replace_target(t, block.clone()).map_err(|e| e.to_string())?;
                    }
                    context.wait().map_err(|e| e.to_string())?;
                }
                let start = Instant::now();
                match stages {
                    Stages::Kernels => {
                        let mut encoder = context.device.create_command_encoder(&Default::default());
                        denter.record_batch(&mut encoder, &jobs).map_err(|e| e.to_string())?;
                        context.queue.submit([encoder.finish()]);
                    }
                    Stages::All => drop(denter.dent_batch(&jobs).map_err(|e| e.to_string())?),
                }
                let waited = if stages == Stages::All { denter.waited_seconds() } else { 0.0 };
                host.push(start.elapsed().as_secs_f64() - waited);
                context.wait().map_err(|e| e.to_string())?;
                Ok(start.elapsed().as_secs_f64())
            })?;
            // The first call is `median`'s warm-up (it allocates the denter's buffers): not a sample.
            host.remove(0);
            host.sort_by(f64::total_cmp);
            let mut targets = scene.targets.clone();
            let cpu_s = median(min_time, || {
                targets.clone_from(&scene.targets);
                let start = Instant::now();
                dent_batch(&mut targets, &jobs).map_err(|e| e.to_string())?;
                Ok(start.elapsed().as_secs_f64())
            })?;
            let kernels_s = match stages {
                Stages::Kernels => denter.dent_batch_timed(&jobs).map_err(|e| e.to_string())?,
                Stages::All => BTreeMap::new(),
            };
            let row = Row {
                res,
                batch,
                gpu_dents_per_s: batch as f64 / gpu_s,
                gpu_host_s: host[host.len() / 2],
                cpu_dents_per_s: batch as f64 / cpu_s,
                kernels_s,
            };
            eprintln!(
                "  {res:>4}² × {batch:>5} ({}): GPU {:>9.0} dents/s ({:.2} ms of a batch on the host), CPU ({} threads) {:>9.0} dents/s",
                stages.name(),
                row.gpu_dents_per_s,
                row.gpu_host_s * 1e3,
                rayon::current_num_threads(),
                row.cpu_dents_per_s
            );
            rows.push(row);
        }
    }
    Ok(rows)
}

/// The table as text.
pub fn render(adapter: &str, timing: &str, rows: &[Row]) -> String {
    let mut text =
        format!("adapter: {adapter}; CPU: {} threads; kernel times: {timing}\n", rayon::current_num_threads());
    text += "  res │ batch │ GPU dents/s │ CPU dents/s │ zbuffer  env_rows env_cols heat     glance   displace normals (ms per batch)\n";
    for r in rows {
        let k = |name| r.kernels_s.get(name).copied().unwrap_or(0.0) * 1e3;
        text += &format!(
            "{:>5} │ {:>5} │ {:>11.0} │ {:>11.0} │ {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8.2}\n",
            format!("{}²", r.res),
            r.batch,
            r.gpu_dents_per_s,
            r.cpu_dents_per_s,
            k("zbuffer"),
            k("envelope_rows"),
            k("envelope_cols"),
            k("heat"),
            k("glance"),
            k("displace"),
            k("normals"),
        );
    }
    text
}
