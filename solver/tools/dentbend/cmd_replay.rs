//! `dentbend replay DIR/damage.json --out DIR2`: rebuilds a run's final meshes from its damage
//! file and the scene's base meshes (the pieces of a fracture from the body that broke), and
//! writes them as `run` wrote its last frame's. Everything
//! is checked before anything is written: a file that is truncated, of another version, from
//! another scene or mesh, or tampered with is refused and `--out` is not touched.

use std::io::Read;
use std::path::PathBuf;

use clap::Args;
use dentbend::TriMesh;
use dentbend::record::{DamageFile, DentForm, Projectiles, replay_body};
use dentbend_solver::scene::{LoadOptions, MeshPaths, SceneSize, load_with};

use crate::cmd_run::{MeshChoice, Shown, write_meshes};
use crate::damage_output::scene_ref;
use crate::error::CliError;
use crate::options::SizeChoice;

/// Arguments of `dentbend replay`.
#[derive(Debug, Args)]
pub struct ReplayArgs {
    /// The damage file `dentbend run` wrote (DIR/damage.json)
    pub damage: PathBuf,

    /// Output directory (created if missing): meshes/ with the final frame's meshes, named as
    /// `run` names them
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,

    /// Which meshes to write (as `run --meshes`)
    #[arg(long, value_enum, default_value = "frame")]
    pub meshes: MeshChoice,

    /// Let a scene file's mesh paths leave its folder (as `run --trust-paths`)
    #[arg(long)]
    pub trust_paths: bool,

    /// Load a scene file past the default limits (as `run --allow-large`)
    #[arg(long)]
    pub allow_large: bool,
}

/// Runs the command; returns the summary line.
pub fn run(args: &ReplayArgs) -> Result<String, CliError> {
    let shown_path = args.damage.display().to_string();
    let bad = |e: &dyn std::fmt::Display| CliError::Usage(format!("{shown_path}: {e}"));
    let bytes = read_bounded(&args.damage).map_err(|e| bad(&e))?;
    let file = DamageFile::from_json(&bytes).map_err(|e| bad(&e))?;
    let recorded = file.scene.clone().ok_or_else(|| bad(&"names no scene to replay against"))?;
    let size = match recorded.size.as_str() {
        "full" => SizeChoice::Full,
        "demo" => SizeChoice::Demo,
        other => return Err(bad(&format!("unknown scene size {other:?}"))),
    };
    let now = scene_ref(&recorded.spec, size, recorded.frame)?;
    if now.file_hash != recorded.file_hash {
        return Err(bad(&format!(
            "was recorded on scene file {} with hash {}, which now hashes to {}",
            recorded.spec,
            recorded.file_hash.map_or("-".into(), |h| format!("{h:016x}")),
            now.file_hash.map_or("-".into(), |h| format!("{h:016x}"))
        )));
    }
    let mut options = LoadOptions::sized(if size == SizeChoice::Full { SceneSize::Full } else { SceneSize::Demo });
    if args.trust_paths {
        options.mesh_paths = MeshPaths::Trusted;
    }
    if args.allow_large {
        options = options.unlimited();
    }
    let scene = load_with(&recorded.spec, &options).map_err(|e| CliError::Usage(e.to_string()))?;
    let bases = base_meshes(&scene);
    let mut projectiles = Projectiles::new();
    bases.iter().for_each(|b| {
        projectiles.insert(b.mesh.clone());
    });
    let names: Vec<String> = bases.iter().map(|b| b.name.clone()).collect();
    let mismatch =
        |listed: Vec<&str>| bad(&format!("lists bodies {listed:?}, the scene {} has {names:?}", recorded.spec));
    // The file lists the scene's bodies in order, with the pieces of fractures (made by a body
    // listed before them) among them: each body replays from its scene mesh or its piece mesh.
    let mut scene_bases = bases.into_iter().peekable();
    let mut pieces: Vec<(String, Base)> = Vec::new();
    let mut shown = Vec::with_capacity(file.bodies.len());
    for body in &file.bodies {
        let base = match pieces.iter().position(|(name, _)| *name == body.name) {
            Some(k) => pieces.swap_remove(k).1,
            None if scene_bases.peek().is_some_and(|b| b.name == body.name) => scene_bases.next().expect("peeked"),
            None => return Err(mismatch(file.bodies.iter().map(|b| b.name.as_str()).collect())),
        };
        let replayed = replay_body(body, &base.mesh, DentForm::Edits, &projectiles).map_err(|e| bad(&e))?;
        // As the simulation makes them: a piece is dynamic, in its parent's colour, and does not dent.
        pieces.extend(
            replayed
                .pieces
                .into_iter()
                .map(|(name, mesh)| (name.clone(), Base { name, mesh, colour: base.colour, changes: false })),
        );
        let mut mesh = replayed.mesh;
        if let Some(pose) = body.pose {
            mesh.transform(pose).map_err(|e| bad(&format!("body \"{}\": pose: {e}", body.name)))?;
        }
        shown.push(Shown { name: base.name, mesh, colour: base.colour, changes: base.changes });
    }
    if scene_bases.peek().is_some() || !pieces.is_empty() {
        return Err(mismatch(file.bodies.iter().map(|b| b.name.as_str()).collect()));
    }
    let meshes_dir = args.out.join("meshes");
    std::fs::create_dir_all(&meshes_dir).map_err(|source| CliError::CreateDir { path: meshes_dir.clone(), source })?;
    let frame = u32::try_from(recorded.frame).map_err(|_| bad(&"frame beyond u32"))?;
    let written = write_meshes(&shown, frame, args.meshes, &meshes_dir)?;
    let dents = file.dents();
    let per_dent =
        if dents > 0 { format!("{:.0} bytes/dent", bytes.len() as f64 / dents as f64) } else { "no dents".into() };
    Ok(format!(
        "replay {}: {} bodies, {dents} dents ({} bytes, {per_dent}), frame {frame}: {written} mesh files → {}",
        recorded.spec,
        shown.len(),
        bytes.len(),
        args.out.display()
    ))
}

