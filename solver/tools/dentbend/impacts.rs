//! `dentbend dent --impacts FILE.json`: many impacts on one target in one call, read from a
//! JSON list, dented as one batch (each impact's map from the target before the batch, the
//! dents applied in the list's order).
//!
//! Each entry: `point` and `normal` (into the target) as `[x, y, z]`; optional `velocity`
//! (the projectile's, relative to the target; default head-on), `depth` (m; default
//! `--dent-distance`), and the projectile's extra pose `scale`, `rotate` (degrees, as
//! `--rotate`) and `translate`, applied after the command line's.

use std::path::Path;

use dentbend::dent::{BatchOutcome, DentJob, dent_batch_tracked};
use dentbend::glam::Vec3;
use dentbend::{DentParams, Impact, TriMesh};
use serde::Deserialize;

use crate::error::CliError;
use crate::options::{nonzero, placement};

/// Most impacts one file may hold.
pub const MAX_IMPACTS: usize = 100_000;
/// Largest impacts file read, bytes.
const MAX_FILE_BYTES: u64 = 64 << 20;

/// One entry of the file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    point: [f32; 3],
    normal: [f32; 3],
    velocity: Option<[f32; 3]>,
    depth: Option<f32>,
    scale: Option<f32>,
    rotate: Option<[f32; 3]>,
    translate: Option<[f32; 3]>,
}

/// One impact ready to dent: where, how deep, and the projectile as it hits.
pub struct PlannedImpact {
    /// The contact.
    pub impact: Impact,
    /// The dent's parameters (its depth from the entry or the command line).
    pub params: DentParams,
    /// The projectile, placed by the entry's pose when it has one.
    pub projectile: Option<TriMesh>,
}

/// Reads and checks `path`'s impacts, each with `params` (its depth replaced by the entry's)
/// and `projectile` placed by the entry's pose.
pub fn read(path: &Path, params: &DentParams, projectile: &TriMesh) -> Result<Vec<PlannedImpact>, CliError> {
    let bad = |reason: String| CliError::Usage(format!("--impacts {}: {reason}", path.display()));
    let size = std::fs::metadata(path).map_err(|e| bad(e.to_string()))?.len();
    if size > MAX_FILE_BYTES {
        return Err(bad(format!("{size} bytes, more than the {MAX_FILE_BYTES} an impacts file may have")));
    }
    let bytes = std::fs::read(path).map_err(|e| bad(e.to_string()))?;
    let entries: Vec<Entry> = serde_json::from_slice(&bytes).map_err(|e| {
        bad(format!("{e} (expected a JSON list of {{\"point\": [x, y, z], \"normal\": [x, y, z], …}})"))
    })?;
    if entries.is_empty() || entries.len() > MAX_IMPACTS {
        return Err(bad(format!("{} impacts: give 1 to {MAX_IMPACTS}", entries.len())));
    }
    entries
        .iter()
        .enumerate()
        .map(|(k, e)| plan(e, params, projectile).map_err(|reason| bad(format!("impact {k}: {reason}"))))
        .collect()
}

/// The impact of entry `e`, checked.
fn plan(e: &Entry, params: &DentParams, projectile: &TriMesh) -> Result<PlannedImpact, String> {
    let normal = nonzero(Vec3::from_array(e.normal), "normal").map_err(|e| e.to_string())?;
    let velocity = e.velocity.map_or(normal, Vec3::from_array);
    let impact = Impact { point: Vec3::from_array(e.point), normal, relative_velocity: velocity };
    impact.validate().map_err(|e| e.to_string())?;
    let mut params = params.clone();
    if let Some(depth) = e.depth {
        params.dent_distance = depth;
    }
    params.validate().map_err(|e| e.to_string())?;
    let projectile = match (e.scale, e.rotate, e.translate) {
        (None, None, None) => None,
        (scale, rotate, translate) => {
            let scale = scale.unwrap_or(1.0);
            if !(scale.is_finite() && scale > 0.0) {
                return Err(format!("scale {scale} must be finite and > 0"));
            }
            let placed = placement(
                scale,
                rotate.map_or(Vec3::ZERO, Vec3::from_array),
                translate.map_or(Vec3::ZERO, Vec3::from_array),
            );
            let mut moved = projectile.clone();
            moved.transform(placed).map_err(|e| e.to_string())?;
            Some(moved)
        }
    };
    Ok(PlannedImpact { impact, params, projectile })
}

/// Dents `target` with every impact of `planned` (the projectile `projectile` unless an entry
/// placed its own) as one batch; returns the dented mesh and the batch's outcome (what the
/// refinement appended, the vertices that moved, each dent's report).
pub fn dent_all(
    target: &TriMesh,
    projectile: &TriMesh,
    planned: &[PlannedImpact],
) -> Result<(TriMesh, BatchOutcome), CliError> {
    let jobs: Vec<DentJob<'_>> = planned
        .iter()
        .map(|p| DentJob {
            target: 0,
            projectile: p.projectile.as_ref().unwrap_or(projectile),
            impact: p.impact,
            params: p.params.clone(),
        })
        .collect();
    let mut targets = [target.clone()];
    let outcome = dent_batch_tracked(&mut targets, &jobs)
        .map_err(|e| CliError::Usage(format!("impact {}: {}", e.job, e.error)))?;
    let [dented] = targets;
    Ok((dented, outcome))
}
