//! Balls rain on a dentable block and the bunny, rendered without a window (lavapipe works):
//! `cargo +nightly run --release -p bevy_dentbend --ignore-rust-version --example headless_rain --
//! --frames N --out DIR` writes `DIR/frame_<n>.png` and `DIR/summary.json`.
//!
//! Flags: `--cpu` (every dent on the CPU path), `--no-dents` (the same rain, nothing dents: the
//! baseline frame time), `--size WxH` (default 640x360), `--balls-per-frame F` (default 0.5),
//! `--no-png` (render every frame, write none), `--no-wall` (no breakable wall and no dents on the
//! plank: by default a wrecking ball breaks a wall behind the block, counted in `summary.json`'s
//! `fractures` and `pieces`, a ball splits a bone of the bendable plank, `splits`, and balls dent
//! it, `bendable_dents`), `--physics rapier|avian` (the engine: bevy_rapier3d by default, or
//! Avian 0.8 with the `avian` feature; the plank bends, splits and dents on either).
//!
//! Throughput: `--burst N` stops the rain and instead writes N contacts a frame on the block
//! through the contact hook (a hidden ball landing at 3 m/s at random points: one batch of N
//! dents a frame), `--resolution R` fixes the dents' Z-buffer side (default 100 with
//! `--burst`); `summary.json` then has `dents_per_second` (dents made from the first burst frame
//! to the last, over that wall time) and the batch size.

use std::path::PathBuf;
use std::process::ExitCode;

use bevy::prelude::*;
use bevy::render::RenderPlugin;
use std::time::Instant;

use bevy::math::{Affine3A, Mat3};
use bevy_dentbend::demo::{
    Capture, CapturePlugin, Captured, FrameClock, Physics, RainPlugin, RainSettings, Summary, Target, headless_app_with,
};
use bevy_dentbend::dentbend::dent::{BodyState, MAX_RESOLUTION};
use bevy_dentbend::{DentBody, DentContact, DentGpu, DentProjectile, DentStats, DentWorld, bevy_mesh};

struct Args {
    frames: u32,
    out: PathBuf,
    gpu: bool,
    dents: bool,
    size: UVec2,
    balls_per_frame: f32,
    png: bool,
    burst: u32,
    resolution: Option<u32>,
    wall: bool,
    physics: Physics,
}