/// The file's bytes, refused past [`DamageFile::MAX_FILE_BYTES`] before reading them.
fn read_bounded(path: &std::path::Path) -> Result<Vec<u8>, String> {
    let file = std::fs::File::open(path).map_err(|e| format!("cannot open: {e}"))?;
    let mut bytes = Vec::new();
    file.take(DamageFile::MAX_FILE_BYTES + 1).read_to_end(&mut bytes).map_err(|e| format!("cannot read: {e}"))?;
    if bytes.len() as u64 > DamageFile::MAX_FILE_BYTES {
        return Err(format!("larger than {} bytes, the most a damage file may have", DamageFile::MAX_FILE_BYTES));
    }
    Ok(bytes)
}

/// A body of the scene as `run` shows it, at the start.
struct Base {
    name: String,
    mesh: TriMesh,
    colour: [f32; 3],
    changes: bool,
}

/// The scene's shown bodies at the start, in the order `run` lists them: the world's bodies but
/// sub-bodies and cluster stand-ins (their own meshes), then the bending bodies (rest meshes).
fn base_meshes(scene: &dentbend_solver::scene::Scene) -> Vec<Base> {
    let bodies = scene.world.bodies();
    let owners = scene.bending.owners(bodies.len());
    let mut out: Vec<Base> = (bodies.iter().enumerate())
        .filter(|(k, b)| owners[*k].is_none() && !b.is_cluster_proxy())
        .map(|(_, b)| Base { name: b.name.clone(), mesh: b.mesh().clone(), colour: b.color, changes: b.dent.is_some() })
        .collect();
    out.extend(scene.bending.bodies().iter().map(|b| Base {
        name: b.name().to_owned(),
        mesh: b.rest_mesh().clone(),
        colour: b.color(),
        changes: true,
    }));
    out
}
