//! `dentbend-bench scene NAME`: steps a built-in scene (or scene file) with denting in the loop
//! and reports ms per step split into dynamics, denting and (with `--skin`) skinning, and dents
//! per step, over the whole run and over its busy part (the steps from the first dent to the
//! last).

use dentbend_solver::coupling::{Simulation, StepStats, StepTiming};
use dentbend_solver::scene::{SceneSize, load_sized};
use serde::Serialize;

/// The benchmark's report.
#[derive(Debug, Serialize)]
pub struct Report {
    /// Scene name.
    pub scene: String,
    /// Bodies in the scene.
    pub bodies: usize,
    /// Where the dents ran.
    pub dents_on: &'static str,
    /// Where the bending bodies were skinned at the end of every step: "gpu", "cpu", or "off".
    pub skin_on: &'static str,
    /// Rayon threads.
    pub threads: usize,
    /// The whole run.
    pub all: StepStats,
    /// Steps from the first dent to the last.
    pub busy: StepStats,
    /// Every step's timing.
    pub steps: Vec<StepTiming>,
}

/// Runs `frames` steps of `spec` (built-in name or path) at `size`, dents on `gpu` when given;
/// with `skin`, every step ends by skinning the bending bodies (on `gpu` too when given).
pub fn run(
    spec: &str,
    size: SceneSize,
    frames: Option<u32>,
    gpu: Option<&'static dentbend::gpu::GpuContext>,
    skin: bool,
) -> Result<Report, String> {
    let scene = load_sized(spec, size).map_err(|e| e.to_string())?;
    let frames = frames.unwrap_or(scene.frames);
    let bodies = scene.world.bodies().len();
    let sim = Simulation::new(scene.world, gpu).map_err(|e| e.to_string())?.with_bending(scene.bending);
    let mut sim = sim.skin_every_step(skin);
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
        skin_on: match (skin, sim.skins_on_gpu()) {
            (false, _) => "off",
            (true, true) => "gpu",
            (true, false) => "cpu",
        },
        threads: rayon::current_num_threads(),
        all: StepStats::of(&steps),
        busy: StepStats::of(&steps[first..last]),
        steps,
    })
}

/// The report as a few lines of text.
pub fn render(report: &Report) -> String {
    let line = |label: &str, p: &StepStats| {
        let skinning = match report.skin_on {
            "off" => String::new(),
            _ => format!(" + {:.2} skinning", p.skinning_mean),
        };
        format!(
            "  {label:<5} {:>5} steps: {:8.2} ms/step ({:.2} dynamics + {:.2} denting{skinning}), median {:.2}, {:.2} dents/step, {:.3} ms/dent\n",
            p.steps,
            p.total_mean,
            p.dynamics_mean,
            p.denting_mean,
            p.total_median,
            p.dents_per_step_mean,
            p.denting_per_dent
        )
    };
    format!(
        "scene {}: {} bodies, dents on {}, skinning {}, {} threads\n{}{}",
        report.scene,
        report.bodies,
        report.dents_on,
        report.skin_on,
        report.threads,
        line("all", &report.all),
        line("busy", &report.busy)
    )
}
