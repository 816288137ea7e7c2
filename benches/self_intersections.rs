//! The self-intersection check on the bunny, and one dent on `block-fine` with
//! and without the intersection guard (the guard's share of a dent's cost).
//! Run with `cargo bench --bench self_intersections`.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use dentbend::glam::{Affine3A, Vec3};
use dentbend::{DentParams, Impact, dent, mesh};

fn check(c: &mut Criterion) {
    for name in ["bunny", "bunny-dense", "block-fine"] {
        let m = mesh::builtin(name).expect("built-in");
        c.bench_function(&format!("self_intersections/{name}"), |b| b.iter(|| m.self_intersections()));
    }
}

fn dent_with_and_without_guard(c: &mut Criterion) {
    let block = mesh::builtin("block-fine").expect("block-fine");
    let mut ball = mesh::icosphere(0.15, 2).expect("ball");
    ball.transform(Affine3A::from_translation(Vec3::new(0.3, 0.65, -0.2))).expect("move ball");
    let impact =
        Impact { point: Vec3::new(0.3, 0.5, -0.2), normal: -Vec3::Y, relative_velocity: Vec3::new(0.3, -1.0, 0.1) };
    for (label, guard) in [("without_guard", false), ("with_guard", true)] {
        let params = DentParams { guard_crossings: guard, ..DentParams::new(0.15) };
        c.bench_function(&format!("dent_block_fine/{label}"), |b| {
            b.iter_batched(
                || block.clone(),
                |mut target| dent(&mut target, &ball, &impact, &params).expect("dent"),
                BatchSize::LargeInput,
            )
        });
    }
}

criterion_group!(benches, check, dent_with_and_without_guard);
criterion_main!(benches);
