//! Criterion benches, one group per kernel (DESIGN.md §1), on the paper's Table 1 scene.
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

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(2));
    targets = kernels, displace
}
criterion_main!(benches);
