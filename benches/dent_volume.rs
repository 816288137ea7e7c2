//! What volume preservation costs: one dent on `block-fine` (28,674
//! vertices, a ball of radius 0.4, d = 0.1) with `VolumeMode::Free` (the paper's dent; the
//! volume stage only measures the change) and with `Preserve` (measures and raises the rim), in
//! the same run; each iteration dents a fresh copy of the block (the copy is timed in both).
//! Run on one core with `RAYON_NUM_THREADS=1 cargo bench --bench dent_volume`.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use dentbend::glam::{Affine3A, Vec3};
use dentbend::{DentParams, Impact, VolumeMode, dent, mesh};

fn volume(c: &mut Criterion) {
    let block = mesh::builtin("block-fine").expect("block-fine");
    let top = block.support_point(Vec3::Y).y;
    let point = Vec3::new(0.3, top, -0.2);
    let mut ball = mesh::icosphere(0.4, 3).expect("ball");
    ball.transform(Affine3A::from_translation(point + Vec3::Y * 0.4)).expect("move ball");
    let impact = Impact::head_on(point, -Vec3::Y);
    let mut group = c.benchmark_group("dent_volume_block_fine");
    for (name, mode) in [("free", VolumeMode::Free), ("preserve", VolumeMode::Preserve)] {
        let params = DentParams { volume: mode, ..DentParams::new(0.1) };
        group.bench_function(name, |b| {
            b.iter_batched_ref(
                || block.clone(),
                |target| dent(target, &ball, &impact, &params).expect("dent"),
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

criterion_group!(benches, volume);
criterion_main!(benches);
