//! `dentbend-bench stages`: what refinement, volume preservation and the intersection guard
//! add to one dent (against its budget), measured as in `cargo bench --bench dent_game` but with
//! the two settings interleaved dent by dent, so that both see the same machine state: a ball of
//! radius [`BALL_RADIUS`] resting on the middle of the target's top, a dent of
//! [`DENT_DISTANCE`], head-on and at [`GLANCE_DEG`], once as the paper makes it (no
//! refinement, volume free, no guard) and once with every stage on.

use dentbend::dent::Refine;
use dentbend::glam::{Affine3A, Quat, Vec3};
use dentbend::{DentParams, Impact, TriMesh, VolumeMode, dent, mesh};
use serde::Serialize;

use crate::soak::nearest_rank;

/// Ball radius, m.
pub const BALL_RADIUS: f32 = 0.25;
/// Dent distance, m (30 % of the ball's radius).
pub const DENT_DISTANCE: f32 = 0.06;
/// Incidence of the glancing dent, degrees from the normal.
pub const GLANCE_DEG: f32 = 60.0;
/// Untimed dents of each setting before the timed ones.
const WARM_UP: usize = 20;

/// One impact's medians; the keys are the interface.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    /// "head-on" or "glancing-60".
    pub impact: String,
    /// Median wall time of the paper's dent, ms.
    pub paper_ms: f64,
    /// Median wall time with refinement auto, volume kept and the guard on, ms.
    pub game_ms: f64,
    /// game_ms / paper_ms.
    pub ratio: f64,
}

/// The report; the keys are the interface.
#[derive(Debug, Serialize)]
pub struct Report {
    /// The target's spec (built-in name or path).
    pub target: String,
    /// Timed dents per setting and impact.
    pub dents: usize,
    /// Rayon threads the dents could use.
    pub threads: usize,
    /// Head-on, then glancing.
    pub rows: Vec<Row>,
}

/// Times `dents` dents of each setting per impact on a fresh copy of `target` each.
pub fn run(target: &str, dents: usize) -> Result<Report, String> {
    if !(1..=100_000).contains(&dents) {
        return Err(format!("--dents {dents} is outside 1..=100000"));
    }
    let body = mesh::load(target).map_err(|e| format!("{target}: {e}"))?;
    let (point, ball) = ball_on_top(&body)?;
    let paper = DentParams {
        refine: Refine::Off,
        volume: VolumeMode::Free,
        guard_crossings: false,
        ..DentParams::new(DENT_DISTANCE)
    };
    let game = DentParams { volume: VolumeMode::Preserve, ..DentParams::new(DENT_DISTANCE) };
    let mut rows = Vec::new();
    for (name, degrees) in [("head-on", 0.0f32), ("glancing-60", GLANCE_DEG)] {
        let velocity = Quat::from_rotation_z(degrees.to_radians()) * -Vec3::Y;
        let impact = Impact { point, normal: -Vec3::Y, relative_velocity: velocity };
        let mut times = [Vec::with_capacity(dents), Vec::with_capacity(dents)];
        for i in 0..WARM_UP + dents {
            for (setting, params) in [&paper, &game].into_iter().enumerate() {
                let mut copy = body.clone();
                let start = std::time::Instant::now();
                dent(&mut copy, &ball, &impact, params).map_err(|e| format!("{name} dent: {e}"))?;
                if i >= WARM_UP {
                    times[setting].push(start.elapsed().as_secs_f64() * 1e3);
                }
            }
        }
        let [paper_ms, game_ms] = times.map(|mut t| {
            t.sort_by(f64::total_cmp);
            nearest_rank(&t, 0.5)
        });
        rows.push(Row { impact: name.into(), paper_ms, game_ms, ratio: game_ms / paper_ms });
    }
    Ok(Report { target: target.into(), dents, threads: rayon::current_num_threads(), rows })
}

/// The middle of the top of `body` (its box's centre on x and z, its highest point's height),
/// and the built-in sphere scaled to [`BALL_RADIUS`] resting on it.
fn ball_on_top(body: &TriMesh) -> Result<(Vec3, TriMesh), String> {
    let (low, high) = body.bounds();
    let point = Vec3::new(0.5 * (low.x + high.x), high.y, 0.5 * (low.z + high.z));
    let mut ball = mesh::builtin("sphere").map_err(|e| e.to_string())?;
    let placement = Affine3A::from_scale_rotation_translation(
        Vec3::splat(BALL_RADIUS),
        Quat::IDENTITY,
        point + Vec3::Y * BALL_RADIUS,
    );
    ball.transform(placement).map_err(|e| e.to_string())?;
    Ok((point, ball))
}

/// The report as a table.
pub fn render(report: &Report) -> String {
    let mut out = format!(
        "stages on {} ({} dents per setting, {} threads; d = {DENT_DISTANCE} m, ball r = {BALL_RADIUS} m):\n",
        report.target, report.dents, report.threads
    );
    for row in &report.rows {
        out += &format!(
            "  {:<12} paper {:.3} ms, all stages {:.3} ms, ratio {:.2}\n",
            row.impact, row.paper_ms, row.game_ms, row.ratio
        );
    }
    out
}
