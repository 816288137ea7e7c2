//! `dentbend run`'s rest-state files of every bending body, written once before the first step
//! into `OUT/rest/`: `<body>_skeleton.png`, `<body>_sub_bodies.png` and `<body>_level_set.png`
//! (paper Figure 12), and `<body>_sub<k>.obj`, bone k's open sub-body surface in world
//! coordinates at the start.

use std::path::Path;

use dentbend_solver::coupling::Simulation;
use dentbend_solver::render::{Camera, Renderer, rest_pictures};

use crate::error::CliError;
use crate::file_names::file_stem;
use crate::output::{write_mesh, write_picture};

/// Folder under the output directory that holds the rest-state files.
pub const REST_DIR: &str = "rest";

/// The rest-state files written, as paths relative to the output directory.
#[derive(Debug, Default)]
pub struct RestFiles {
    /// The pictures, three per bending body.
    pub pictures: Vec<String>,
    /// The sub-body meshes, one per bone.
    pub meshes: Vec<String>,
}

/// Writes the rest-state files of every bending body of `sim` (at its start; bodies that share
/// one rest state once, under the first one's name, with `/` and other characters unfit for a
/// file name as `_`) under `out/rest/`: pictures when `renderer` is given (`size` pixels, seen along the scene
/// `camera`'s view), sub-body meshes when `meshes` holds.
///
/// # Errors
/// [`CliError::CreateDir`], [`CliError::Write`] for a file, [`CliError::Usage`] when a picture
/// cannot be drawn.
pub fn write_rest_files(
    sim: &Simulation,
    camera: &Camera,
    renderer: Option<&Renderer<'_>>,
    size: (u32, u32),
    meshes: bool,
    out: &Path,
) -> Result<RestFiles, CliError> {
    let mut files = RestFiles::default();
    let bodies = sim.bending().bodies();
    if bodies.is_empty() || (renderer.is_none() && !meshes) {
        return Ok(files);
    }
    let dir = out.join(REST_DIR);
    std::fs::create_dir_all(&dir).map_err(|source| CliError::CreateDir { path: dir.clone(), source })?;
    // Bodies built alike share one rest state (`ArticulatedBody::new_like`): drawn once.
    let mut drawn: Vec<&dentbend::bend::SubBodies> = Vec::new();
    for body in bodies {
        if drawn.iter().any(|&d| std::ptr::eq(d, body.sub_bodies())) {
            continue;
        }
        drawn.push(body.sub_bodies());
        let name = body.name();
        let stem = file_stem(name);
        let usage = |e: &dyn std::fmt::Display| CliError::Usage(format!("bending body \"{name}\": {e}"));
        let transforms = body.bone_transforms(sim.world()).map_err(|e| usage(&e))?;
        let pose = *transforms.get(body.skeleton().root()).ok_or_else(|| usage(&"no sub-body for the root bone"))?;
        if let Some(renderer) = renderer {
            let pictures =
                rest_pictures(body, pose, camera.target - camera.eye, renderer, size).map_err(|e| usage(&e))?;
            for (kind, picture) in [
                ("skeleton", &pictures.skeleton),
                ("sub_bodies", &pictures.sub_bodies),
                ("level_set", &pictures.level_set),
            ] {
                let file = format!("{stem}_{kind}.png");
                let path = dir.join(&file);
                write_picture(&path, picture)?;
                files.pictures.push(format!("{REST_DIR}/{file}"));
            }
        }
        if meshes {
            for (k, mut mesh) in body.sub_meshes().map_err(|e| usage(&e))?.into_iter().enumerate() {
                mesh.transform(pose).map_err(|e| usage(&e))?;
                let file = format!("{stem}_sub{k}.obj");
                let path = dir.join(&file);
                write_mesh(&path, &mesh)?;
                files.meshes.push(format!("{REST_DIR}/{file}"));
            }
        }
    }
    Ok(files)
}
