//! Balls rain on the bunny and a block in Rapier; everything dents.
//!
//! `cargo run --release -p dentbend-rapier --example rapier_rain -- --json FILE`
//!
//! Runs on 2 CPU threads (dentbend's CPU backend uses rayon; Rapier is built single-threaded)
//! and prints (and writes to FILE) the run's numbers as JSON.

use dentbend_rapier::demo::rain::{Rain, RainSettings};
use dentbend_rapier::demo::report::{json_arg, publish};

fn main() {
    if let Err(e) = run() {
        eprintln!("rapier_rain: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let json_path = json_arg()?;
    rayon::ThreadPoolBuilder::new().num_threads(2).build_global()?;
    let mut rain = Rain::new(RainSettings::default())?;
    let totals = rain.run()?;
    let steps = totals.steps.max(1) as f64;
    let ms = |s: f64| 1000.0 * s / steps;
    let max_depth = totals.dents.iter().map(|(_, d)| d.dent_distance).fold(0.0, f32::max);
    let on = |c| totals.dents.iter().filter(|(_, d)| d.target == c).count();
    let (physics, dent, collider) = (ms(totals.physics_seconds), ms(totals.dent_seconds), ms(totals.collider_seconds));
    let json = serde_json::json!({
        "steps": totals.steps,
        "dents": totals.dents.len(),
        "dents_on_bunny": on(rain.bunny),
        "dents_on_block": on(rain.block),
        "dents_on_balls": totals.dents.len() - on(rain.bunny) - on(rain.block),
        "balls": rain.balls.len(),
        "max_dent_depth": max_depth,
        "physics_ms_per_step": physics,
        "dent_ms_per_step": dent,
        "collider_ms_per_step": collider,
        "dent_and_collider_share_of_physics": (dent + collider) / physics.max(1e-12),
        "threads": 2,
        "joints_created": 0,
        "plastic_bends": 0,
        "max_bend_deg": 0.0,
    });
    publish(&serde_json::to_string_pretty(&json)?, json_path.as_deref())?;
    Ok(())
}
