//! Volume kept: with `VolumeMode::Preserve` a dent raises a rim around its
//! crater until the enclosed volume is back within 2 % of the cavity volume (the volume the
//! same dent takes without the rim); the rim stays near the crater; every dent reports its
//! volume change; errors leave the mesh unchanged.

mod common;

use common::sphere_at;
use dentbend::dent::{DentJob, dent_batch};
use dentbend::glam::Vec3;
use dentbend::{DentParams, DentReport, Impact, TriMesh, VolumeMode, dent, mesh};

/// The bound: |V_after − V_before| ≤ 2 % of the cavity volume.
const TOLERANCE: f64 = 0.02;

/// Enclosed volume in f64 (the library's `TriMesh::volume` rounds to f32, too coarse to see a
/// small difference of two large volumes).
fn volume(mesh: &TriMesh) -> f64 {
    let p = mesh.positions();
    mesh.faces()
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|v| p[v as usize].as_dvec3());
            a.dot(b.cross(c))
        })
        .sum::<f64>()
        / 6.0
}

fn preserving(d: f32) -> DentParams {
    DentParams { volume: VolumeMode::Preserve, ..DentParams::new(d) }
}

/// Dents a copy of `target` with `params`; the copy, the report and the exact volume change.
fn dented(target: &TriMesh, ball: &TriMesh, impact: &Impact, params: &DentParams) -> (TriMesh, DentReport, f64) {
    let mut mesh = target.clone();
    let report = dent(&mut mesh, ball, impact, params).unwrap();
    let change = volume(&mesh) - volume(target);
    (mesh, report, change)
}

/// Checks one dent both ways: without the rim the body loses what the report calls the
/// cavity; with it the change is within 2 % of that cavity, and the report says so.
fn keeps_volume(target: &TriMesh, ball: &TriMesh, impact: &Impact, d: f32) -> (TriMesh, TriMesh, f64) {
    let (free, free_report, lost) = dented(target, ball, impact, &DentParams::new(d));
    let cavity = free_report.cavity_volume;
    assert!(lost < 0.0, "the dent should take volume away, changed it by {lost}");
    // The local sum and the whole-mesh sum differ by f64 rounding only.
    assert!((free_report.volume_change - lost).abs() <= 1e-9 * volume(target).abs(), "{free_report:?} vs {lost}");
    assert!((cavity - lost.abs()).abs() <= 1e-9 * volume(target).abs(), "{free_report:?} vs {lost}");

    let (kept, report, change) = dented(target, ball, impact, &preserving(d));
    assert_eq!(report.cavity_volume, cavity, "the cavity is the same dent's, rim or not");
    assert!(
        change.abs() <= TOLERANCE * cavity,
        "volume changed by {change:.3e} with the rim, cavity {cavity:.3e} ({:.2} %)",
        100.0 * change / cavity
    );
    assert!((report.volume_change - change).abs() <= 1e-9 * volume(target).abs() + 1e-3 * cavity);
    assert!(report.warnings.iter().all(|w| !w.contains("volume")), "{:?}", report.warnings);
    (free, kept, cavity)
}

/// The case: the bunny hit by a sphere as large as the bunny, d = L/2 (L the bunny's
/// largest side), loses about a third of its volume; with the rim it keeps it.
#[test]
fn bunny_keeps_its_volume_under_a_large_sphere() {
    let bunny = mesh::builtin("bunny").unwrap();
    let (lo, hi) = bunny.bounds();
    let size = (hi - lo).max_element();
    let top = bunny.support_point(Vec3::Y);
    let ball = sphere_at(top + Vec3::Y * size, size);
    let impact = Impact::head_on(top, -Vec3::Y);
    let (_, _, cavity) = keeps_volume(&bunny, &ball, &impact, 0.5 * size);
    let share = cavity / volume(&bunny);
    assert!(share > 0.2, "the dent should take a large share of the bunny, took {:.1} %", 100.0 * share);
}

