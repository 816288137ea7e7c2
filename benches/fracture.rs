//! Prescored fracture (the goal: a wall into ≤ 50 pieces in ≤ 5 ms): the figure-3
//! wall (3 × 2 × 0.2 m, 10,400 triangles) broken at its centre by a 40-cell and a 50-cell
//! pattern of radius 0.45 m (40 and 50 pieces), the same wall faceted as a game asset (every
//! face's vertices its own, so the pieces keep its seams), and a 24-cell pattern on the
//! 3,674-triangle bunny. `break_body` cuts the cells on all cores (rayon); run with
//! `cargo bench --bench fracture`, and with `RAYON_NUM_THREADS=1` for one core.

use criterion::{Criterion, criterion_group, criterion_main};
use dentbend::fracture::{FractureSettings, PatternParams, Placement, break_body};
use dentbend::glam::Vec3;
use dentbend::mesh;

fn fracture(c: &mut Criterion) {
    let wall = mesh::subdivided_box(Vec3::new(3.0, 2.0, 0.2), [60, 40, 2]).expect("wall");
    let placement = Placement { point: Vec3::new(0.0, 0.0, 0.1), normal: -Vec3::Z };
    let mut group = c.benchmark_group("fracture");
    for cells in [40, 50] {
        let settings =
            FractureSettings::new(PatternParams { cells, seed: 3, radius: 0.45 }, Some(1.0), None).expect("settings");
        let outcome = break_body(&wall, &settings.pattern, &placement, 2400.0).expect("break").expect("pieces");
        eprintln!("wall: {} triangles → {} pieces", wall.face_count(), outcome.pieces.len());
        assert!(outcome.pieces.len() <= 50);
        group.bench_function(format!("wall_{cells}_cells"), |b| {
            b.iter(|| break_body(&wall, &settings.pattern, &placement, 2400.0).expect("break"))
        });
    }
    // The same wall as a game asset with hard edges (every face's vertices its own): the
    // output keeps the seams and tells each vertex's origin.
    let faceted = {
        let positions = wall.faces().iter().flat_map(|f| f.map(|v| wall.positions()[v as usize])).collect();
        let faces = (0..wall.face_count() as u32).map(|f| [3 * f, 3 * f + 1, 3 * f + 2]).collect();
        dentbend::TriMesh::new(positions, faces).expect("faceted wall")
    };
    let settings =
        FractureSettings::new(PatternParams { cells: 40, seed: 3, radius: 0.45 }, Some(1.0), None).expect("settings");
    group.bench_function("wall_40_cells_faceted", |b| {
        b.iter(|| break_body(&faceted, &settings.pattern, &placement, 2400.0).expect("break"))
    });
    let bunny = mesh::builtin("bunny").expect("bunny");
    let bunny_settings =
        FractureSettings::new(PatternParams { cells: 24, seed: 11, radius: 2.5 }, Some(1.0), None).expect("settings");
    let hit = Placement { point: Vec3::new(-1.0, 7.0, 0.5), normal: Vec3::new(0.3, -0.2, -1.0) };
    group.bench_function("bunny_24_cells", |b| {
        b.iter(|| break_body(&bunny, &bunny_settings.pattern, &hit, 1000.0).expect("break"))
    });
    group.bench_function("pattern_40_cells", |b| {
        b.iter(|| dentbend::fracture::FracturePattern::new(PatternParams { cells: 40, seed: 3, radius: 0.45 }))
    });
    group.finish();
}

criterion_group!(benches, fracture);
criterion_main!(benches);
