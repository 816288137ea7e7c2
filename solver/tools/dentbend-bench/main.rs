//! `dentbend-bench`: offscreen benchmarks of the dent pipeline, printed as tables and written
//! as JSON. Every kernel runs on one CPU thread.

mod displace;
mod glance;
mod gpu;
#[path = "../common/headless.rs"]
mod headless;
mod memory;
mod scene;
mod setup;
mod soak;
mod soak_target;
mod stages;
mod surface_sample;
mod table1;
mod timing;
mod triangle_quality;

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "dentbend-bench",
    version,
    about = "Benchmarks of the dentbend kernels (median wall times, one thread)."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Reproduce the paper's Table 1: Z-buffer, exact envelope, brute-force envelope and
    /// smoothing of the bunny's dent map for grids 25² to 400².
    Table1 {
        /// Write the rows as JSON: {"rows":[{"res","zbuffer_s","envelope_s","brute_s","smoothing_s"}]}.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Largest grid side for which the O(N²) brute force is timed (it takes ~16× longer per doubling).
        #[arg(long, default_value_t = 100)]
        brute_max: u32,
        /// Grid sides to measure, comma separated.
        #[arg(long, value_delimiter = ',', default_values_t = [25, 50, 100, 200, 400])]
        res: Vec<u32>,
        /// Minimum wall time per measurement, seconds (more repetitions, steadier medians).
        #[arg(long, default_value_t = 0.5)]
        min_time: f64,
    },
    /// Batched dents per second on the GPU next to the CPU twins on all cores, and per-kernel GPU
    /// times, for grid sides × batch sizes (block targets, 16 unless `--targets`, a small ball, d = 0.1).
    Gpu {
        /// Write {"adapter", "kernel_timing", "targets", "rows":[{"res","batch","gpu_dents_per_s","gpu_host_s","cpu_dents_per_s","kernels_s":{..}}]}.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Grid sides, comma separated.
        #[arg(long, value_delimiter = ',', default_values_t = [64, 100, 200])]
        res: Vec<u32>,
        /// Batch sizes (dents per batch), comma separated.
        #[arg(long, value_delimiter = ',', default_values_t = [1, 16, 256, 1024])]
        batch: Vec<usize>,
        /// Blocks the dents are spread over, round robin (1: every dent on one body).
        #[arg(long, default_value_t = gpu::TARGETS)]
        targets: usize,
        /// Which stages the GPU batch runs: `kernels` (the paper's dent on resident targets,
        /// `GpuDenter`) or `all` (the game dent: refinement, fitted falloff, volume rim and
        /// intersection guard, as the GPU backend runs them, `GpuBackend`); the CPU column runs the
        /// same dents on all cores.
        #[arg(long, value_enum, default_value_t = gpu::Stages::Kernels)]
        stages: gpu::Stages,
        /// Minimum wall time per measurement, seconds.
        #[arg(long, default_value_t = 0.5)]
        min_time: f64,
    },
    /// Step a built-in scene (or a scene file) with denting in the loop: ms per step split into
    /// dynamics, denting and skinning, dents per step, over the whole run and its busy part.
    Scene {
        /// Built-in scene name (rain, pair, ball-block, bunny-block, glancing, resolution) or a .toml file.
        name: String,
        /// Write the report as JSON: {"scene","bodies","dents_on","skin_on","threads","all":{..},"busy":{..},"steps":[..]}.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Frames (steps) to run [default: the scene's].
        #[arg(long)]
        frames: Option<u32>,
        /// Run the scene's small demo size instead of the paper's.
        #[arg(long)]
        demo: bool,
        /// Where dents run: cpu, gpu or auto.
        #[arg(long, default_value = "cpu")]
        backend: String,
        /// End every step by skinning the bending bodies (on the --backend's device), timed as
        /// skinning.
        #[arg(long)]
        skin: bool,
    },
    /// Apply one dent map to a target of about 100,000 vertices.
    Displace {
        /// Write the report as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Cells of the target block along x, y, z (184,46,184 gives 101,570 vertices).
        #[arg(long, value_delimiter = ',', num_args = 3, default_values_t = setup::DISPLACE_CELLS)]
        cells: Vec<u32>,
        /// Minimum wall time per measurement, seconds.
        #[arg(long, default_value_t = 0.5)]
        min_time: f64,
    },
    /// Head-on dents next to steep glancing ones (θ 60–84°) on one target, interleaved in one
    /// run, soak-like hits: median, p99 and max per-dent wall time of each group.
    Glance {
        /// Dents per group.
        #[arg(long, default_value_t = 500)]
        dents: usize,
        /// Target: a built-in mesh name or a .obj/.ply/.gltf/.glb path.
        #[arg(long, default_value = "block-fine")]
        target: String,
        /// Seed of the random hits.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Write the report as JSON: {"head_on":{"median_ms","p99_ms","max_ms",..},"steep":{..},
        /// "steep_p99_over_head_on_median",..}.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// What refinement, volume preservation and the intersection guard add to one dent: the
    /// `dent_game` benchmark's dent (a 0.25 m ball, d = 0.06 m, head-on and at 60°) as the paper
    /// makes it and with every stage on, interleaved dent by dent: medians and their ratio.
    Stages {
        /// Timed dents per setting and impact.
        #[arg(long, default_value_t = 400)]
        dents: usize,
        /// Target: a built-in mesh name or a .obj/.ply/.gltf/.glb path (hit on the middle of its top).
        #[arg(long, default_value = "block-fine")]
        target: String,
        /// Write the report as JSON: {"target","dents","threads","rows":[{"impact","paper_ms","game_ms","ratio"}]}.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Dent one target N times at seeded random points of its surface (a small ball, random
    /// incidence) through the damage API on the CPU (or the GPU backend): errors, non-finite
    /// vertices, per-dent times (the first and last 100 dents' medians too), triangle quality,
    /// faces turned over, volume and memory, first against last.
    Soak {
        /// Dents to make.
        #[arg(long, default_value_t = 10_000)]
        dents: usize,
        /// Target: a built-in mesh name or a .obj/.ply/.gltf/.glb path.
        #[arg(long, default_value = "block")]
        target: String,
        /// Seed of the random hits (the same seed gives the same hits).
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Projectile radius of each hit drawn uniformly up to F × the target's size (its bounding
        /// box's largest side) [default: every ball 3 % of the bounding-box diagonal].
        #[arg(long, value_name = "F")]
        projectile_scale: Option<f32>,
        /// Head-on dent distance of each hit drawn uniformly up to F × the target's thickness (its
        /// bounding box's smallest side) [default: every dent 0.3 % of the bounding-box diagonal];
        /// a hit at incidence θ dents cos θ of it.
        #[arg(long, value_name = "F")]
        depth: Option<f32>,
        /// Half-angle of the cone of incidence about the inward normal, degrees.
        #[arg(long, default_value_t = soak::CONE_DEG)]
        cone_deg: f32,
        /// Where dents run: cpu, or gpu (the crate's GPU backend; an error without an adapter).
        #[arg(long, default_value = "cpu")]
        backend: String,
        /// Write the report as JSON: {"dents","errors","non_finite","median_ms","p99_ms","max_ms",
        /// "median_first_ms","median_last_ms","moved_vertices_median":{"first","last"},"flipped_faces","target_size","target_thickness",
        /// "min_triangle_quality":{"first","last"},"volume_change","peak_rss_mb":{"first","last"},..}.
        #[arg(long)]
        json: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    headless::quiet_headless_vulkan();
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> Result<(), String> {
    match cli.command {
        Command::Table1 { json, brute_max, res, min_time } => {
            if let Some(&bad) = res.iter().find(|&&r| !(1..=dentbend::dent::MAX_RESOLUTION).contains(&r)) {
                return Err(format!("grid side {bad} is outside 1..={}", dentbend::dent::MAX_RESOLUTION));
            }
            let rows = table1::run(&res, brute_max, seconds(min_time)?)?;
            print!("{}", table1::render(&rows));
            write_json(json, &serde_json::json!({ "rows": rows }))
        }
        Command::Gpu { json, res, batch, targets, stages, min_time } => {
            if let Some(&bad) = res.iter().find(|&&r| !(1..=dentbend::dent::MAX_RESOLUTION).contains(&r)) {
                return Err(format!("grid side {bad} is outside 1..={}", dentbend::dent::MAX_RESOLUTION));
            }
            if batch.contains(&0) {
                return Err("batch sizes must be at least 1".into());
            }
            if !(1..=gpu::MAX_TARGETS).contains(&targets) {
                return Err(format!("--targets must be 1..={}", gpu::MAX_TARGETS));
            }
            let context = dentbend::gpu::shared_context().map_err(|e| e.to_string())?;
            let adapter = context.adapter_name();
            eprintln!("adapter: {adapter}");
            let rows = gpu::run(context, targets, stages, &res, &batch, seconds(min_time)?)?;
            let timing = if context.timestamps { "timestamp queries" } else { "submit-and-wait" };
            print!("{}", gpu::render(&adapter, timing, &rows));
            write_json(
                json,
                &serde_json::json!({
                    "adapter": adapter,
                    "kernel_timing": timing,
                    "targets": targets,
                    "stages": stages.name(),
                    "rows": rows
                }),
            )
        }
        Command::Scene { name, json, frames, demo, backend, skin } => {
            let backend = dentbend::gpu::KernelDevice::parse(&backend).map_err(|e| e.to_string())?;
            let gpu = backend.context().map_err(|e| e.to_string())?;
            let size =
                if demo { dentbend_solver::scene::SceneSize::Demo } else { dentbend_solver::scene::SceneSize::Full };
            let report = scene::run(&name, size, frames, gpu, skin)?;
            print!("{}", scene::render(&report));
            write_json(json, &serde_json::to_value(&report).map_err(|e| e.to_string())?)
        }
        Command::Displace { json, cells, min_time } => {
            let cells: [u32; 3] = cells.try_into().map_err(|_| "--cells takes three numbers".to_string())?;
            let report = displace::run(cells, seconds(min_time)?)?;
            println!(
                "displace: {} vertices ({} moved, map {}²): kernel {:.3} ms, DentMap::apply {:.3} ms",
                report.vertices,
                report.moved,
                report.map_res,
                report.displace_s * 1e3,
                report.apply_s * 1e3
            );
            write_json(json, &serde_json::to_value(&report).map_err(|e| e.to_string())?)
        }
        Command::Glance { dents, target, seed, json } => {
            let report = glance::run(&target, dents, seed)?;
            print!("{}", glance::render(&report));
            write_json(json, &serde_json::to_value(&report).map_err(|e| e.to_string())?)
        }
        Command::Stages { dents, target, json } => {
            let report = stages::run(&target, dents)?;
            print!("{}", stages::render(&report));
            write_json(json, &serde_json::to_value(&report).map_err(|e| e.to_string())?)
        }
        Command::Soak { dents, target, seed, projectile_scale, depth, cone_deg, backend, json } => {
            let options = soak::Options {
                projectile_scale,
                depth,
                cone_deg,
                backend,
                ..soak::Options::new(&target, dents, seed)
            };
            let report = soak::run(&options)?;
            print!("{}", soak::render(&report));
            write_json(json, &serde_json::to_value(&report).map_err(|e| e.to_string())?)
        }
    }
}

fn seconds(value: f64) -> Result<Duration, String> {
    Duration::try_from_secs_f64(value).map_err(|_| format!("--min-time {value} is not a duration in seconds"))
}

fn write_json(path: Option<PathBuf>, value: &serde_json::Value) -> Result<(), String> {
    let Some(path) = path else { return Ok(()) };
    let text = serde_json::to_string_pretty(value).map_err(|e| e.to_string())?;
    // Whole or not at all: an earlier result survives a failed write.
    dentbend::mesh::write_file_atomically(&path, |out| out.write_all((text + "\n").as_bytes()))
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}
