//! `dentbend run SCENE`: steps a built-in scene or a scene file with denting in the loop and
//! writes meshes (OBJ and glTF), PNG frames and `summary.json`, and once at the start the rest
//! state of every bending body (`rest/`: skeleton, sub-body and level-set pictures, sub-body
//! meshes).

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use dentbend::mesh::{GltfNode, TriMesh, save_glb_scene};
use dentbend_solver::coupling::{BendRecord, JointRecord};
use dentbend_solver::coupling::{DamageLog, Simulation, StepStats};
use dentbend_solver::render::{Renderer, Shaded};
use dentbend_solver::scene::{LoadOptions, MeshPaths, Scene, SceneSize, load_with};
use dentbend_solver::sim::DentRecord;
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;

use crate::backend::BackendOption;
use crate::damage_output::{DamageSummary, write_damage};
use crate::error::CliError;
use crate::file_names::{check_distinct_stems, file_stem};
use crate::options::SizeChoice;
use crate::output::{write_json, write_mesh, write_picture};
use crate::rest_output::write_rest_files;
use crate::run_budget::{self, BodyOutput, RunShape};
use crate::step_log::{LoggedSteps, StepLog};

/// Which meshes are written at each output frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MeshChoice {
    /// One binary glTF scene per output frame, `meshes/frame_<frame>.glb`, every body a named
    /// node with its colour.
    Frame,
    /// Every body in its own files, `meshes/<body>_<frame>.obj` and `.glb`.
    All,
    /// Like `all`, only the dentable and bending bodies (the ones whose shape changes).
    Dentable,
    /// No meshes.
    None,
}

/// Arguments of `dentbend run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// A built-in scene (pair, ball-block, bunny-block, glancing, resolution, rain, plank, spring,
    /// bunny-bones, tetrahedra, arm, wall) or a scene file (.toml)
    pub scene: String,

    /// Frames to run (one world step each, ≥ 1) [default: the scene's]
    #[arg(long, value_name = "N")]
    pub frames: Option<u32>,

    /// Output directory (created if missing): meshes/, frames/, rest/ (bending bodies' rest
    /// state), summary.json
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,

    /// Write meshes and pictures every K frames (and at the first and last)
    #[arg(long, value_name = "K", default_value_t = 10)]
    pub every: u32,

    /// Size of a built-in scene: the paper's (full) or a quick one (demo)
    #[arg(long, value_enum, default_value = "full")]
    pub size: SizeChoice,

    /// Which meshes to write at each output frame
    #[arg(long, value_enum, default_value = "frame")]
    pub meshes: MeshChoice,

    /// Picture size in pixels, WIDTH,HEIGHT (0,0 writes no pictures)
    #[arg(long, value_name = "W,H", value_parser = crate::cmd_render::parse_size, default_value = "960,640")]
    pub picture: (u32, u32),

    /// Go ahead with a run over the output budget (1 GB, 10,000 files, 10,000 bodies, 20
    /// million triangles), which is otherwise refused up front with its estimate
    #[arg(long)]
    pub allow_large: bool,

    /// Print what the run would write (bytes, files, output frames) and whether that is within
    /// the budget, then stop: nothing is run or written
    #[arg(long)]
    pub estimate: bool,

    /// Let a scene file's mesh paths leave its folder (absolute paths, `..`, symbolic links out);
    /// only for scene files you trust
    #[arg(long)]
    pub trust_paths: bool,

    #[command(flatten)]
    pub backend: BackendOption,
}

/// `summary.json`.
#[derive(Debug, Serialize)]
struct Summary<'a> {
    scene: &'a str,
    description: &'a str,
    frames: u32,
    dt: f32,
    bodies: Vec<&'a str>,
    dents_on: &'static str,
    /// Where the bending bodies are skinned: "gpu" (every step, timed in `steps[].skinning_ms`,
    /// read back for output frames only) or "cpu" (for output frames only).
    skin_on: &'static str,
    pictures_on: &'static str,
    ms_per_step: StepStats,
    steps: LoggedSteps<'a>,
    dents: Vec<DentEntry<'a>>,
    /// Joints made by dynamic articulation: frame, bending body, world position (m).
    joints: Vec<JointEntry<'a>>,
    /// Plastic bends: frame, joint index, angle (rad).
    bends: &'a [BendRecord],
    /// Fractures: frame, the body that broke, the pieces it broke into, and the record that
    /// replays it.
    fractures: Vec<FractureEntry<'a>>,
    /// Pictures of the bending bodies' rest state (skeleton, sub-bodies, level set), relative
    /// to the output directory.
    rest_pictures: &'a [String],
    /// The bending bodies' sub-body meshes at the start, relative to the output directory.
    rest_meshes: &'a [String],
    /// `damage.json`: its size and bytes per dent.
    damage: DamageSummary,
}

