//! `dentbend demo`: the README's pictures and meshes, made by running the other subcommands.
//! Each step prints the command line that reproduces it.

use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

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

/// The demo's steps: a caption for the gallery and a command line, where `{out}` is replaced by
/// the output directory. A step without a caption continues the one before (a render of the
/// mesh that step made): the gallery shows both commands under the first one's caption.
const STEPS: &[(&str, &str)] = &[
    (
        "Paper Figure 7: the bunny's Z-buffer profile, Gaussian envelope and smoothed dent map",
        "dentmap --projectile bunny --normal 0,1,0 --dent-distance 3 --sigma 0.3 --res 200 --out {out}/fig07_bunny",
    ),
    (
        "Paper Figure 2c: a ball dents a block head-on; the far face bulges a little",
        "dent --target block-fine --projectile sphere --translate 0,1.5,0 --point 0,0.5,0 --normal 0,-1,0 \
         --dent-distance 0.3 --out {out}/block_sphere.obj",
    ),
    ("", "render --mesh {out}/block_sphere.obj --zoom 1.5 --out {out}/block_sphere.png"),
    (
        "Paper Figure 5: a bunny-shaped dent, the bunny dropped ears first",
        "dent --target block-fine --projectile bunny --scale 0.25 --rotate 180,0,0 --translate 0.35,2.95,0.1 \
         --point 0,0.5,0 --normal 0,-1,0 --dent-distance 0.6 --sigma 0.08 --out {out}/block_bunny.obj",
    ),
    ("", "render --mesh {out}/block_bunny.obj --view -0.3,-1,-0.6 --zoom 1.8 --out {out}/block_bunny.png"),
    (
        "Paper Figures 8–9: a glancing hit at 50°, sheared along the velocity and widened",
        "dent --target block-fine --projectile sphere --scale 0.6 --translate -0.46,1.09,0 --point 0,0.5,0 \
         --normal 0,-1,0 --velocity 0.766,-0.643,0 --dent-distance 0.3 --widen 3 --out {out}/block_glancing.obj",
    ),
    ("", "render --mesh {out}/block_glancing.obj --zoom 1.5 --out {out}/block_glancing.png"),
    (
        "A 12-triangle crate takes a ball's dent: refined under the dent first, its volume kept by a rim",
        "dent --target crate --projectile sphere --scale 0.5 --translate 0.3,1.5,0.2 --point 0.3,1,0.2 \
         --normal 0,-1,0 --dent-distance 0.15 --preserve-volume --out {out}/crate.obj",
    ),
    ("", "render --mesh {out}/crate.obj --view -0.5,-1,-0.7 --zoom 1.2 --out {out}/crate.png"),
    (
        "Paper Figure 1: two dentable balls dent each other symmetrically (Jacobi)",
        "dent --target sphere --projectile sphere --translate 0,2.05,0 --point 0,1,0 --normal 0,-1,0 \
         --dent-distance 0.3 --out {out}/pair_lower.obj --projectile-out {out}/pair_upper.obj",
    ),
    (
        "",
        "render --mesh {out}/pair_lower.obj --mesh {out}/pair_upper.obj --view 0,-0.35,-1 --size 640,800 \
         --out {out}/pair.png",
    ),
    (
        "Scene `pair` (Figure 1): two balls fly at each other and keep their dents",
        "run pair --size demo --out {out}/scenes/pair --every 30 --meshes dentable",
    ),
    (
        "Scene `ball-block` (Figure 2): balls dent blocks with different falloffs",
        "run ball-block --size demo --out {out}/scenes/ball-block --every 30 --meshes dentable",
    ),
    (
        "Scene `bunny-block` (Figure 5): bunnies dent blocks",
        "run bunny-block --size demo --out {out}/scenes/bunny-block --every 30 --meshes dentable",
    ),
    (
        "Scene `glancing` (Figure 8): glancing hits leave sheared dents",
        "run glancing --size demo --out {out}/scenes/glancing --every 30 --meshes dentable",
    ),
    (
        "Scene `resolution` (Figure 11): one hit at four dent-map resolutions",
        "run resolution --size demo --out {out}/scenes/resolution --every 30 --meshes dentable",
    ),
    (
        "Scene `rain` (Figure 10): objects rain on dentable targets",
        "run rain --size demo --out {out}/scenes/rain --every 40 --meshes dentable",
    ),
    (
        "Scene `plank` (Figure 14): a joint appears where the ball hits the plank, and it bends",
        "run plank --size demo --out {out}/scenes/plank --every 15 --meshes dentable",
    ),
    (
        "Scene `spring`: an elastic joint bends and springs back",
        "run spring --size demo --out {out}/scenes/spring --every 30 --meshes dentable",
    ),
    (
        "Scene `bunny-bones` (Figure 12): the bunny's four bones, sub-bodies and level set",
        "run bunny-bones --size demo --out {out}/scenes/bunny-bones --every 30 --meshes dentable",
    ),
    (
        "Scene `tetrahedra` (Figure 13): tetrahedra fall and their struts bend",
        "run tetrahedra --size demo --out {out}/scenes/tetrahedra --every 30 --meshes dentable",
    ),
    (
        "Scene `arm` (Figure 15): an arm bends at four joints after a hit",
        "run arm --size demo --out {out}/scenes/arm --every 30 --meshes dentable",
    ),
    (
        "Scene `wall` (Figure 3): balls dent a prescored wall over time, then it breaks",
        "run wall --size demo --out {out}/scenes/wall --every 20 --meshes frame",
    ),
    (
        "The wall's damage replayed from its damage.json to the same meshes, byte for byte",
        "replay {out}/scenes/wall/damage.json --out {out}/scenes/wall-replay",
    ),
];

