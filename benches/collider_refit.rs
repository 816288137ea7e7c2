//! Collider refits after a dent on a 25,000-triangle target: dentbend's refit
//! against parry3d's `set_vertices` and a rebuild, and a whole CPU dent plus refit.
//! Run on one core with `RAYON_NUM_THREADS=1 cargo bench --bench collider_refit`.

use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use dentbend::collider::refit_trimesh;
use dentbend::dent::moved_vertices;
use dentbend::glam::{Affine3A, Vec3};
use dentbend::{DentParams, Impact, TriMesh, dent, mesh};
use parry3d::shape::{TriMesh as ParryMesh, TriMeshFlags};

/// A unit UV sphere of 24,960 triangles and a ball of radius 0.2 resting on its top.
fn scene() -> (TriMesh, TriMesh, Impact, DentParams) {
    let target = mesh::uv_sphere(1.0, 160, 79).expect("target");
    let mut ball = mesh::icosphere(0.2, 3).expect("ball");
    ball.transform(Affine3A::from_translation(Vec3::new(0.0, 1.2, 0.0))).expect("move ball");
    let impact = Impact { point: Vec3::Y, normal: -Vec3::Y, relative_velocity: -Vec3::Y };
    (target, ball, impact, DentParams::new(0.05))
}

/// Flag sets: dentbend's world collider (pseudo-normals) and a bare deformable mesh.
const FLAGS: [(&str, TriMeshFlags); 2] = [
    (
        "world_flags",
        TriMeshFlags::DEFORMABLE
            .union(TriMeshFlags::DELETE_DEGENERATE_TRIANGLES)
            .union(TriMeshFlags::FIX_INTERNAL_EDGES),
    ),
    ("plain", TriMeshFlags::DEFORMABLE),
];

fn collider(mesh: &TriMesh, flags: TriMeshFlags) -> ParryMesh {
    ParryMesh::with_flags(mesh.positions().to_vec(), mesh.faces().to_vec(), flags).expect("collider")
}

fn refits(c: &mut Criterion) {
    let (target, ball, impact, params) = scene();
    let mut dented = target.clone();
    let report = dent(&mut dented, &ball, &impact, &params).expect("dent");
    eprintln!(
        "target: {} triangles, {} vertices; dent moved {} vertices at resolution {}",
        target.face_count(),
        target.vertex_count(),
        report.moved_vertices,
        report.resolution
    );
    for (name, flags) in FLAGS {
        // The world flags merge vertices, so parry renumbers them: the map translates.
        let shape = collider(&target, flags);
        let map = dentbend::collider::VertexMap::new(&shape, target.positions(), target.faces()).expect("map");
        let (moved, positions) = map.moved_between(target.positions(), dented.positions());

        let mut group = c.benchmark_group("refit_partial");
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter_batched_ref(
                || shape.clone(),
                |s| refit_trimesh(s, &moved, &positions).expect("refit"),
                BatchSize::LargeInput,
            )
        });
        group.finish();

        let mut all = shape.vertices().to_vec();
        for (&j, &p) in moved.iter().zip(&positions) {
            all[j as usize] = p;
        }
        let mut group = c.benchmark_group("set_vertices");
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter_batched_ref(|| shape.clone(), |s| s.set_vertices(&all), BatchSize::LargeInput)
        });
        group.finish();

        let mut group = c.benchmark_group("rebuild");
        group.bench_function(BenchmarkId::from_parameter(name), |b| b.iter(|| collider(&dented, flags)));
        group.finish();

        let mut group = c.benchmark_group("dent_plus_refit");
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter_batched_ref(
                || (target.clone(), shape.clone()),
                |(mesh, s)| {
                    let before = mesh.positions().to_vec();
                    dent(mesh, &ball, &impact, &params).expect("dent");
                    let (moved, positions) = map.moved_between(&before, mesh.positions());
                    refit_trimesh(s, &moved, &positions).expect("refit")
                },
                BatchSize::LargeInput,
            )
        });
        group.finish();
    }

    let mut group = c.benchmark_group("dent_only");
    group.bench_function("uv_sphere_25k", |b| {
        b.iter_batched_ref(
            || target.clone(),
            |mesh| dent(mesh, &ball, &impact, &params).expect("dent"),
            BatchSize::LargeInput,
        )
    });
    group.finish();

    let mut group = c.benchmark_group("moved_vertices");
    group.bench_function("uv_sphere_25k", |b| b.iter(|| moved_vertices(target.positions(), dented.positions())));
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).measurement_time(std::time::Duration::from_secs(3));
    targets = refits
}
criterion_main!(benches);