/// One joint of `summary.json`.
#[derive(Debug, Serialize)]
struct JointEntry<'a> {
    frame: u64,
    body: &'a str,
    position: [f32; 3],
    rest_position: [f32; 3],
    joint: usize,
    split_ms: f64,
}

impl<'a> From<&'a JointRecord> for JointEntry<'a> {
    fn from(r: &'a JointRecord) -> Self {
        Self {
            frame: r.frame,
            body: &r.body,
            position: r.position.to_array(),
            rest_position: r.rest_position.to_array(),
            joint: r.joint,
            split_ms: r.split_ms,
        }
    }
}

/// One dent of `summary.json`.
#[derive(Debug, Serialize)]
struct DentEntry<'a> {
    /// Frame after which the dent was made (1 = after the first step).
    frame: u64,
    #[serde(flatten)]
    record: &'a DentRecord,
}

/// One fracture of `summary.json`.
#[derive(Debug, Serialize)]
struct FractureEntry<'a> {
    /// Frame after which the body broke (1 = after the first step).
    frame: u64,
    #[serde(flatten)]
    event: &'a dentbend_solver::coupling::FractureEvent,
}

/// Runs the command; returns the summary line.
pub fn run(args: &RunArgs) -> Result<String, CliError> {
    if args.every == 0 {
        return Err(CliError::Usage("--every must be at least 1".into()));
    }
    if args.frames == Some(0) {
        return Err(CliError::Usage("--frames must be at least 1".into()));
    }
    let size = match args.size {
        SizeChoice::Full => SceneSize::Full,
        SizeChoice::Demo => SceneSize::Demo,
    };
    let mut options = LoadOptions::sized(size);
    if args.trust_paths {
        options.mesh_paths = MeshPaths::Trusted;
    }
    if args.allow_large {
        options = options.unlimited();
    }
    let scene = load_with(&args.scene, &options).map_err(|e| CliError::Usage(e.to_string()))?;
    let frames = args.frames.unwrap_or(scene.frames);
    let context = args.backend.context()?;
    let pictures = args.picture.0 > 0 && args.picture.1 > 0;
    let renderer = if pictures { Some(args.backend.renderer()?) } else { None };
    let Scene { name, world, camera, description, bending, .. } = scene;
    let sim = Simulation::new(world, context).map_err(|e| CliError::Usage(e.to_string()))?.with_bending(bending);
    // On the GPU, skin every step as a game would before drawing: the kernel's output stays
    // resident, only output frames read it back, and `skinning_ms` shows what the issue's
    // "every frame" costs. The CPU twin skins output frames only: nothing would read the
    // frames between them, and its time would land in the same loop as the dynamics.
    let every_step = sim.skins_on_gpu();
    let mut sim = sim.skin_every_step(every_step);
    // Everything is checked before the first file is written.
    let mut shown = Some(shown_meshes(&mut sim)?);
    let first = shown.as_deref().unwrap_or_default();
    check_distinct_stems(first.iter().map(|s| s.name.as_str())).map_err(CliError::Usage)?;
    let outputs: Vec<BodyOutput> = first.iter().map(|s| body_output(s, args.meshes)).collect();
    let shape = RunShape { frames, every: args.every, picture: args.picture };
    let estimate = run_budget::estimate(&shape, &outputs);
    if args.estimate {
        let verdict = match run_budget::check(&estimate, &outputs, false) {
            Ok(()) => "within the budget".to_owned(),
            Err(e) => e.one_line().replace("this run is too large: ", "over the budget: "),
        };
        return Ok(format!(
            "run {name}: would write about {} in {} files ({} output frames of {} bodies), {verdict}",
            run_budget::human_bytes(estimate.bytes),
            estimate.files,
            estimate.output_frames,
            outputs.len()
        ));
    }
    run_budget::check(&estimate, &outputs, args.allow_large)?;
    let meshes_dir = args.out.join("meshes");
    let frames_dir = args.out.join("frames");
    for dir in [&args.out, &meshes_dir, &frames_dir] {
        std::fs::create_dir_all(dir).map_err(|source| CliError::CreateDir { path: dir.clone(), source })?;
    }
    let writes_meshes = args.meshes != MeshChoice::None;
    let rest = write_rest_files(&sim, &camera, renderer.as_ref(), args.picture, writes_meshes, &args.out)?;
    let progress = progress_bar(&name, frames);
    let mut log = StepLog::create(&args.out)?;
    let mut damage = DamageLog::new(&sim);
    let mut written = 0usize;
    // Output frames need the shown bodies' world meshes only for files or pictures.
    let wanted = args.meshes != MeshChoice::None || renderer.is_some();
    for frame in 0..=frames {
        if wanted && (frame % args.every == 0 || frame == frames) {
            let shown = match shown.take() {
                Some(first) => first,
                None => shown_meshes(&mut sim)?,
            };
            written += write_meshes(&shown, frame, args.meshes, &meshes_dir)?;
            if let Some(renderer) = &renderer {
                draw(&shown, renderer, &camera, args.picture, &frames_dir.join(format!("{frame:04}.png")))?;
            }
        }
        if frame == frames {
            break;
        }
        let (timing, _) = sim.step().map_err(|e| CliError::Usage(format!("frame {}: {e}", frame + 1)))?;
        log.push(&timing)?;
        damage.after_step(&sim).map_err(|e| CliError::Usage(format!("frame {}: recording damage: {e}", frame + 1)))?;
        progress.set_message(format!("{} dents", sim.dents().len()));
        progress.inc(1);
    }
    progress.finish_and_clear();
    let damage = write_damage(&damage, &mut sim, &args.scene, args.size, frames, &args.out)?;
    let ms = log.stats();
    let summary = Summary {
        scene: &name,
        description: &description,
        frames,
        dt: sim.world().settings().dt,
        bodies: shown_bodies(&sim).map(|(_, b)| b.name.as_str()).chain(bending_names(&sim)).collect(),
        dents_on: if sim.dents_on_gpu() { "gpu" } else { "cpu" },
        skin_on: if sim.skins_on_gpu() { "gpu" } else { "cpu" },
        pictures_on: match &renderer {
            Some(r) if r.is_gpu() => "gpu",
            Some(_) => "cpu",
            None => "none",
        },
        ms_per_step: ms,
        steps: log.steps()?,
        dents: sim.dents().iter().map(|record| DentEntry { frame: record.step, record }).collect(),
        joints: sim.bending().joints().iter().map(JointEntry::from).collect(),
        bends: sim.bending().bends(),
        fractures: sim.fractures().iter().map(|event| FractureEntry { frame: event.step, event }).collect(),
        rest_pictures: &rest.pictures,
        rest_meshes: &rest.meshes,
        damage,
    };
    write_json(&args.out.join("summary.json"), &summary)?;
    Ok(format!(
        "run {name}: {frames} frames, {} dents, {} joints, {} plastic bends, {:.2} ms/step ({:.2} dynamics + {:.2} denting{}), {written} mesh files{}, damage.json {} bytes ({}) → {}",
        sim.dents().len(),
        sim.bending().joints().len(),
        sim.bending().bends().len(),
        ms.total_mean,
        ms.dynamics_mean,
        ms.denting_mean,
        if every_step && !sim.bending().is_empty() {
            format!(" + {:.2} skinning", ms.skinning_mean)
        } else {
            String::new()
        },
        match rest.pictures.len() + rest.meshes.len() {
            0 => String::new(),
            n => format!(", {n} rest-state files"),
        },
        summary.damage.bytes,
        match summary.damage.bytes_per_dent {
            Some(b) => format!("{b:.0} bytes/dent"),
            None => "no dents".to_owned(),
        },
        args.out.display()
    ))
}