/// A ball on the middle of block-fine's top face, and a glancing one near its edge.
#[test]
fn block_fine_keeps_its_volume_head_on_and_glancing() {
    let block = mesh::builtin("block-fine").unwrap();
    let top = block.support_point(Vec3::Y).y;
    let point = Vec3::new(0.3, top, -0.2);
    let ball = sphere_at(point + Vec3::Y * 0.4, 0.4);
    keeps_volume(&block, &ball, &Impact::head_on(point, -Vec3::Y), 0.1);
    let glancing = Impact { point, normal: -Vec3::Y, relative_velocity: Vec3::new(1.0, -1.0, 0.0) };
    keeps_volume(&block, &ball, &glancing, 0.08);
}

/// The thin plank bulges at the back as well: still kept.
#[test]
fn plank_keeps_its_volume() {
    let plank = mesh::builtin("plank").unwrap();
    let top = plank.support_point(Vec3::Y).y;
    let point = Vec3::new(0.0, top, 0.0);
    let ball = sphere_at(point + Vec3::Y * 0.3, 0.3);
    keeps_volume(&plank, &ball, &Impact::head_on(point, -Vec3::Y), 0.05);
}

/// The rim stays local: every vertex farther than 2.5 crater radii from the impact point
/// (the crater: vertices the plain dent moves by at least a tenth of its deepest) is where the
/// plain dent leaves it. The rim reaches 2 radii across and 1 deep, at most √5 ≈ 2.24 away.
#[test]
fn the_rim_stays_near_the_crater() {
    let block = mesh::builtin("block-fine").unwrap();
    let top = block.support_point(Vec3::Y).y;
    let point = Vec3::new(-0.4, top, 0.1);
    let ball = sphere_at(point + Vec3::Y * 0.5, 0.5);
    let impact = Impact::head_on(point, -Vec3::Y);
    let (free, kept, _) = keeps_volume(&block, &ball, &impact, 0.12);
    let shift = |v: usize| free.positions()[v].distance(block.positions()[v]);
    let deepest = (0..block.vertex_count()).map(shift).fold(0.0, f32::max);
    let crater = (0..block.vertex_count())
        .filter(|&v| shift(v) >= 0.1 * deepest)
        .map(|v| block.positions()[v].distance(point))
        .fold(0.0, f32::max);
    let mut raised = 0;
    for v in 0..block.vertex_count() {
        let (f, k) = (free.positions()[v], kept.positions()[v]);
        if f != k {
            raised += 1;
            let far = block.positions()[v].distance(point);
            assert!(far <= 2.5 * crater, "vertex {v} moved by the rim {far} from the impact, crater radius {crater}");
            // Out of the body, not in: the rim rises.
            assert!((k - f).dot(block.normals()[v]) > 0.0, "vertex {v} pushed inward");
        }
    }
    assert!(raised > 20, "the rim should move a ring of vertices, moved {raised}");
}

