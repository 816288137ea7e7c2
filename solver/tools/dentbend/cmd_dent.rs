//! `dentbend dent`: dents a target mesh where a projectile hits it and saves it, with its
//! attributes (UVs, normals, groups, materials, glTF vertex data), as OBJ or glTF.

use std::fs;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use dentbend::dent::Refine;
use dentbend::glam::Vec3;
use dentbend::mesh::Asset;
use dentbend::{Attenuation, Impact, MeshError, TriMesh, VolumeMode, mesh};

use crate::backend::{BackendChoice, BackendOption, dent_pair_or_one};
use crate::error::{CliError, flag_error};
use crate::impacts;
use crate::options::{MapOptions, ProjectileOptions, nonzero, parse_refine, sig3};
use crate::output::require_extension;
use crate::vector::parse_vec3;

/// How the dent fades with depth z below the collision plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Falloff {
    /// a(z) = 2 / (1 + e^(z/d)), the paper's: the far side of a thin wall bulges
    Logistic,
    /// a(z) = max(0, 1 − z / (scale·d)), scale from --falloff-scale
    Linear,
    /// a(z) = 1: the whole target moves with the dent map
    None,
}

/// Arguments of `dentbend dent`.
#[derive(Debug, Args)]
#[command(after_help = "\
Both meshes are in the same coordinates, placed as at the moment of impact; --scale, --rotate, \
then --translate place the projectile first (a built-in one, say). With --projectile-out both \
bodies dent each other: both maps come from the undented meshes (Jacobi, paper Figure 1). \
The dent is measured from the projectile's most advanced point along the viewing direction (the \
velocity, θ clamped by --min-cos), wherever the projectile is, and that point is placed on \
--point: the dent map is centred there.")]
pub struct DentArgs {
    /// Target mesh to dent: an .obj, .ply, .gltf or .glb path, or a built-in name (its UVs,
    /// normals, groups, materials and glTF vertex attributes follow the dent)
    #[arg(long, value_name = "MESH")]
    pub target: String,

    #[command(flatten)]
    pub projectile: ProjectileOptions,

    /// Contact point, mesh units
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true,
          required_unless_present = "impacts", conflicts_with = "impacts")]
    pub point: Option<Vec3>,

    /// Denting normal at the contact, pointing into the target
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true,
          required_unless_present = "impacts", conflicts_with = "impacts")]
    pub normal: Option<Vec3>,

    /// Velocity of the projectile relative to the target; its angle to the normal is θ
    /// [default: the normal, head-on]
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true,
          conflicts_with = "impacts")]
    pub velocity: Option<Vec3>,

    /// Many impacts in one call, instead of --point, --normal and --velocity: a JSON list of
    /// {"point": [x,y,z], "normal": [x,y,z]} entries, each with an optional "velocity",
    /// "depth" (else --dent-distance) and projectile pose ("scale", "rotate" in degrees,
    /// "translate", after the command line's), dented as one batch on the CPU
    #[arg(long, value_name = "FILE.json", conflicts_with = "projectile_out")]
    pub impacts: Option<PathBuf>,

    #[command(flatten)]
    pub map: MapOptions,

    #[command(flatten)]
    pub backend: BackendOption,

    /// Falloff of the dent with depth into the target
    #[arg(long, value_enum, default_value_t = Falloff::Logistic)]
    pub falloff: Falloff,

    /// Depth at which the linear falloff reaches zero, in dent distances (> 0; below 1 it is
    /// steep enough to fold thin walls) [default: 1]
    #[arg(long, value_name = "SCALE", allow_negative_numbers = true)]
    pub falloff_scale: Option<f32>,

    /// Refine the target's triangles under the dent first, so a coarse mesh takes the dent's
    /// shape: auto (where the map needs finer triangles, at most 20,000 new ones), off, or a
    /// maximum edge length, mesh units
    #[arg(long, value_name = "auto|off|MAX_EDGE", default_value = "auto", value_parser = parse_refine, allow_negative_numbers = true)]
    pub refine: Refine,

    /// Keep the target's volume: raise a rim around the crater that puts back the volume the
    /// dent takes (within 2 % of it)
    #[arg(long)]
    pub preserve_volume: bool,

    /// Output file, .obj (with vt, vn, groups and materials) or .glb (with every glTF vertex
    /// attribute); not written if anything fails
    #[arg(long, value_name = "OUT.obj|OUT.glb")]
    pub out: PathBuf,

    /// Also dent the projectile by the target (same parameters) and save it here as OBJ
    #[arg(long, value_name = "OUT.obj")]
    pub projectile_out: Option<PathBuf>,
}

