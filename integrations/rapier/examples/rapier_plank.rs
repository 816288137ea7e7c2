//! Figure 14 in Rapier: a ball hits a plank on two supports; a plastic joint appears where it
//! hits, the plank bends and stays bent, its ends stay straight.
//!
//! `cargo run --release -p dentbend-rapier --example rapier_plank -- --json FILE`

use dentbend_rapier::demo::plank::Plank;
use dentbend_rapier::demo::report::{json_arg, publish};

/// Steps of 1/60 s: the ball lands within 0.1 s, the bend settles well before 2 s.
const STEPS: usize = 120;

fn main() {
    if let Err(e) = run() {
        eprintln!("rapier_plank: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let json_path = json_arg()?;
    rayon::ThreadPoolBuilder::new().num_threads(2).build_global()?;
    let mut plank = Plank::new(64)?;
    let totals = plank.run(STEPS)?;
    let steps = totals.steps.max(1) as f64;
    let joints = plank.plank().joints();
    let final_bend = joints.iter().map(|j| j.bend_angle().to_degrees()).fold(0.0, f32::max);
    let joint_x = joints.first().map(|j| j.rest_point.x);
    let json = serde_json::json!({
        "steps": totals.steps,
        "dents": totals.dents,
        "max_dent_depth": totals.max_dent_depth,
        "physics_ms_per_step": 1000.0 * totals.physics_seconds / steps,
        "dent_ms_per_step": 1000.0 * totals.dent_seconds / steps,
        "collider_ms_per_step": 1000.0 * totals.collider_seconds / steps,
        "bend_ms_per_step": 1000.0 * totals.bend_seconds / steps,
        "joints_created": totals.joints_created,
        "split_step": totals.split_step,
        "joint_rest_x": joint_x,
        "plastic_bends": totals.plastic_bends,
        "max_bend_deg": totals.max_bend_deg,
        "final_bend_deg": final_bend,
    });
    publish(&serde_json::to_string_pretty(&json)?, json_path.as_deref())?;
    Ok(())
}
