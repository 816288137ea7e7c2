//! What the game-proof stages cost together: one CPU dent on
//! `block-fine` as the paper makes it (no refinement, volume free, no intersection guard) and
//! with every stage on (refinement auto, volume kept, guard on), head-on and glancing at 60°,
//! in the same run. The budget: the stages add at most 30 % to a dent.
//! Run with `cargo bench --bench dent_game`.

use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use dentbend::dent::Refine;
use dentbend::glam::{Affine3A, Vec3};
use dentbend::{DentParams, Impact, VolumeMode, dent, mesh};

fn dent_game(c: &mut Criterion) {
    let block = mesh::builtin("block-fine").expect("block-fine");
    let mut ball = mesh::builtin("sphere").expect("sphere");
    // A ball of radius 0.25 m resting on the top face (y = 0.5) above the origin.
    let placement = Affine3A::from_scale_rotation_translation(Vec3::splat(0.25), Default::default(), Vec3::Y * 0.75);
    ball.transform(placement).expect("place ball");
    let head_on = Vec3::new(0.0, -1.0, 0.0);
    let glancing = Vec3::new(60f32.to_radians().sin(), -60f32.to_radians().cos(), 0.0);
    // d = 0.06 m: 30 % of the ball's radius, the size of dent the soak benchmark makes.
    let paper =
        DentParams { refine: Refine::Off, volume: VolumeMode::Free, guard_crossings: false, ..DentParams::new(0.06) };
    let game = DentParams { volume: VolumeMode::Preserve, ..DentParams::new(0.06) };
    for (name, velocity) in [("head-on", head_on), ("glancing-60", glancing)] {
        let impact = Impact { point: Vec3::new(0.0, 0.5, 0.0), normal: -Vec3::Y, relative_velocity: velocity };
        let mut group = c.benchmark_group(format!("dent_game/{name}"));
        for (setting, params) in [("paper", &paper), ("game", &game)] {
            group.bench_function(BenchmarkId::from_parameter(setting), |b| {
                b.iter_batched_ref(
                    || block.clone(),
                    |t| dent(t, &ball, &impact, params).expect("dent"),
                    BatchSize::LargeInput,
                )
            });
        }
        group.finish();
    }
}

criterion_group!(benches, dent_game);
criterion_main!(benches);