/// Runs every step; returns the summary line and the warnings raised along the way.
pub fn run(args: &DemoArgs) -> Result<(String, Vec<String>), CliError> {
    std::fs::create_dir_all(&args.out).map_err(|source| CliError::CreateDir { path: args.out.clone(), source })?;
    let mut warnings = Vec::new();
    let mut made: Vec<Step> = Vec::new();
    for &(caption, step) in STEPS {
        let mut line = step.replace("{out}", &display(&args.out));
        line = line.split_whitespace().collect::<Vec<_>>().join(" ");
        if let Some(flag) = args.backend.flag() {
            line = format!("{line} {flag}");
        }
        println!("$ dentbend {line}");
        let argv = std::iter::once("dentbend").chain(line.split_whitespace());
        let cli = crate::Cli::try_parse_from(argv).map_err(|e| CliError::Usage(format!("demo step `{line}`: {e}")))?;
        let started = SystemTime::now();
        let (summary, step_warnings) = crate::execute(&cli.command)?;
        println!("  {summary}");
        warnings.extend(step_warnings);
        let pictures = pictures_written(&line, &args.out, started);
        let command = format!("dentbend {line}");
        match made.last_mut() {
            Some(previous) if caption.is_empty() => {
                previous.commands.push(command);
                previous.pictures.extend(pictures);
            }
            _ => made.push(Step { caption, commands: vec![command], pictures }),
        }
    }
    let gallery = write_gallery(&args.out, &made)?;
    Ok((format!("demo: {} steps → {} (gallery: {})", STEPS.len(), display(&args.out), display(&gallery)), warnings))
}

/// One step as the gallery shows it.
struct Step {
    caption: &'static str,
    /// The command lines, in order.
    commands: Vec<String>,
    /// PNG files the step wrote, relative to the demo's folder, `/`-separated.
    pictures: Vec<String>,
}

/// The PNG files a step's `--out` (a `.png` file or a folder) holds that were written since
/// `started`: the gallery shows this run's pictures only, never stale ones from an earlier run.
fn pictures_written(line: &str, root: &Path, started: SystemTime) -> Vec<String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let Some(out) = words.windows(2).rev().find(|w| w[0] == "--out").map(|w| PathBuf::from(w[1])) else {
        return Vec::new();
    };
    let mut found = Vec::new();
    collect_pngs(&out, &mut found);
    // File systems with coarse timestamps (FAT: 2 s) round a fresh file's time down.
    let since = started.checked_sub(Duration::from_secs(2)).unwrap_or(started);
    let fresh = |path: &PathBuf| std::fs::metadata(path).and_then(|m| m.modified()).is_ok_and(|t| t >= since);
    let mut pictures: Vec<String> = found
        .iter()
        .filter(|p| fresh(p))
        .filter_map(|p| p.strip_prefix(root).ok())
        .map(|p| p.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/"))
        .collect();
    pictures.sort();
    pictures
}

/// Writes `DIR/gallery.html`: each step's caption, the command that made it and its pictures.
fn write_gallery(out: &Path, steps: &[Step]) -> Result<PathBuf, CliError> {
    let mut html = String::from(
        "<!doctype html><meta charset=utf-8><title>dentbend demo</title>\n<style>body{font-family:sans-serif}\
         figure{display:inline-block;margin:6px}img{width:320px}code{display:block;white-space:pre-wrap;\
         background:#f4f4f4;padding:4px}</style>\n<h1>dentbend demo</h1>\n",
    );
    for step in steps.iter().filter(|s| !s.pictures.is_empty()) {
        let commands = step.commands.iter().map(|c| escape(c)).collect::<Vec<_>>().join("\n");
        html.push_str(&format!("<h2>{}</h2>\n<code>{commands}</code>\n", escape(step.caption)));
        for picture in &step.pictures {
            let name = escape(picture);
            html.push_str(&format!(
                "<figure><img src=\"{name}\" alt=\"{name}\"><figcaption>{name}</figcaption></figure>\n"
            ));
        }
    }
    let path = out.join("gallery.html");
    write_text(&path, &html)?;
    Ok(path)
}

/// `text` with the characters HTML gives a meaning escaped.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// The PNG files at `path` (a file) or under it (a folder).
fn collect_pngs(path: &Path, found: &mut Vec<PathBuf>) {
    if path.is_file() {
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
            found.push(path.to_path_buf());
        }
        return;
    }
    let Ok(entries) = std::fs::read_dir(path) else { return };
    for entry in entries.flatten() {
        collect_pngs(&entry.path(), found);
    }
}

fn display(path: &Path) -> String {
    path.display().to_string()
}
