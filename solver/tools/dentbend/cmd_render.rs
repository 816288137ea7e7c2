//! `dentbend render`: a shaded picture of one or more meshes (CPU rasterizer, or the GPU
//! renderer with `--backend gpu|auto`).

use std::path::PathBuf;

use clap::Args;
use dentbend::glam::Vec3;
use dentbend_solver::render::{Camera, Shaded};

use crate::backend::BackendOption;
use crate::error::CliError;
use crate::options::{load_mesh, nonzero};
use crate::output::{prepare_file, require_extension, write_picture};
use crate::vector::parse_vec3;

/// Colours given to the meshes in order (linear RGB): steel, copper, sage, plum.
const PALETTE: [[f32; 3]; 4] = [[0.42, 0.48, 0.58], [0.80, 0.36, 0.16], [0.38, 0.55, 0.35], [0.55, 0.32, 0.55]];

/// Arguments of `dentbend render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Mesh to draw: an .obj or .ply path, or a built-in name; repeat for several
    #[arg(long = "mesh", value_name = "MESH", required = true)]
    pub meshes: Vec<String>,

    /// Viewing direction, from the camera towards the scene
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true, default_value = "-0.45,-0.75,-1")]
    pub view: Vec3,

    /// Up direction of the picture
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true, default_value = "0,1,0")]
    pub up: Vec3,

    /// Zoom factor: 1 frames the meshes' bounding sphere, 2 shows half as much around its centre
    #[arg(long, value_name = "Z", default_value_t = 1.0)]
    pub zoom: f32,

    /// Picture size in pixels, WIDTH,HEIGHT
    #[arg(long, value_name = "W,H", value_parser = parse_size, default_value = "960,640")]
    pub size: (u32, u32),

    /// Output PNG file
    #[arg(long, value_name = "PIC.png")]
    pub out: PathBuf,

    #[command(flatten)]
    pub backend: BackendOption,
}

/// Runs the command; returns the summary line.
pub fn run(args: &RenderArgs) -> Result<String, CliError> {
    let view = nonzero(args.view, "--view")?;
    let up = nonzero(args.up, "--up")?;
    if view.cross(up).length_squared() < 1e-12 {
        return Err(CliError::Usage("--up must not be parallel to --view".into()));
    }
    if !(args.zoom.is_finite() && args.zoom > 0.0) {
        return Err(CliError::Usage(format!("--zoom {} is out of range: it must be finite and > 0", args.zoom)));
    }
    require_extension(&args.out, "--out", &["png"])?;
    let (width, height) = args.size;
    let meshes = args.meshes.iter().map(|spec| load_mesh("mesh", spec)).collect::<Result<Vec<_>, _>>()?;
    let bounds = meshes
        .iter()
        .map(|m| m.bounds())
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), (a, b)| (lo.min(a), hi.max(b)));
    let mut camera = Camera::framing(bounds, view, up);
    camera.eye = camera.target + (camera.eye - camera.target) / args.zoom;
    let shaded: Vec<Shaded> =
        meshes.iter().zip(PALETTE.iter().cycle()).map(|(mesh, &colour)| Shaded { mesh, colour }).collect();
    let renderer = args.backend.renderer()?;
    let picture = renderer.render(&shaded, &camera, width, height).map_err(|e| CliError::Usage(e.to_string()))?;
    prepare_file(&args.out)?;
    write_picture(&args.out, &picture)?;
    Ok(format!("render: {} mesh(es), {width}×{height} → {}", meshes.len(), args.out.display()))
}

/// Largest picture side, pixels.
const MAX_SIDE: u32 = 16_384;
/// Largest picture, pixels (8192 × 8192: 200 MB of colour, as much again of depth).
const MAX_PIXELS: u64 = 1 << 26;

/// Parses `W,H` (two whole numbers, each at most 16384, together at most 8192 × 8192 pixels).
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let (w, h) = match parts.as_slice() {
        [w, h] => match (w.parse::<u32>(), h.parse::<u32>()) {
            (Ok(w), Ok(h)) => (w, h),
            _ => return Err(format!("expected two whole numbers W,H, got '{text}'")),
        },
        _ => return Err(format!("expected W,H, got '{text}'")),
    };
    if w > MAX_SIDE || h > MAX_SIDE || u64::from(w) * u64::from(h) > MAX_PIXELS {
        return Err(format!(
            "{w}×{h} pixels is too large: each side may be at most {MAX_SIDE} and the picture at most {} megapixels",
            MAX_PIXELS >> 20
        ));
    }
    Ok((w, h))
}
