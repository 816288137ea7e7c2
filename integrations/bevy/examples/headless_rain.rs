//! Balls rain on a dentable block and the bunny, rendered without a window (lavapipe works):
//! `cargo +nightly run --release -p bevy_dentbend --ignore-rust-version --example headless_rain --
//! --frames N --out DIR` writes `DIR/frame_<n>.png` and `DIR/summary.json`.
//!
//! Flags: `--cpu` (every dent on the CPU path), `--no-dents` (the same rain, nothing dents: the
//! baseline frame time), `--size WxH` (default 640x360), `--balls-per-frame F` (default 0.5).

use std::path::PathBuf;
use std::process::ExitCode;

use bevy::prelude::*;
use bevy_dentbend::demo::{CapturePlugin, Captured, FrameClock, RainPlugin, RainSettings, Summary, headless_app};
use bevy_dentbend::{DentGpu, DentStats};

struct Args {
    frames: u32,
    out: PathBuf,
    gpu: bool,
    dents: bool,
    size: UVec2,
    balls_per_frame: f32,
}

fn parse() -> Result<Args, String> {
    let mut args = Args {
        frames: 120,
        out: PathBuf::from("out/headless_rain"),
        gpu: true,
        dents: true,
        size: UVec2::new(640, 360),
        balls_per_frame: 0.5,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = |name: &str| it.next().ok_or(format!("{name} needs a value"));
        match flag.as_str() {
            "--frames" => args.frames = value("--frames")?.parse().map_err(|e| format!("--frames: {e}"))?,
            "--out" => args.out = PathBuf::from(value("--out")?),
            "--cpu" => args.gpu = false,
            "--no-dents" => args.dents = false,
            "--size" => {
                let v = value("--size")?;
                let (w, h) = v.split_once('x').ok_or("--size takes WxH, e.g. 640x360")?;
                let parse = |s: &str| s.parse::<u32>().map_err(|e| format!("--size: {e}"));
                args.size = UVec2::new(parse(w)?, parse(h)?);
            }
            "--balls-per-frame" => {
                args.balls_per_frame =
                    value("--balls-per-frame")?.parse().map_err(|e| format!("--balls-per-frame: {e}"))?;
            }
            "--help" | "-h" => {
                return Err("usage: headless_rain [--frames N] [--out DIR] [--cpu] [--no-dents] [--size WxH] [--balls-per-frame F]".into());
            }
            other => return Err(format!("unknown flag {other} (try --help)")),
        }
    }
    if args.frames == 0 || args.size.x == 0 || args.size.y == 0 || args.size.max_element() > 8192 {
        return Err("--frames and --size must be positive (at most 8192 pixels a side)".into());
    }
    if !(args.balls_per_frame.is_finite() && (0.0..=64.0).contains(&args.balls_per_frame)) {
        return Err("--balls-per-frame must be in 0..=64".into());
    }
    Ok(args)
}

/// Frames past `--frames` allowed for the last captures to be written.
const DRAIN_FRAMES: u32 = 600;

fn main() -> ExitCode {
    let args = match parse() {
        Ok(args) => args,
        Err(e) => {
            eprintln!("headless_rain: {e}");
            return ExitCode::from(2);
        }
    };
    if let Err(e) = std::fs::create_dir_all(&args.out) {
        eprintln!("headless_rain: cannot create {}: {e}", args.out.display());
        return ExitCode::from(1);
    }
    let mut app = headless_app(args.gpu);
    app.insert_resource(RainSettings { dents: args.dents, balls_per_frame: args.balls_per_frame, ..default() })
        .add_plugins(RainPlugin)
        .add_plugins(CapturePlugin { size: args.size, out: Some(args.out.clone()), keep: false })
        .insert_resource(Run { frames: args.frames, out: args.out.clone(), dents: args.dents })
        .add_systems(Last, finish);
    match app.run() {
        AppExit::Success => ExitCode::SUCCESS,
        AppExit::Error(code) => ExitCode::from(code.get()),
    }
}

#[derive(Resource)]
struct Run {
    frames: u32,
    out: PathBuf,
    dents: bool,
}

/// After `--frames` frames: stop capturing, wait for the last PNG files, write the summary.
fn finish(
    run: Res<Run>,
    clock: Res<FrameClock>,
    captured: Res<Captured>,
    stats: Res<DentStats>,
    gpu: Res<DentGpu>,
    mut capture: ResMut<bevy_dentbend::demo::Capture>,
    mut exit: MessageWriter<AppExit>,
) {
    if clock.frame <= run.frames {
        return;
    }
    capture.enabled = false;
    let drained = captured.all_done();
    if !drained && clock.frame <= run.frames + DRAIN_FRAMES {
        return;
    }
    let mut timed = clock.clone();
    timed.frame_ms.truncate(run.frames.saturating_sub(1) as usize);
    timed.frame = run.frames;
    let summary = Summary::new(&timed, &stats, gpu.status(), run.dents, captured.readback_bytes());
    let path = run.out.join("summary.json");
    let text = serde_json::to_string_pretty(&summary.to_json()).unwrap_or_default();
    match std::fs::write(&path, text + "\n") {
        Ok(()) => println!("{}", serde_json::to_string(&summary.to_json()).unwrap_or_default()),
        Err(e) => {
            eprintln!("headless_rain: cannot write {}: {e}", path.display());
            exit.write(AppExit::from_code(1));
            return;
        }
    }
    if !drained {
        eprintln!("headless_rain: {} frame(s) were not captured in time", run.frames.saturating_sub(captured.done()));
        exit.write(AppExit::from_code(1));
        return;
    }
    exit.write(AppExit::Success);
}