/// Runs the command; returns the summary line and the warnings raised.
pub fn run(args: &DentArgs) -> Result<(String, Vec<String>), CliError> {
    let mut params = args.map.params()?;
    params.attenuation = match (args.falloff, args.falloff_scale) {
        (Falloff::Linear, scale) => Attenuation::Linear { scale: scale.unwrap_or(1.0) },
        (_, Some(_)) => {
            return Err(CliError::Usage("--falloff-scale only applies to --falloff linear".into()));
        }
        (Falloff::Logistic, None) => Attenuation::Logistic,
        (Falloff::None, None) => Attenuation::None,
    };
    params.refine = args.refine;
    if args.preserve_volume {
        params.volume = VolumeMode::Preserve;
    }
    params.validate().map_err(flag_error)?;
    require_extension(&args.out, "--out", &["obj", "glb"])?;
    if let Some(path) = &args.projectile_out {
        require_extension(path, "--projectile-out", &["obj"])?;
    }
    if let Some(path) = &args.impacts {
        return run_impacts(args, path, &params);
    }
    let (Some(point), Some(normal)) = (args.point, args.normal) else {
        return Err(CliError::Usage("give --point and --normal, or --impacts".into()));
    };
    let normal = nonzero(normal, "--normal")?;
    let impact = Impact { point, normal, relative_velocity: args.velocity.unwrap_or(normal) };
    impact.validate()?;
    let mut asset = mesh::load_asset(&args.target).map_err(|source| CliError::Load {
        role: "target",
        spec: args.target.clone(),
        source,
    })?;
    let mut projectile = args.projectile.load()?;
    if let Some(path) = &args.projectile_out
        && same_file(path, &args.out)
    {
        return Err(CliError::Usage("--projectile-out must differ from --out".into()));
    }
    let gpu = args.backend.context()?;
    let mut target = asset.mesh().clone();
    let mutual = args.projectile_out.is_some();
    let dent = dent_pair_or_one(gpu, &mut target, &mut projectile, &impact, &params, mutual)?;
    asset
        .follow_dent(target, &dent.refinement, &dent.moved)
        .map_err(|source| CliError::Save { path: args.out.clone(), source })?;
    // Both files are written aside first, and only put in place once both are.
    let staged = stage(&Output::Asset(&asset), &args.out)?;
    match &args.projectile_out {
        None => staged.commit()?,
        Some(path) => {
            let staged = [staged, stage(&Output::Mesh(&projectile), path)?];
            staged.into_iter().try_for_each(Staged::commit)?;
        }
    }
    let report = dent.report;
    let target = asset.mesh();
    let refined = match report.refined_triangles {
        0 => String::new(),
        n => format!(", refined first: +{n} triangles, +{} vertices", report.refined_vertices),
    };
    let summary = format!(
        "dent: moved {} of {} vertices of {} by up to {} (θ = {:.1}°, {res}×{res} cells{refined}, volume change {} of a {} cavity) → {}",
        report.moved_vertices,
        target.vertex_count(),
        args.target,
        sig3(report.max_displacement),
        report.theta_deg,
        sig3(report.volume_change as f32),
        sig3(report.cavity_volume as f32),
        args.out.display(),
        res = report.resolution,
    );
    let mut warnings = report.warnings;
    if report.moved_vertices == 0 {
        warnings.push("the dent moved no vertex of the target: does the projectile touch it near --point?".into());
    }
    Ok((summary, warnings))
}

