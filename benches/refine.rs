//! The refine stage's cost: one CPU dent on `block-fine` (fine already:
//! refinement auto should add nothing and cost little) and on a 12-triangle 2 m cube (refined
//! to about 800 triangles under the dent), each with refinement auto and off, same run.
//! Run with `cargo bench --bench refine`.

use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use dentbend::dent::Refine;
use dentbend::glam::{Affine3A, Vec3};
use dentbend::{DentParams, Impact, TriMesh, dent, mesh};

/// A 2 m cube centred at the origin: 8 vertices, 12 triangles.
fn cube() -> TriMesh {
    let corners: Vec<Vec3> =
        (0..8).map(|k| Vec3::new([-1., 1.][k & 1], [-1., 1.][(k >> 1) & 1], [-1., 1.][k >> 2])).collect();
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let faces: Vec<[u32; 3]> = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
    TriMesh::new(corners, faces).expect("cube")
}

/// The built-in sphere scaled by `scale`, resting on the plane y = `top` above the origin.
fn ball(scale: f32, top: f32) -> TriMesh {
    let mut ball = mesh::builtin("sphere").expect("sphere");
    let placement = Affine3A::from_scale_rotation_translation(
        Vec3::splat(scale),
        Default::default(),
        Vec3::new(0.0, top + scale, 0.0),
    );
    ball.transform(placement).expect("place ball");
    ball
}

fn refine(c: &mut Criterion) {
    let scenes = [
        ("block-fine", mesh::builtin("block-fine").expect("block-fine"), ball(1.0, 0.5), 0.5, 0.1),
        ("cube12", cube(), ball(0.5, 1.0), 1.0, 0.1),
    ];
    for (name, target, projectile, top, d) in &scenes {
        let impact = Impact { point: Vec3::new(0.0, *top, 0.0), normal: -Vec3::Y, relative_velocity: -Vec3::Y };
        let mut group = c.benchmark_group(format!("dent_refine/{name}"));
        for (setting, refine) in [("auto", Refine::default()), ("off", Refine::Off)] {
            let params = DentParams { refine, ..DentParams::new(*d) };
            let mut once = target.clone();
            let report = dent(&mut once, projectile, &impact, &params).expect("dent");
            eprintln!("{name} {setting}: +{} triangles, moved {}", report.refined_triangles, report.moved_vertices);
            group.bench_function(BenchmarkId::from_parameter(setting), |b| {
                b.iter_batched_ref(
                    || target.clone(),
                    |t| dent(t, projectile, &impact, &params).expect("dent"),
                    BatchSize::LargeInput,
                )
            });
        }
        group.finish();
    }
}

criterion_group!(benches, refine);
criterion_main!(benches);
