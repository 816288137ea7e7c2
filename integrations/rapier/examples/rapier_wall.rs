//! Figure 3 in Rapier: a ball breaks a prescored wall. The hit dents the wall, then breaks it
//! along a pattern placed where it hit; the pieces become Rapier bodies and the ball carries on
//! through the hole.
//!
//! `cargo run --release -p dentbend-rapier --example rapier_wall -- --json FILE`

use dentbend_rapier::demo::report::{json_arg, publish};
use dentbend_rapier::demo::wall::Wall;

/// Steps of 1/60 s: the ball reaches the wall within 0.1 s; the pieces have left it by 1.5 s.
const STEPS: usize = 90;

fn main() {
    if let Err(e) = run() {
        eprintln!("rapier_wall: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let json_path = json_arg()?;
    rayon::ThreadPoolBuilder::new().num_threads(2).build_global()?;
    let mut wall = Wall::new()?;
    let totals = wall.run(STEPS)?;
    let steps = totals.steps.max(1) as f64;
    let ball = wall.world.bodies.get(wall.ball).ok_or("the ball is gone")?;
    let rest_volume = wall.wall_mesh().map_or(0.0, |m| m.volume().abs());
    let json = serde_json::json!({
        "steps": totals.steps,
        "fractures": totals.fractures,
        "pieces": totals.pieces,
        "piece_bodies": totals.piece_bodies,
        "fracture_step": totals.fracture_step,
        "dents": totals.dents,
        "wall_volume": dentbend_rapier::demo::wall::WALL_SIZE.x * dentbend_rapier::demo::wall::WALL_SIZE.y * dentbend_rapier::demo::wall::WALL_SIZE.z,
        "rest_volume": rest_volume,
        "ball_z": ball.translation().z,
        "ball_speed": ball.linvel().length(),
        "physics_ms_per_step": 1000.0 * totals.physics_seconds / steps,
        "damage_ms_per_step": 1000.0 * totals.damage_seconds / steps,
    });
    publish(&serde_json::to_string_pretty(&json)?, json_path.as_deref())?;
    Ok(())
}
