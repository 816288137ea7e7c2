//! `dentbend demo`: the README's pictures and meshes, made by running the other subcommands.
//! Each step prints the command line that reproduces it.

use std::path::{Path, PathBuf};

use clap::{Args, Parser};

use crate::backend::BackendOption;
use crate::error::CliError;
use crate::output::write_text;

/// Arguments of `dentbend demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Output directory (created if missing)
    #[arg(long, value_name = "DIR", default_value = "out")]
    pub out: PathBuf,

    // Passed on to every step as given; each step otherwise follows $DENTBEND_BACKEND, else cpu.
    #[command(flatten)]
    pub backend: BackendOption,
}

/// The demo's steps as command lines; `{out}` is replaced by the output directory.
const STEPS: &[&str] = &[
    // Paper Figure 7: the bunny's Z-buffer profile, Gaussian envelope and smoothed dent map.
    "dentmap --projectile bunny --normal 0,1,0 --dent-distance 3 --sigma 0.3 --res 200 --out {out}/fig07_bunny",
    // Paper Figure 2c: a ball dents a block head-on; the far face bulges a little.
    "dent --target block-fine --projectile sphere --translate 0,1.5,0 --point 0,0.5,0 --normal 0,-1,0 \
     --dent-distance 0.3 --out {out}/block_sphere.obj",
    "render --mesh {out}/block_sphere.obj --zoom 1.5 --out {out}/block_sphere.png",
    // Paper Figure 5: a bunny-shaped dent, the bunny dropped ears first.
    "dent --target block-fine --projectile bunny --scale 0.25 --rotate 180,0,0 --translate 0.35,2.95,0.1 \
     --point 0,0.5,0 --normal 0,-1,0 --dent-distance 0.6 --sigma 0.08 --out {out}/block_bunny.obj",
    "render --mesh {out}/block_bunny.obj --view -0.3,-1,-0.6 --zoom 1.8 --out {out}/block_bunny.png",
    // Paper Figures 8–9: a glancing hit at 50°, sheared along the velocity and widened.
    "dent --target block-fine --projectile sphere --scale 0.6 --translate -0.46,1.09,0 --point 0,0.5,0 \
     --normal 0,-1,0 --velocity 0.766,-0.643,0 --dent-distance 0.3 --widen 3 --out {out}/block_glancing.obj",
    "render --mesh {out}/block_glancing.obj --zoom 1.5 --out {out}/block_glancing.png",
    // Paper Figure 1: two dentable balls dent each other symmetrically (Jacobi).
    "dent --target sphere --projectile sphere --translate 0,2.05,0 --point 0,1,0 --normal 0,-1,0 \
     --dent-distance 0.3 --out {out}/pair_lower.obj --projectile-out {out}/pair_upper.obj",
    "render --mesh {out}/pair_lower.obj --mesh {out}/pair_upper.obj --view 0,-0.35,-1 --size 640,800 \
     --out {out}/pair.png",
    // The built-in scenes, small: bodies fly, collide and keep their dents (Figures 1, 2, 5, 8, 11, 10).
    "run pair --size demo --out {out}/scenes/pair --every 30 --meshes dentable",
    "run ball-block --size demo --out {out}/scenes/ball-block --every 30 --meshes dentable",
    "run bunny-block --size demo --out {out}/scenes/bunny-block --every 30 --meshes dentable",
    "run glancing --size demo --out {out}/scenes/glancing --every 30 --meshes dentable",
    "run resolution --size demo --out {out}/scenes/resolution --every 30 --meshes dentable",
    "run rain --size demo --out {out}/scenes/rain --every 40 --meshes dentable",
    // The bending scenes, small: a joint appears where the ball hits the plank (Figure 14), an
    // elastic joint springs back, the bunny's four bones (Figure 12), tetrahedra whose struts
    // bend (Figure 13), an arm that bends at four joints after a hit (Figure 15).
    "run plank --size demo --out {out}/scenes/plank --every 15 --meshes dentable",
    "run spring --size demo --out {out}/scenes/spring --every 30 --meshes dentable",
    "run bunny-bones --size demo --out {out}/scenes/bunny-bones --every 30 --meshes dentable",
    "run tetrahedra --size demo --out {out}/scenes/tetrahedra --every 30 --meshes dentable",
    "run arm --size demo --out {out}/scenes/arm --every 30 --meshes dentable",
];

/// Runs every step; returns the summary line and the warnings raised along the way.
pub fn run(args: &DemoArgs) -> Result<(String, Vec<String>), CliError> {
    std::fs::create_dir_all(&args.out).map_err(|source| CliError::CreateDir { path: args.out.clone(), source })?;
    let mut warnings = Vec::new();
    for step in STEPS {
        let mut line = step.replace("{out}", &display(&args.out));
        if let Some(flag) = args.backend.flag() {
            line = format!("{line} {flag}");
        }
        println!("$ dentbend {line}");
        let argv = std::iter::once("dentbend").chain(line.split_whitespace());
        let cli = crate::Cli::try_parse_from(argv).map_err(|e| CliError::Usage(format!("demo step `{line}`: {e}")))?;
        let (summary, step_warnings) = crate::execute(&cli.command)?;
        println!("  {summary}");
        warnings.extend(step_warnings);
    }
    let gallery = write_gallery(&args.out)?;
    Ok((format!("demo: {} steps → {} (gallery: {})", STEPS.len(), display(&args.out), display(&gallery)), warnings))
}

/// Writes `DIR/gallery.html`: every PNG under `DIR`, grouped by folder.
fn write_gallery(out: &Path) -> Result<PathBuf, CliError> {
    let mut pictures = Vec::new();
    collect_pngs(out, out, &mut pictures);
    pictures.sort();
    let mut html = String::from(
        "<!doctype html><meta charset=utf-8><title>dentbend demo</title>\n<style>body{font-family:sans-serif}\
         figure{display:inline-block;margin:6px}img{width:320px}</style>\n<h1>dentbend demo</h1>\n",
    );
    for picture in &pictures {
        html.push_str(&format!("<figure><img src=\"{picture}\"><figcaption>{picture}</figcaption></figure>\n"));
    }
    let path = out.join("gallery.html");
    write_text(&path, &html)?;
    Ok(path)
}

/// Paths (relative to `root`, `/`-separated) of the PNG files under `dir`.
fn collect_pngs(root: &Path, dir: &Path, found: &mut Vec<String>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect_pngs(root, &path, found);
        } else if path.extension().is_some_and(|e| e == "png")
            && let Ok(relative) = path.strip_prefix(root)
        {
            found.push(relative.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/"));
        }
    }
}

fn display(path: &Path) -> String {
    path.display().to_string()
}
