//! Balls rain on the bunny and a block in Rapier; everything dents.
//!
//! `cargo run --release -p dentbend-rapier --example rapier_rain -- [--json FILE] [--damage D]`
//! `cargo run --release -p dentbend-rapier --example rapier_rain -- [--json FILE] --restore D`
//!
//! Runs on 2 CPU threads (dentbend's CPU backend uses rayon; Rapier is built single-threaded)
//! and prints (and writes to FILE) the run's numbers as JSON, with every dented body's mesh
//! hash (`mesh_hashes`). `--damage D` also writes the run's damage file; `--restore D` rebuilds
//! the scene's meshes and colliders from it with no simulation (the same `mesh_hashes`).

use std::collections::BTreeMap;
use std::path::PathBuf;

use dentbend_rapier::demo::rain::{Rain, RainSettings};
use dentbend_rapier::demo::report::publish;
use dentbend_rapier::dentbend::record::DamageFile;

/// The command line.
struct Args {
    json: Option<PathBuf>,
    damage: Option<PathBuf>,
    restore: Option<PathBuf>,
}

fn args() -> Result<Args, String> {
    let mut out = Args { json: None, damage: None, restore: None };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let slot = match a.as_str() {
            "--json" => &mut out.json,
            "--damage" => &mut out.damage,
            "--restore" => &mut out.restore,
            other => return Err(format!("unknown argument {other} (usage: [--json FILE] [--damage D | --restore D])")),
        };
        *slot = Some(PathBuf::from(args.next().ok_or(format!("{a} needs a file name"))?));
    }
    if out.damage.is_some() && out.restore.is_some() {
        return Err("--damage writes a run's damage, --restore reads one: give one of them".into());
    }
    Ok(out)
}

fn hashes(rain: &Rain) -> BTreeMap<String, String> {
    rain.mesh_hashes().into_iter().map(|(name, h)| (name, format!("{h:016x}"))).collect()
}

fn main() {
    if let Err(e) = run() {
        eprintln!("rapier_rain: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args = args()?;
    let json_path = args.json;
    rayon::ThreadPoolBuilder::new().num_threads(2).build_global()?;
    let mut rain = Rain::new(RainSettings::default())?;
    if let Some(path) = &args.restore {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let file = DamageFile::from_json(&bytes)?;
        rain.restore(&file)?;
        let json = serde_json::json!({
            "restored_from": path.display().to_string(),
            "bodies": file.bodies.len(),
            "dents": file.dents(),
            "mesh_hashes": hashes(&rain),
        });
        publish(&serde_json::to_string_pretty(&json)?, json_path.as_deref())?;
        return Ok(());
    }
    if args.damage.is_some() {
        rain.record_damage()?;
    }
    let totals = rain.run()?;
    if let Some(path) = &args.damage {
        let bytes = rain.adapter.dentables.damage_file().to_json()?;
        std::fs::write(path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    }
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
        "mesh_hashes": hashes(&rain),
    });
    publish(&serde_json::to_string_pretty(&json)?, json_path.as_deref())?;
    Ok(())
}