/// The progress bar on stderr (hidden when stderr is not a terminal).
fn progress_bar(name: &str, frames: u32) -> ProgressBar {
    let progress = ProgressBar::new(u64::from(frames));
    progress.set_style(
        ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} frames, {msg} ({elapsed} / ~{duration})")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    progress.set_prefix(name.to_owned());
    progress
}

/// What `choice` writes of one shown body at each output frame.
fn body_output(shown: &Shown, choice: MeshChoice) -> BodyOutput {
    BodyOutput {
        vertices: shown.mesh.vertex_count(),
        triangles: shown.mesh.face_count(),
        own_files: choice == MeshChoice::All || (choice == MeshChoice::Dentable && shown.changes),
        in_frame_scene: choice == MeshChoice::Frame,
        changes: shown.changes,
    }
}

/// The world's bodies but the sub-bodies of bending bodies and the stand-ins of rigid clusters,
/// with their indices.
fn shown_bodies(sim: &Simulation) -> impl Iterator<Item = (usize, &dentbend_solver::sim::RigidBody)> {
    let owners = sim.bending().owners(sim.world().bodies().len());
    sim.world().bodies().iter().enumerate().filter(move |(k, b)| owners[*k].is_none() && !b.is_cluster_proxy())
}

/// The bending bodies' names.
fn bending_names(sim: &Simulation) -> impl Iterator<Item = &str> {
    sim.bending().bodies().iter().map(|b| b.name())
}

