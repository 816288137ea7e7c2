//! `dentbend-bench scene NAME`: steps a built-in scene (or scene file) with denting in the loop
//! and reports ms per step split into dynamics and denting, and dents per step, over the whole
//! run and over its busy part (the steps from the first dent to the last).

use dentbend::scene::{SceneSize, load_sized};
use dentbend::sim::{Simulation, StepTiming};
use serde::Serialize;

/// Step time statistics of one part of the run, ms.
#[derive(Debug, Serialize)]
pub struct Part {
    /// Steps in this part.
    pub steps: usize,
    /// Mean ms per step: dynamics (broad phase, contacts, impulses).
    pub dynamics_ms_mean: f64,
    /// Mean ms per step: dent batches and collider rebuilds.
    pub denting_ms_mean: f64,
    /// Mean ms per step, both.
    pub total_ms_mean: f64,
    /// Median ms per step, both.
    pub total_ms_median: f64,
    /// Mean dents per step.
    pub dents_per_step: f64,
    /// Mean denting ms per dent (the per-dent cost of the batched pipeline).
    pub denting_ms_per_dent: f64,
}

/// The benchmark's report.
#[derive(Debug, Serialize)]
pub struct Report {
    /// Scene name.
    pub scene: String,
    /// Bodies in the scene.
    pub bodies: usize,
    /// Where the dents ran.
    pub dents_on: &'static str,
    /// Rayon threads.
    pub threads: usize,
    /// The whole run.
    pub all: Part,
    /// Steps from the first dent to the last.
    pub busy: Part,
    /// Every step's timing.
    pub steps: Vec<StepTiming>,
}

/// Runs `frames` steps of `spec` (built-in name or path) at `size`, dents on `gpu` when given.
pub fn run(
    spec: &str,
    size: SceneSize,
    frames: Option<u32>,
    gpu: Option<&'static dentbend::gpu::GpuContext>,
) -> Result<Report, String> {
    let scene = load_sized(spec, size).map_err(|e| e.to_string())?;
    let frames = frames.unwrap_or(scene.frames);
    let bodies = scene.world.bodies().len();
    let mut sim = Simulation::new(scene.world, gpu).map_err(|e| e.to_string())?;
    let mut steps = Vec::with_capacity(frames as usize);
    for _ in 0..frames {
        steps.push(sim.step().map_err(|e| e.to_string())?.0);
    }
    let first = steps.iter().position(|s| s.dents > 0).unwrap_or(0);
    let last = steps.iter().rposition(|s| s.dents > 0).map_or(steps.len(), |k| k + 1);
    Ok(Report {
        scene: scene.name,
        bodies,
        dents_on: if sim.dents_on_gpu() { "gpu" } else { "cpu" },
        threads: rayon::current_num_threads(),
        all: part(&steps),
        busy: part(&steps[first..last]),
        steps,
    })
}

fn part(steps: &[StepTiming]) -> Part {
    let n = steps.len().max(1) as f64;
    let sum = |f: fn(&StepTiming) -> f64| steps.iter().map(f).sum::<f64>();
    let mut totals: Vec<f64> = steps.iter().map(|s| s.dynamics_ms + s.denting_ms).collect();
    totals.sort_by(f64::total_cmp);
    let dents = sum(|s| s.dents as f64);
    Part {
        steps: steps.len(),
        dynamics_ms_mean: sum(|s| s.dynamics_ms) / n,
        denting_ms_mean: sum(|s| s.denting_ms) / n,
        total_ms_mean: sum(|s| s.dynamics_ms + s.denting_ms) / n,
        total_ms_median: totals.get(totals.len() / 2).copied().unwrap_or(0.0),
        dents_per_step: dents / n,
        denting_ms_per_dent: if dents > 0.0 { sum(|s| s.denting_ms) / dents } else { 0.0 },
    }
}

/// The report as a few lines of text.
pub fn render(report: &Report) -> String {
    let line = |label: &str, p: &Part| {
        format!(
            "  {label:<5} {:>5} steps: {:8.2} ms/step ({:.2} dynamics + {:.2} denting), median {:.2}, {:.2} dents/step, {:.3} ms/dent\n",
            p.steps,
            p.total_ms_mean,
            p.dynamics_ms_mean,
            p.denting_ms_mean,
            p.total_ms_median,
            p.dents_per_step,
            p.denting_ms_per_dent
        )
    };
    format!(
        "scene {}: {} bodies, dents on {}, {} threads\n{}{}",
        report.scene,
        report.bodies,
        report.dents_on,
        report.threads,
        line("all", &report.all),
        line("busy", &report.busy)
    )
}
