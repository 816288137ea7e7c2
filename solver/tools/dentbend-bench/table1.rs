//! `dentbend-bench table1`: the paper's Table 1 (seconds per dent-map stage under grid
//! refinement, bunny projectile, one CPU thread) measured on this machine.

use std::time::Duration;

use dentbend::cpu::{self, reference};
use serde::Serialize;

use crate::setup::Scene;
use crate::timing::median_seconds;

/// The paper's Table 1 (2014 CPU, seconds): res, Z-buffer, broadening (theirs), O(N²), smoothing.
pub const PAPER: [(u32, f64, f64, f64, f64); 5] = [
    (25, 0.0086, 0.0053, 0.0148, 1.5e-4),
    (50, 0.0094, 0.0118, 0.2392, 5.9e-4),
    (100, 0.0104, 0.0696, 3.949, 0.0025),
    (200, 0.0125, 0.6643, 65.88, 0.0105),
    (400, 0.0178, 8.031, 1057.0, 0.0438),
];

/// One row of the table; keys are the JSON interface.
#[derive(Debug, Serialize)]
pub struct Row {
    pub res: u32,
    pub zbuffer_s: f64,
    pub envelope_s: f64,
    pub brute_s: Option<f64>,
    pub smoothing_s: f64,
}

/// Measures every row; the brute force only for `res <= brute_max`.
pub fn run(resolutions: &[u32], brute_max: u32, min_time: Duration) -> Result<Vec<Row>, String> {
    resolutions.iter().map(|&res| row(res, brute_max, min_time)).collect()
}

fn row(res: u32, brute_max: u32, min_time: Duration) -> Result<Row, String> {
    let scene = Scene::table1(res)?;
    let cells = (res as usize).pow(2);
    let (zparams, eparams) = (scene.plan.zbuffer, scene.plan.envelope);
    let profile = scene.stages.zbuffer.clone();

    let mut out = vec![0.0f32; cells];
    let zbuffer_s = median_seconds(5, min_time, || {
        cpu::zbuffer(&zparams, scene.projectile.positions(), scene.projectile.faces(), &mut out)
    });

    let mut rows = vec![0.0f32; cells];
    let mut envelope = vec![0.0f32; cells];
    let envelope_s = median_seconds(5, min_time, || {
        cpu::envelope_rows(&eparams, &profile, &mut rows);
        cpu::envelope_cols(&eparams, &rows, &mut envelope);
    });

    let brute_s = (res <= brute_max).then(|| {
        median_seconds(3, Duration::ZERO, || {
            std::hint::black_box(reference::envelope_brute(res, f64::from(eparams.c), &profile));
        })
    });

    let p = &scene.params;
    let mut smoothed = scene.stages.envelope.clone();
    let smoothing_s = median_seconds(5, min_time, || {
        smoothed.copy_from_slice(&scene.stages.envelope);
        cpu::heat(&mut smoothed, res, p.heat_rate, p.heat_iters, p.clamp_iters, p.dent_distance);
    });

    Ok(Row { res, zbuffer_s, envelope_s, brute_s, smoothing_s })
}

/// The table as text, each of our columns beside the paper's.
pub fn render(rows: &[Row]) -> String {
    let fmt = |s: f64| if s < 1e-3 { format!("{:.1} µs", s * 1e6) } else { format!("{:.2} ms", s * 1e3) };
    let mut text = String::from(
        "  res │ Z-buffer (paper)        │ envelope (paper broadening) │ brute O(N²) (paper)     │ smoothing (paper)\n",
    );
    for r in rows {
        let paper = PAPER.iter().find(|p| p.0 == r.res);
        let theirs = |pick: fn(&(u32, f64, f64, f64, f64)) -> f64| paper.map_or("—".to_string(), |p| fmt(pick(p)));
        let brute = r.brute_s.map_or("—".to_string(), fmt);
        text += &format!(
            "{:>5} │ {:>9} ({:>10}) │ {:>9} ({:>10})        │ {:>9} ({:>10}) │ {:>9} ({:>9})\n",
            format!("{0}²", r.res),
            fmt(r.zbuffer_s),
            theirs(|p| p.1),
            fmt(r.envelope_s),
            theirs(|p| p.2),
            brute,
            theirs(|p| p.3),
            fmt(r.smoothing_s),
            theirs(|p| p.4),
        );
    }
    text
}
