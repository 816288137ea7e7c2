//! Criterion benches, one group per kernel (ARCHITECTURE.md §1), on the paper's Table 1 scene.
//! Run with `cargo bench --bench kernels`; `dentbend-bench` gives the same numbers as JSON.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use dentbend::cpu;

#[path = "../tools/dentbend-bench/setup.rs"]
#[allow(dead_code, reason = "shared with dentbend-bench, which uses every item")]
mod setup;

use setup::{DISPLACE_CELLS, DisplaceScene, Scene};

const SIDES: [u32; 3] = [100, 200, 400];

fn scenes() -> Vec<Scene> {
    SIDES.iter().map(|&res| Scene::table1(res).expect("Table 1 scene")).collect()
}

fn kernels(c: &mut Criterion) {
    let scenes = scenes();
    let mut group = c.benchmark_group("zbuffer");
    for s in &scenes {
        let params = s.plan.zbuffer;
        let mut out = vec![0.0; s.plan.zbuffer_grid.cell_count()];
        group.bench_with_input(BenchmarkId::from_parameter(s.plan.zbuffer_grid.res), s, |b, s| {
            b.iter(|| cpu::zbuffer(&params, s.projectile.positions(), s.projectile.faces(), &mut out))
        });
    }
    group.finish();

    let mut group = c.benchmark_group("envelope_rows");
    for s in &scenes {
        let mut rows = vec![0.0; s.plan.zbuffer_grid.cell_count()];
        group.bench_with_input(BenchmarkId::from_parameter(s.plan.zbuffer_grid.res), s, |b, s| {
            b.iter(|| cpu::envelope_rows(&s.plan.envelope, &s.stages.zbuffer, &mut rows))
        });
    }
    group.finish();

    let mut group = c.benchmark_group("envelope_cols");
    for s in &scenes {
        let mut rows = vec![0.0; s.plan.zbuffer_grid.cell_count()];
        cpu::envelope_rows(&s.plan.envelope, &s.stages.zbuffer, &mut rows);
        let mut envelope = vec![0.0; s.plan.zbuffer_grid.cell_count()];
        group.bench_with_input(BenchmarkId::from_parameter(s.plan.zbuffer_grid.res), s, |b, s| {
            b.iter(|| cpu::envelope_cols(&s.plan.envelope, &rows, &mut envelope))
        });
    }
    group.finish();

    let mut group = c.benchmark_group("heat");
    for s in &scenes {
        let p = &s.params;
        let mut values = s.stages.envelope.clone();
        group.bench_with_input(BenchmarkId::from_parameter(s.plan.zbuffer_grid.res), s, |b, s| {
            b.iter(|| {
                values.copy_from_slice(&s.stages.envelope);
                cpu::heat(
                    &mut values,
                    s.plan.zbuffer_grid.res,
                    p.heat_rate,
                    p.heat_iters,
                    p.clamp_iters,
                    p.dent_distance,
                )
            })
        });
    }
    group.finish();

    let mut group = c.benchmark_group("glance");
    for s in &scenes {
        let m = &s.plan.map_grid;
        let params = s.plan.glance;
        let mut cells = vec![[0.0; 4]; m.cell_count()];
        group.bench_with_input(BenchmarkId::from_parameter(s.plan.zbuffer_grid.res), s, |b, s| {
            b.iter(|| cpu::glance(&params, &s.stages.smoothed, &mut cells))
        });
    }
    group.finish();
}

fn displace(c: &mut Criterion) {
    let scene = DisplaceScene::new(DISPLACE_CELLS).expect("displace scene");
    let mut positions = scene.target.positions().to_vec();
    let mut moved = vec![false; positions.len()];
    c.bench_function("displace/101570", |b| {
        b.iter(|| {
            positions.copy_from_slice(scene.target.positions());
            cpu::displace(&scene.kernel_params, &scene.map.cells, &scene.table, &mut positions, &mut moved)
        })
    });
}

/// The dense bunny (58,784 triangles) on four bones stacked up its height, each bent about its
/// own centre: smooth weights from the distance to the bone centres, as a skeleton would give.
fn skin_scene() -> (dentbend::TriMesh, Vec<cpu::SkinInfluence>, Vec<cpu::SkinBone>) {
    use dentbend::glam::{Affine3A, Quat, Vec3};
    let mesh = dentbend::mesh::builtin("bunny-dense").expect("dense bunny");
    let (lo, hi) = mesh.bounds();
    let centres: [Vec3; 4] = std::array::from_fn(|k| lo.lerp(hi, (k as f32 + 0.5) / 4.0));
    let influences = mesh
        .positions()
        .iter()
        .map(|p| {
            let closeness = centres.map(|c| 1.0 / (1.0 + p.distance_squared(c)));
            let sum: f32 = closeness.iter().sum();
            cpu::SkinInfluence { bones: [0, 1, 2, 3], weights: closeness.map(|w| w / sum) }
        })
        .collect();
    let rest: Vec<Affine3A> = centres.iter().map(|&c| Affine3A::from_translation(c)).collect();
    let current: Vec<Affine3A> = centres
        .iter()
        .enumerate()
        .map(|(k, &c)| Affine3A::from_rotation_translation(Quat::from_rotation_z(0.1 * k as f32), c))
        .collect();
    let bones = cpu::skin_bones(&rest, &current).expect("skin bones");
    (mesh, influences, bones)
}