fn parse() -> Result<Args, String> {
    let mut args = Args {
        frames: 120,
        out: PathBuf::from("out/headless_rain"),
        gpu: true,
        dents: true,
        size: UVec2::new(640, 360),
        balls_per_frame: 0.5,
        png: true,
        burst: 0,
        resolution: None,
        wall: true,
        physics: Physics::default(),
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
            "--no-png" => args.png = false,
            "--no-wall" => args.wall = false,
            "--physics" => args.physics = Physics::from_name(&value("--physics")?)?,
            "--burst" => args.burst = value("--burst")?.parse().map_err(|e| format!("--burst: {e}"))?,
            "--resolution" => {
                args.resolution = Some(value("--resolution")?.parse().map_err(|e| format!("--resolution: {e}"))?);
            }
            "--help" | "-h" => {
                return Err("usage: headless_rain [--frames N] [--out DIR] [--cpu] [--no-dents] [--size WxH] \
                            [--balls-per-frame F] [--no-png] [--no-wall] [--physics rapier|avian] [--burst N] \
                            [--resolution R]"
                    .into());
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
    if args.burst > MAX_BURST {
        return Err(format!("--burst must be at most {MAX_BURST}"));
    }
    if args.resolution.is_some_and(|r| !(8..=MAX_RESOLUTION).contains(&r)) {
        return Err(format!("--resolution must be in 8..={MAX_RESOLUTION}"));
    }
    if args.burst > 0 {
        args.balls_per_frame = 0.0;
        args.resolution = args.resolution.or(Some(100));
    }
    // A burst measures the GPU path's throughput: no CPU-path wall in it.
    args.wall &= args.burst == 0;
    Ok(args)
}

/// Most contacts a burst frame writes.
const MAX_BURST: u32 = 65_536;

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
    let mut app = headless_app_with(args.gpu, RenderPlugin::default(), args.physics);
    let rain = RainSettings {
        dents: args.dents,
        balls_per_frame: args.balls_per_frame,
        resolution: args.resolution,
        wall: args.wall,
        dent_plank: args.wall,
        ..default()
    };
    app.insert_resource(rain)
        .add_plugins(RainPlugin)
        .add_plugins(CapturePlugin { size: args.size, out: Some(args.out.clone()), keep: false })
        .insert_resource(Run {
            frames: args.frames,
            physics: args.physics,
            out: args.out.clone(),
            dents: args.dents,
            burst: args.burst,
            resolution: args.resolution,
            burst_started: None,
            written: 0,
            rng: 1,
        })
        .add_systems(Startup, spawn_burst_ball)
        .add_systems(Update, burst)
        .add_systems(Last, finish);
    if !args.png {
        app.world_mut().resource_mut::<Capture>().enabled = false;
    }
    match app.run() {
        AppExit::Success => ExitCode::SUCCESS,
        AppExit::Error(code) => ExitCode::from(code.get()),
    }
}

#[derive(Resource)]
struct Run {
    frames: u32,
    physics: Physics,
    out: PathBuf,
    dents: bool,
    burst: u32,
    resolution: Option<u32>,
    /// When the first burst was written, and the dents made and contacts rejected before it.
    burst_started: Option<(Instant, u64, u64)>,
    /// Contacts the bursts wrote.
    written: u64,
    /// The bursts' random stream (a linear congruential generator's state).
    rng: u64,
}

/// A hidden ball for the burst's contacts.
#[derive(Component)]
struct BurstBall;

/// `--burst`: the hidden ball whose contacts the bursts write.
fn spawn_burst_ball(mut commands: Commands, run: Res<Run>, mut meshes: ResMut<Assets<Mesh>>) {
    if run.burst > 0 {
        let sphere = meshes.add(bevy_mesh(&dentbend::mesh::icosphere(BURST_BALL, 2).expect("a valid sphere")));
        commands.spawn((BurstBall, DentProjectile, Mesh3d(sphere), Transform::default(), Visibility::Hidden));
    }
}

/// `--burst N`: N contacts of the hidden ball on the block each frame, at random points.
fn burst(
    mut run: ResMut<Run>,
    targets: Query<(Entity, &Target, &GlobalTransform)>,
    ball: Query<Entity, With<BurstBall>>,
    world: Res<DentWorld>,
    stats: Res<DentStats>,
    clock: Res<FrameClock>,
    mut contacts: MessageWriter<DentContact>,
) {
    if run.burst == 0 || clock.frame > run.frames {
        return;
    }
    let Ok(ball) = ball.single() else { return };
    let Some((block, _, transform)) = targets.iter().find(|(_, t, _)| **t == Target::Block) else { return };
    // Both bodies known to the plug-in (and the block on its path) before the clock starts.
    if world.path(block).is_none() || world.surface(ball).is_none() {
        return;
    }
    run.burst_started.get_or_insert((Instant::now(), stats.dents, stats.rejected_contacts));
    run.written += u64::from(run.burst);
    let top = transform.translation().y + 0.5;
    let inertia = Mat3::from_diagonal(Vec3::splat(1.0 / (0.4 * BURST_BALL * BURST_BALL)));
    for _ in 0..run.burst {
        let mut unit = || {
            run.rng = run.rng.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (run.rng >> 40) as f32 / (1u64 << 24) as f32
        };
        let point = Vec3::new(-1.8 + 3.6 * unit(), top, -1.8 + 3.6 * unit());
        let centre = point + Vec3::Y * BURST_BALL;
        let state = BodyState::moving(centre, Vec3::new(0.0, -BURST_SPEED, 0.0), Vec3::ZERO, 1.0, inertia);
        contacts.write(DentContact {
            a: DentBody { entity: block, pose: transform.affine(), state: BodyState::FIXED },
            b: DentBody { entity: ball, pose: Affine3A::from_translation(centre), state },
            point,
            normal: Vec3::Y,
            started: true,
        });
    }
}

/// The burst's ball radius, m, and speed, m/s (8 mm dents in the block).
const BURST_BALL: f32 = 0.12;
const BURST_SPEED: f32 = 3.0;

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
    let burst_done = run
        .burst_started
        .is_none_or(|(_, dents, rejected)| stats.dents + stats.rejected_contacts >= dents + rejected + run.written);
    if !burst_done && clock.frame <= run.frames + DRAIN_FRAMES {
        // The last bursts are still on their way through the render world.
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
    let mut json = summary.to_json();
    json["physics"] = run.physics.name().into();
    if run.burst > 0 {
        // Dents made from the first burst until the last one was made (seen a frame later).
        let (rate, seconds) = match run.burst_started {
            Some((at, dents, _)) => {
                let seconds = at.elapsed().as_secs_f64();
                ((stats.dents - dents) as f64 / seconds.max(1e-9), seconds)
            }
            None => (0.0, 0.0),
        };
        json["burst"] = run.burst.into();
        json["resolution"] = run.resolution.unwrap_or(0).into();
        json["dents_per_second"] = rate.into();
        json["burst_seconds"] = seconds.into();
    }
    let path = run.out.join("summary.json");
    let text = serde_json::to_string_pretty(&json).unwrap_or_default();
    match std::fs::write(&path, text + "\n") {
        Ok(()) => println!("{}", serde_json::to_string(&json).unwrap_or_default()),
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
