//! `dentbend dentmap`: the dent map a projectile leaves, with every stage written out.

use std::fs;
use std::path::{Path, PathBuf};

use clap::Args;
use dentbend::dent::{DentFrame, DentStages, Grid, dent_map_stages};
use dentbend::glam::Vec3;
use dentbend::io::{write_heatmap_png, write_npy_f32};
use dentbend::{DentParams, Impact, Resolution, TriMesh};
use serde::Serialize;

use crate::backend::{BackendOption, gpu_stages};
use crate::error::CliError;
use crate::options::{MapOptions, ProjectileOptions, nonzero, sig3};
use crate::output::write_json;
use crate::vector::parse_vec3;

/// Arguments of `dentbend dentmap`.
#[derive(Debug, Args)]
#[command(after_help = "\
The projectile is used in its file's coordinates, after --rotate and --translate. The dent is \
taken at its most advanced vertex along the viewing direction (the velocity, θ clamped by \
--min-cos), which is also the Z-buffer grid's origin.

Writes to DIR: zbuffer.npy, envelope.npy, smoothed.npy (f32, shape (res, res), [row][col]); \
dentmap.npy (f32, shape (res_d, res_d, 3): displacement vectors in the projectile's coordinates); \
a heat-map PNG of each (the first three on a common scale 0..d, dentmap.png of the displacement \
length); and dentmap.json with the parameters used and both grids.")]
pub struct DentmapArgs {
    #[command(flatten)]
    pub projectile: ProjectileOptions,

    /// Denting normal: the direction the dent is pushed in, into the target
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true, default_value = "0,0,1")]
    pub normal: Vec3,

    /// Velocity of the projectile relative to the target; its angle to the normal is θ
    /// [default: the normal, head-on]
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub velocity: Option<Vec3>,

    #[command(flatten)]
    pub map: MapOptions,

    #[command(flatten)]
    pub backend: BackendOption,

    /// Output directory (created if missing)
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

/// Runs the command; returns the summary line.
pub fn run(args: &DentmapArgs) -> Result<String, CliError> {
    let params = args.map.params()?;
    let normal = nonzero(args.normal, "--normal")?;
    let probe = Impact { point: Vec3::ZERO, normal, relative_velocity: args.velocity.unwrap_or(normal) };
    probe.validate()?;
    let projectile = args.projectile.load()?;
    let impact = at_tip(&projectile, probe, &params);
    let stages = match args.backend.context()? {
        Some(context) => gpu_stages(context, &projectile, &impact, &params)?,
        None => dent_map_stages(&projectile, &impact, &params, None)?,
    };
    write_outputs(&args.out, &stages, &Metadata::new(args, &params, &impact, &stages))?;
    let res = stages.zbuffer_grid.res;
    Ok(format!(
        "dentmap: {}, {res}×{res} cells of {}, θ = {:.1}°, σ = {} → {} (4 .npy, 4 .png, dentmap.json)",
        args.projectile.projectile,
        sig3(stages.zbuffer_grid.cell_size),
        stages.frame.theta_deg(),
        sig3(stages.sigma),
        display_dir(&args.out),
    ))
}

/// `probe` moved to the projectile's most advanced vertex along the (clamped) viewing direction.
fn at_tip(projectile: &TriMesh, probe: Impact, params: &DentParams) -> Impact {
    let view = DentFrame::new(&probe, params.min_cos).view();
    Impact { point: projectile.support_point(view), ..probe }
}

/// Everything `dentmap.json` records; lengths in the projectile's units, f32 values written
/// in their shortest exact form.
#[derive(Serialize)]
struct Metadata<'a> {
    projectile: &'a str,
    rotate_deg: Vec3,
    translate: Vec3,
    normal: Vec3,
    velocity: Vec3,
    impact_point: Vec3,
    dent_distance: f32,
    sigma: f32,
    heat_iters: u32,
    clamp_iters: u32,
    heat_rate: f32,
    widen: f32,
    min_cos: f32,
    /// `"auto"` or `"fixed"`; the sides chosen are in the grids.
    resolution: &'static str,
    theta_deg: f32,
    max_displacement: f32,
    zbuffer_grid: Grid,
    dentmap_grid: Grid,
}

impl<'a> Metadata<'a> {
    fn new(args: &'a DentmapArgs, params: &DentParams, impact: &Impact, stages: &DentStages) -> Self {
        Self {
            projectile: &args.projectile.projectile,
            rotate_deg: args.projectile.rotate_deg(),
            translate: args.projectile.translation(),
            normal: impact.normal,
            velocity: impact.relative_velocity,
            impact_point: impact.point,
            dent_distance: params.dent_distance,
            sigma: stages.sigma,
            heat_iters: params.heat_iters,
            clamp_iters: params.clamp_iters,
            heat_rate: params.heat_rate,
            widen: params.widen,
            min_cos: params.min_cos,
            resolution: match params.resolution {
                Resolution::Fixed(_) => "fixed",
                Resolution::Auto { .. } => "auto",
            },
            theta_deg: stages.frame.theta_deg(),
            max_displacement: stages.map.max_displacement(),
            zbuffer_grid: stages.zbuffer_grid,
            dentmap_grid: stages.map.grid,
        }
    }
}

/// Writes the four arrays, their heat maps and the JSON into `dir`.
fn write_outputs(dir: &Path, stages: &DentStages, metadata: &Metadata) -> Result<(), CliError> {
    fs::create_dir_all(dir).map_err(|source| CliError::CreateDir { path: dir.to_owned(), source })?;
    let d = stages.map.dent_distance;
    let res = stages.zbuffer_grid.res;
    let side = res as usize;
    for (name, values) in [("zbuffer", &stages.zbuffer), ("envelope", &stages.envelope), ("smoothed", &stages.smoothed)]
    {
        write_npy_f32(dir.join(format!("{name}.npy")), &[side, side], values)?;
        write_heatmap_png(dir.join(format!("{name}.png")), values, res, res, d)?;
    }
    let map = &stages.map;
    let map_res = map.grid.res;
    let vectors: Vec<f32> = map.cells.iter().flat_map(|c| [c[0], c[1], c[2]]).collect();
    let lengths: Vec<f32> = map.cells.iter().map(|&[x, y, z, _]| Vec3::new(x, y, z).length()).collect();
    write_npy_f32(dir.join("dentmap.npy"), &[map_res as usize, map_res as usize, 3], &vectors)?;
    write_heatmap_png(dir.join("dentmap.png"), &lengths, map_res, map_res, d.max(map.max_displacement()))?;
    write_json(&dir.join("dentmap.json"), metadata)
}

/// `dir/` for the summary line.
fn display_dir(dir: &Path) -> String {
    let text = dir.display().to_string();
    if text.ends_with(std::path::MAIN_SEPARATOR) { text } else { format!("{text}{}", std::path::MAIN_SEPARATOR) }
}
