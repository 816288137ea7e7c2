//! Criterion benches of the geometry half of bending (paper §4) on the bunny subdivided to
//! 58,784 triangles (the paper's had 34,000) with a four-bone skeleton whose head bone pokes out
//! of the neck: level set, skinning weights (from scratch and with the cache), re-weighting after
//! a bone split, and sub-bodies. Run with `cargo bench --bench bend`.

use criterion::{Criterion, criterion_group, criterion_main};
use dentbend::TriMesh;
use dentbend::bend::{LevelSet, SkinWeights, SubBodies, WeightCache, WeightParams, bunny_skeleton};
use dentbend::glam::Vec3;
use dentbend::mesh;

/// The bunny, midpoint-subdivided twice: 58,784 triangles, 29,394 vertices.
fn dense_bunny() -> TriMesh {
    mesh::subdivide_midpoint_n(&mesh::load("bunny").expect("built-in bunny"), 2)
}

fn bend(c: &mut Criterion) {
    let bunny = dense_bunny();
    // Body, head (leaving the body behind the neck, as in the paper's Figure 12) and two ears.
    let skeleton = bunny_skeleton(1.0).expect("bunny skeleton");
    let params = WeightParams::default();
    let mut group = c.benchmark_group("bend");
    group.sample_size(30);

    group.bench_function("level_set_64", |b| b.iter(|| LevelSet::build(&bunny, params.resolution).unwrap()));
    group.bench_function("weights_from_scratch", |b| {
        b.iter(|| {
            let cache = WeightCache::new(&bunny, params).unwrap();
            SkinWeights::compute(&bunny, &skeleton, &cache).unwrap()
        })
    });
    let cache = WeightCache::new(&bunny, params).unwrap();
    group.bench_function("weights_cached", |b| b.iter(|| SkinWeights::compute(&bunny, &skeleton, &cache).unwrap()));

    let weights = SkinWeights::compute(&bunny, &skeleton, &cache).unwrap();
    let mut split = skeleton.clone();
    // A hit on the body bone's middle.
    let (first, second) = split.split_bone(0, Vec3::new(1.25, 4.05, 0.8)).unwrap();
    group.bench_function("after_split", |b| {
        b.iter(|| weights.after_split(&bunny, &split, 0, (first, second), &cache).unwrap())
    });
    let after = weights.after_split(&bunny, &split, 0, (first, second), &cache).unwrap();
    group.bench_function("sub_bodies", |b| {
        b.iter(|| SubBodies::compute(&bunny, &after, cache.level_set(), 1000.0).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bend);
criterion_main!(benches);