/// Twenty dents in a row on block-fine, one batch each and one batch of all: the volume stays
/// within 2 % of the sum of the cavities (each dent keeps its own).
#[test]
fn many_dents_in_a_row_keep_the_volume() {
    let block = mesh::builtin("block-fine").unwrap();
    let top = block.support_point(Vec3::Y).y;
    let balls: Vec<(TriMesh, Impact)> = (0..20)
        .map(|k| {
            let (x, z) = ((k % 5) as f32 * 0.35 - 0.7, (k / 5) as f32 * 0.35 - 0.5);
            let point = Vec3::new(x, top, z);
            let tilt = Vec3::new(0.3 * (k as f32).sin(), -1.0, 0.3 * (k as f32).cos());
            (sphere_at(point + Vec3::Y * 0.25, 0.25), Impact { point, normal: -Vec3::Y, relative_velocity: tilt })
        })
        .collect();
    let jobs: Vec<DentJob<'_>> = balls
        .iter()
        .map(|(ball, impact)| DentJob { target: 0, projectile: ball, impact: *impact, params: preserving(0.06) })
        .collect();
    let start = volume(&block);

    let mut one_by_one = vec![block.clone()];
    let mut cavities = 0.0;
    for job in &jobs {
        let reports = dent_batch(&mut one_by_one, std::slice::from_ref(job)).unwrap();
        cavities += reports[0].cavity_volume;
    }
    let change = volume(&one_by_one[0]) - start;
    assert!(change.abs() <= TOLERANCE * cavities, "change {change:.3e} after cavities of {cavities:.3e}");

    let mut together = vec![block.clone()];
    let reports = dent_batch(&mut together, &jobs).unwrap();
    let cavities: f64 = reports.iter().map(|r| r.cavity_volume).sum();
    let reported: f64 = reports.iter().map(|r| r.volume_change).sum();
    let change = volume(&together[0]) - start;
    assert!(cavities > 0.0);
    assert!(change.abs() <= TOLERANCE * cavities, "change {change:.3e} after cavities of {cavities:.3e}");
    assert!((reported - change).abs() <= 1e-3 * cavities, "reported {reported:.3e}, measured {change:.3e}");
}

/// A low-poly target: the 12-triangle cube hit near a corner of its top face, where the plain
/// dent tilts the whole face. The rim can only use the cube's eight corners; it keeps the volume
/// or says it could not.
#[test]
fn low_poly_cube_keeps_its_volume_or_says_so() {
    let cube = mesh::subdivided_box(Vec3::splat(2.0), [1, 1, 1]).unwrap();
    assert_eq!(cube.face_count(), 12);
    let point = Vec3::new(0.6, 1.0, 0.6);
    let ball = sphere_at(point + Vec3::Y * 0.5, 0.5);
    let impact = Impact::head_on(point, -Vec3::Y);
    let (_, free, lost) = dented(&cube, &ball, &impact, &DentParams::new(0.2));
    assert!(lost < 0.0 && free.moved_vertices > 0, "the corner dent should tilt the face: {free:?}");
    let (_, report, change) = dented(&cube, &ball, &impact, &preserving(0.2));
    let restored = change.abs() <= TOLERANCE * report.cavity_volume;
    let warned = report.warnings.iter().any(|w| w.contains("volume is not restored"));
    assert!(restored != warned, "kept: {restored} ({change:.3e} of {:.3e}), warned: {warned}", report.cavity_volume);
}

/// Free is the default, and reports the volume the dent takes; a bad parameter with Preserve
/// is refused and leaves the mesh as it was.
#[test]
fn free_by_default_and_errors_leave_the_mesh_unchanged() {
    assert_eq!(DentParams::new(0.1).volume, VolumeMode::Free);
    let block = mesh::builtin("block-fine").unwrap();
    let top = block.support_point(Vec3::Y).y;
    let point = Vec3::new(0.0, top, 0.0);
    let ball = sphere_at(point + Vec3::Y * 0.4, 0.4);
    let impact = Impact::head_on(point, -Vec3::Y);
    for bad in [
        DentParams { sigma: Some(f32::NAN), ..preserving(0.1) },
        DentParams { min_cos: 0.0, ..preserving(0.1) },
        preserving(-1.0),
    ] {
        let mut mesh = block.clone();
        assert!(dent(&mut mesh, &ball, &impact, &bad).is_err());
        assert_eq!(mesh.positions(), block.positions());
        assert_eq!(mesh.normals(), block.normals());
    }
    let moved_ball = sphere_at(point + Vec3::Y * 0.4, 0.4);
    let far = Impact::head_on(point + Vec3::Y * 2.0, -Vec3::Y);
    let mut mesh = block.clone();
    assert!(dent(&mut mesh, &moved_ball, &far, &preserving(0.1)).is_err(), "projectile behind the plane");
    assert_eq!(mesh.positions(), block.positions());
}