/// `dent --impacts`: every impact of the file on the target, as one batch.
fn run_impacts(args: &DentArgs, path: &Path, params: &dentbend::DentParams) -> Result<(String, Vec<String>), CliError> {
    if args.backend.backend == Some(BackendChoice::Gpu) {
        return Err(CliError::Usage("--impacts dents on the CPU, as one batch: drop --backend gpu".into()));
    }
    let mut asset = mesh::load_asset(&args.target).map_err(|source| CliError::Load {
        role: "target",
        spec: args.target.clone(),
        source,
    })?;
    let projectile = args.projectile.load()?;
    let planned = impacts::read(path, params, &projectile)?;
    let (dented, outcome) = impacts::dent_all(asset.mesh(), &projectile, &planned)?;
    let refinement = outcome.refined.first().cloned().unwrap_or_default();
    let moved = outcome.moved.first().cloned().unwrap_or_default();
    asset
        .follow_dent(dented, &refinement, &moved)
        .map_err(|source| CliError::Save { path: args.out.clone(), source })?;
    stage(&Output::Asset(&asset), &args.out)?.commit()?;
    let deepest = outcome.reports.iter().map(|r| r.max_displacement).fold(0.0, f32::max);
    let summary = format!(
        "dent: {} impacts moved {} of {} vertices of {} by up to {} (+{} vertices refined) → {}",
        planned.len(),
        moved.len(),
        asset.mesh().vertex_count(),
        args.target,
        sig3(deepest),
        refinement.vertices.len(),
        args.out.display(),
    );
    let mut warnings: Vec<String> = outcome
        .reports
        .iter()
        .enumerate()
        .flat_map(|(k, r)| r.warnings.iter().map(move |w| format!("impact {k}: {w}")))
        .collect();
    let idle = outcome.reports.iter().filter(|r| r.moved_vertices == 0).count();
    if idle > 0 {
        warnings.push(format!(
            "{idle} of the impacts moved no vertex: do their projectiles touch the target near their points?"
        ));
    }
    Ok((summary, warnings))
}

/// True when `a` and `b` name the same file (compared through their canonical directories).
fn same_file(a: &Path, b: &Path) -> bool {
    let canonical = |p: &Path| {
        let parent = p.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
        parent.canonicalize().ok().map(|dir| dir.join(p.file_name().unwrap_or_default()))
    };
    a == b || matches!((canonical(a), canonical(b)), (Some(x), Some(y)) if x == y)
}

/// An OBJ written beside its destination, not yet renamed into place; removed if dropped.
struct Staged {
    temp: PathBuf,
    path: PathBuf,
}

impl Staged {
    /// Renames the file into place.
    fn commit(self) -> Result<(), CliError> {
        let result =
            fs::rename(&self.temp, &self.path).map_err(|source| CliError::Write { path: self.path.clone(), source });
        drop(self); // removes the temporary file if the rename failed
        result
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        let _ = fs::remove_file(&self.temp);
    }
}

/// What to write: the dented target with its attributes, or a plain mesh as OBJ.
enum Output<'a> {
    Asset(&'a Asset),
    Mesh(&'a TriMesh),
}

/// Writes `output` to a temporary file beside `path` (in the format its extension names), so
/// that a failure leaves neither a partial file nor a damaged earlier one.
fn stage(output: &Output<'_>, path: &Path) -> Result<Staged, CliError> {
    crate::output::prepare_file(path)?;
    let stem = path.file_stem().map_or_else(|| "out".into(), |s| s.to_string_lossy());
    let extension = path.extension().map_or_else(|| "obj".into(), |e| e.to_string_lossy());
    let temp = path.with_file_name(format!(".{stem}.dentbend-{}.{extension}", std::process::id()));
    let staged = Staged { temp, path: path.to_owned() };
    let saved = match output {
        Output::Asset(asset) => mesh::save_asset(&staged.temp, asset),
        Output::Mesh(mesh) => mesh::save(&staged.temp, mesh),
    };
    match saved {
        Ok(()) => Ok(staged),
        Err(MeshError::Io { source, .. }) => Err(CliError::Write { path: path.to_owned(), source }),
        Err(source) => Err(CliError::Save { path: path.to_owned(), source }),
    }
}