/// A body as shown: name, world mesh, colour, and whether its shape changes (dentable or bending).
pub struct Shown {
    /// The body's name.
    pub name: String,
    /// Its mesh, world coordinates.
    pub mesh: TriMesh,
    /// Its colour, linear RGB.
    pub colour: [f32; 3],
    /// Whether its shape changes (dentable or bending).
    pub changes: bool,
}

/// Every body to show now, world coordinates: the world's bodies but the sub-bodies of bending
/// bodies, then each bending body's skinned mesh (from the simulation's skinner: read back from
/// the GPU, or skinned now on the CPU).
fn shown_meshes(sim: &mut Simulation) -> Result<Vec<Shown>, CliError> {
    let mut meshes: Vec<Shown> = shown_bodies(sim)
        .map(|(_, b)| Shown { name: b.name.clone(), mesh: b.world_mesh(), colour: b.color, changes: b.dent.is_some() })
        .collect();
    let skinned = sim.skinned_meshes().map_err(|e| CliError::Usage(e.to_string()))?;
    meshes.extend(skinned.into_iter().map(|(name, mesh, colour)| Shown { name, mesh, colour, changes: true }));
    Ok(meshes)
}

/// Writes the output frame's meshes (world coordinates; a bending body's skinned mesh under its
/// own name, its sub-bodies not at all): `meshes/frame_<frame>.glb` for `frame`, or
/// `meshes/<body>_<frame>.obj` and `.glb` for `all` and `dentable`; returns the file count.
pub fn write_meshes(shown: &[Shown], frame: u32, choice: MeshChoice, dir: &Path) -> Result<usize, CliError> {
    match choice {
        MeshChoice::None => Ok(0),
        MeshChoice::Frame => {
            let nodes: Vec<GltfNode> = shown
                .iter()
                .map(|s| GltfNode { color: s.colour.map(|c| c.clamp(0.0, 1.0)), ..GltfNode::new(&s.name, &s.mesh) })
                .collect();
            let path = dir.join(format!("frame_{frame:04}.glb"));
            save_glb_scene(&path, &nodes).map_err(|source| CliError::Save { path, source })?;
            Ok(1)
        }
        MeshChoice::All | MeshChoice::Dentable => {
            let mut count = 0;
            for Shown { name, mesh, changes, .. } in shown {
                if choice == MeshChoice::Dentable && !changes {
                    continue;
                }
                for extension in ["obj", "glb"] {
                    write_mesh(&dir.join(format!("{}_{frame:04}.{extension}", file_stem(name))), mesh)?;
                    count += 1;
                }
            }
            Ok(count)
        }
    }
}

/// Draws the shown bodies from the scene's camera into `path`.
fn draw(
    shown: &[Shown],
    renderer: &Renderer<'_>,
    camera: &dentbend_solver::render::Camera,
    (width, height): (u32, u32),
    path: &Path,
) -> Result<(), CliError> {
    let shaded: Vec<Shaded> = shown.iter().map(|s| Shaded { mesh: &s.mesh, colour: s.colour }).collect();
    let picture = renderer.render(&shaded, camera, width, height).map_err(|e| CliError::Usage(e.to_string()))?;
    write_picture(path, &picture)
}