fn skin(c: &mut Criterion) {
    use dentbend::glam::Vec3;
    let (mesh, influences, bones) = skin_scene();
    let n = mesh.vertex_count();
    let params = cpu::SkinParams::new(n as u32, bones.len() as u32);
    let (mut positions, mut normals) = (vec![Vec3::ZERO; n], vec![Vec3::ZERO; n]);
    let mut group = c.benchmark_group("skin");
    group.bench_function(BenchmarkId::new("cpu", n), |b| {
        b.iter(|| {
            cpu::skin(&params, &bones, mesh.positions(), mesh.normals(), &influences, &mut positions, &mut normals)
        })
    });
    match dentbend::gpu::shared_context() {
        Ok(context) => {
            let kernel = dentbend::gpu::skin::Skin::new(context).expect("skin kernel");
            let resident = kernel.upload(context, mesh.positions(), mesh.normals(), &influences, 4).expect("upload");
            // Bones up, dispatch, wait: the output stays on the GPU for a renderer.
            group.bench_function(BenchmarkId::new("gpu_resident", n), |b| {
                b.iter(|| {
                    let mut encoder = context.device.create_command_encoder(&Default::default());
                    kernel.encode(context, &mut encoder, &resident, &bones).expect("encode");
                    context.queue.submit([encoder.finish()]);
                    context.wait().expect("wait")
                })
            });
            // The same plus reading positions and normals back.
            group.bench_function(BenchmarkId::new("gpu_read_back", n), |b| {
                b.iter(|| kernel.run(context, &resident, &bones).expect("skin"))
            });
        }
        Err(error) => eprintln!("skin: GPU benches skipped: {error}"),
    }
    group.finish();
}

/// The dense bunny copied into a 32-byte interleaved layout (`interleave`) and its moved vertices
/// listed, every other vertex flagged (`moved`): CPU twins, and on the GPU from a `GpuDenter`.
fn output(c: &mut Criterion) {
    use dentbend::gpu::{GpuDenter, VertexLayout};
    let mesh = dentbend::mesh::builtin("bunny-dense").expect("dense bunny");
    let n = mesh.vertex_count();
    let flagged = |k: usize| if k.is_multiple_of(2) { 1.0 } else { 0.0 };
    let positions: Vec<[f32; 4]> =
        mesh.positions().iter().enumerate().map(|(k, p)| p.extend(flagged(k)).to_array()).collect();
    let normals: Vec<[f32; 4]> = mesh.normals().iter().map(|v| v.extend(0.0).to_array()).collect();
    let params =
        cpu::InterleaveParams { vertex_count: n as u32, stride_words: 8, normal_word: 3, ..Default::default() };
    let mut dst = vec![0u32; n * 8];
    let mut group = c.benchmark_group("interleave");
    group.bench_function(BenchmarkId::new("cpu", n), |b| {
        b.iter(|| cpu::interleave(&params, &positions, &normals, &mut dst))
    });
    let context = dentbend::gpu::shared_context().ok();
    let denter =
        context.map(|context| (context, GpuDenter::new(context, std::slice::from_ref(&mesh)).expect("denter")));
    if let Some((context, denter)) = &denter {
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX;
        let dst = context.buffer_with_contents("interleaved", &vec![0; n * 32], usage);
        group.bench_function(BenchmarkId::new("gpu", n), |b| {
            b.iter(|| {
                let mut encoder = context.device.create_command_encoder(&Default::default());
                denter.copy_target_into(&mut encoder, 0, &dst, 0, 32, VertexLayout::POSITION_NORMAL).expect("copy");
                context.queue.submit([encoder.finish()]);
                context.wait().expect("wait")
            })
        });
    }
    group.finish();
    let mut group = c.benchmark_group("moved");
    let params = cpu::MovedParams { vertex_offset: 0, vertex_count: n as u32, _pad: [0; 2] };
    let mut list = Vec::with_capacity(n);
    group.bench_function(BenchmarkId::new("cpu", n), |b| {
        b.iter(|| {
            list.clear();
            cpu::moved(&params, &positions, &mut list)
        })
    });
    // On the GPU after no batch: the compaction pass and the two small read-backs.
    if let Some((_, denter)) = &denter {
        group.bench_function(BenchmarkId::new("gpu", n), |b| b.iter(|| denter.read_moved(0).expect("moved")));
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(2));
    targets = kernels, displace, skin, output
}
criterion_main!(benches);
