//! `dentbend run`'s `damage.json`: the run's damage as data (see `dentbend::record`), written
//! once at the end, and its size per dent for `summary.json`.

use std::io::Write;
use std::path::Path;

use dentbend::mesh::write_file_atomically;
use dentbend::record::SceneRef;
use dentbend_solver::coupling::{DamageLog, Simulation};
use dentbend_solver::scene::BUILTIN_SCENES;
use serde::Serialize;

use crate::error::CliError;
use crate::options::SizeChoice;

/// The damage file's name in the output directory.
pub const DAMAGE_FILE: &str = "damage.json";

/// `summary.json`'s `damage` entry.
#[derive(Debug, Serialize)]
pub struct DamageSummary {
    /// The file, relative to the output directory.
    pub file: &'static str,
    /// Its size, bytes.
    pub bytes: u64,
    /// Dents it records.
    pub dents: u64,
    /// `bytes / dents` (`null` without dents).
    pub bytes_per_dent: Option<f64>,
}

/// The scene named `spec` as a damage file records it: a built-in's name and size, or a scene
/// file's path and the hash of its bytes.
pub fn scene_ref(spec: &str, size: SizeChoice, frame: u64) -> Result<SceneRef, CliError> {
    let file_hash = if BUILTIN_SCENES.contains(&spec) {
        None
    } else {
        let bytes =
            std::fs::read(spec).map_err(|e| CliError::Usage(format!("cannot read the scene file {spec}: {e}")))?;
        Some(SceneRef::file_hash_of(&bytes))
    };
    let size = match size {
        SizeChoice::Full => "full",
        SizeChoice::Demo => "demo",
    };
    Ok(SceneRef { spec: spec.to_owned(), size: size.to_owned(), file_hash, frame })
}

/// Writes `out/damage.json` from `log` (the run of `spec` at `size`, `frames` frames) and
/// returns its summary.
pub fn write_damage(
    log: &DamageLog,
    sim: &mut Simulation,
    spec: &str,
    size: SizeChoice,
    frames: u32,
    out: &Path,
) -> Result<DamageSummary, CliError> {
    let scene = scene_ref(spec, size, u64::from(frames))?;
    let file = log.finish(sim, scene).map_err(|e| CliError::Usage(format!("recording damage: {e}")))?;
    let bytes = file.to_json().map_err(|e| CliError::Usage(format!("recording damage: {e}")))?;
    let path = out.join(DAMAGE_FILE);
    write_file_atomically(&path, |w| w.write_all(&bytes)).map_err(|source| CliError::Write { path, source })?;
    let dents = file.dents();
    let size = bytes.len() as u64;
    Ok(DamageSummary {
        file: DAMAGE_FILE,
        bytes: size,
        dents,
        bytes_per_dent: (dents > 0).then(|| size as f64 / dents as f64),
    })
}
