//! Damage over the network: the rain scene on a server; its dents go over loopback TCP to two
//! clients, one there from the start and one that joins after at least 100 dents, which rebuild
//! the dented meshes bit for bit without running physics.
//!
//! `cargo run --release -p dentbend-rapier --example rapier_network -- --json FILE`

use dentbend_rapier::demo::network::{NetworkSettings, run};
use dentbend_rapier::demo::report::{json_arg, publish};

fn main() {
    if let Err(e) = main_result() {
        eprintln!("rapier_network: {e}");
        std::process::exit(1);
    }
}

fn main_result() -> Result<(), Box<dyn std::error::Error>> {
    let json_path = json_arg()?;
    rayon::ThreadPoolBuilder::new().num_threads(2).build_global()?;
    let r = run(NetworkSettings::default())?;
    let hex = |h: u64| format!("{h:016x}");
    let json = serde_json::json!({
        "steps": r.steps,
        "dents": r.dents,
        "messages": r.messages,
        "stream_bytes": r.stream_bytes,
        "bytes_per_dent": r.stream_bytes as f64 / r.dents.max(1) as f64,
        "clients_identical": r.clients_identical,
        "hits_before_join": r.hits_before_join,
        "late_join_bytes": r.late_join_bytes,
        "full_mesh_bytes": r.full_mesh_bytes,
        "server_hashes": r.server_hashes.map(hex),
        "client_hashes": r.client_hashes.map(|c| c.map(hex)),
    });
    publish(&serde_json::to_string_pretty(&json)?, json_path.as_deref())?;
    if !r.clients_identical {
        return Err("a client's meshes differ from the server's".into());
    }
    Ok(())
}
