//! No self-intersections however many dents. The mesh check itself
//! (`TriMesh::self_intersections`), the falloff fitted to the wall's measured thickness, and the
//! intersection guard over 1,000 accumulated random dents on a block and on a plank.

mod common;

use common::SplitMix64;
use dentbend::dent::Refine;
use dentbend::dent::{DentJob, dent_batch};
use dentbend::glam::{Affine3A, Quat, Vec3};
use dentbend::{Attenuation, DentParams, Impact, Resolution, TriMesh, dent, mesh};

/// `a` and `b` as one mesh (faces of `b` renumbered).
fn merged(a: &TriMesh, b: &TriMesh) -> TriMesh {
    let offset = a.vertex_count() as u32;
    let positions = a.positions().iter().chain(b.positions()).copied().collect();
    let faces = a.faces().iter().copied().chain(b.faces().iter().map(|f| f.map(|v| v + offset))).collect();
    TriMesh::new(positions, faces).unwrap()
}

fn moved(mut m: TriMesh, by: Vec3) -> TriMesh {
    m.transform(Affine3A::from_translation(by)).unwrap();
    m
}

/// A strip 1 wide along y whose centre line runs (0,0) → (2,0) → (1.1,1) → (1.1,−0.9) in the
/// xz-plane: its last leg pierces its first (away from any vertex). `n` segments per leg.
fn pierced_strip(n: u32) -> TriMesh {
    let corners = [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(1.1, 0.0, 1.0), Vec3::new(1.1, 0.0, -0.9)];
    let mut line = vec![Vec3::ZERO];
    for leg in corners.windows(2) {
        line.extend((1..=n).map(|k| leg[0].lerp(leg[1], k as f32 / n as f32)));
    }
    let positions: Vec<Vec3> = line.iter().flat_map(|&p| [p - 0.5 * Vec3::Y, p + 0.5 * Vec3::Y]).collect();
    let faces = (0..line.len() as u32 - 1)
        .flat_map(|k| {
            let (a, b, c, d) = (2 * k, 2 * k + 1, 2 * k + 2, 2 * k + 3);
            [[a, c, d], [a, d, b]]
        })
        .collect();
    TriMesh::new(positions, faces).unwrap()
}

#[test]
fn closed_meshes_have_no_crossings() {
    for name in ["sphere", "bunny", "block-fine", "plank", "cylinder", "box"] {
        let m = mesh::builtin(name).unwrap();
        assert_eq!(m.self_intersections(), vec![], "{name}");
        assert!(!m.has_self_intersections(), "{name}");
    }
}

#[test]
fn interpenetrating_boxes_cross_and_separate_ones_do_not() {
    let cube = mesh::subdivided_box(Vec3::ONE, [4, 4, 4]).unwrap();
    let crossing = merged(&cube, &moved(cube.clone(), Vec3::new(0.5, 0.3, 0.2)));
    let pairs = crossing.self_intersections();
    let first = cube.face_count() as u32;
    assert!(!pairs.is_empty());
    // Each crossing pairs a face of one box with a face of the other.
    assert!(pairs.iter().all(|&(i, j)| i < first && j >= first), "{pairs:?}");
    // Boxes exactly face to face touch and do not cross; a gap is a gap.
    assert_eq!(merged(&cube, &moved(cube.clone(), Vec3::X)).self_intersections(), vec![]);
    assert_eq!(merged(&cube, &moved(cube.clone(), Vec3::new(1.01, 0.0, 0.0))).self_intersections(), vec![]);
}

#[test]
fn a_folded_sheet_crosses_itself_and_the_local_check_agrees() {
    let strip = pierced_strip(8);
    let pairs = strip.self_intersections();
    assert!(!pairs.is_empty());
    // The crossing faces are those of the first leg around x = 1.1 and of the last leg around z = 0.
    let centre = |f: u32| strip.faces()[f as usize].iter().map(|&v| strip.positions()[v as usize]).sum::<Vec3>() / 3.0;
    for &(i, j) in &pairs {
        let (a, b) = (centre(i), centre(j));
        assert!(
            (a.x - 1.1).abs() < 0.25 && a.z.abs() < 1e-6 && (b.x - 1.1).abs() < 1e-6 && b.z.abs() < 0.25,
            "{a} {b}"
        );
    }
    // Around the last leg's vertices the local check finds exactly the same pairs.
    let last_leg: Vec<u32> =
        (0..strip.vertex_count() as u32).filter(|&v| strip.positions()[v as usize].z < -0.01).collect();
    let mut near = strip.self_intersections_near(&last_leg);
    near.extend(strip.self_intersections_near(&(0..strip.vertex_count() as u32).collect::<Vec<_>>()));
    near.sort_unstable();
    near.dedup();
    assert_eq!(near, pairs);
    // Unfolded (the last leg lifted clear), nothing crosses.
    let lifted: Vec<Vec3> = strip.positions().iter().map(|&p| if p.z < 0.0 { p.with_z(0.01) } else { p }).collect();
    let mut open = strip.clone();
    open.set_positions(lifted).unwrap();
    assert_eq!(open.self_intersections(), vec![]);
}

#[test]
fn the_check_runs_on_a_hundred_thousand_triangles() {
    // 12·92² = 101,568 triangles.
    let big = mesh::subdivided_box(Vec3::splat(2.0), [92, 92, 92]).unwrap();
    assert!(big.face_count() > 100_000);
    assert_eq!(big.self_intersections(), vec![]);
    // One vertex of the top face pushed down through the bottom: its fan now crosses the bottom.
    let top = (0..big.vertex_count())
        .find(|&v| big.positions()[v].abs().cmplt(Vec3::new(0.02, 1.1, 0.02)).all() && big.positions()[v].y > 0.9)
        .unwrap();
    let mut pushed = big.positions().to_vec();
    pushed[top].y = -1.5;
    let mut broken = big.clone();
    broken.set_positions(pushed).unwrap();
    let pairs = broken.self_intersections();
    assert!(!pairs.is_empty());
    assert_eq!(broken.self_intersections_near(&[top as u32]), pairs);
}

/// A ball of radius `r` resting on the plank's top at x, head-on.
fn plank_dent(attenuation: Attenuation, d: f32) -> (TriMesh, dentbend::DentReport) {
    let mut plank = mesh::builtin("plank").unwrap();
    let ball = common::sphere_at(Vec3::new(0.0, 0.125 + 0.1, 0.0), 0.1);
    let impact = Impact::head_on(Vec3::new(0.0, 0.125, 0.0), -Vec3::Y);
    let params = DentParams { attenuation, resolution: Resolution::Fixed(64), ..DentParams::new(d) };
    let report = dent(&mut plank, &ball, &impact, &params).unwrap();
    (plank, report)
}

/// Thickness left under the dent's centre, along y: top vertex nearest the axis minus bottom one.
fn thickness_at_centre(plank: &TriMesh) -> f32 {
    let nearest = |top: bool| {
        let original = mesh::builtin("plank").unwrap();
        let v = (0..original.vertex_count())
            .filter(|&v| (original.positions()[v].y > 0.0) == top)
            .min_by(|&a, &b| {
                let r = |v: usize| original.positions()[v].with_y(0.0).length();
                r(a).total_cmp(&r(b))
            })
            .unwrap();
        plank.positions()[v].y
    };
    nearest(true) - nearest(false)
}

#[test]
fn thin_wall_warning_reads_the_body() {
    // The plank is 0.25 thick. Linear { scale: 1 } with d = 0.3 would move its top by d and its
    // bottom by (1 − 0.25/0.3)·d: nothing left. It is warned about, and the falloff is stretched
    // so at least half the wall stays.
    let (plank, report) = plank_dent(Attenuation::Linear { scale: 1.0 }, 0.3);
    assert_eq!(report.warnings.len(), 1, "{:?}", report.warnings);
    assert!(report.warnings[0].contains("fold"), "{:?}", report.warnings);
    let left = thickness_at_centre(&plank);
    // Half of 0.25, less the few % the peak cell under the nearest vertex differs from the
    // sampled rays (measured on an 8×8 sample of the 64² map).
    assert!(left > 0.5 * 0.25 * 0.95, "wall left {left}");
    assert!(left < 0.25, "the dent did push the wall in: {left}");
    assert_eq!(plank.self_intersections(), vec![]);

    // A shallow dent with the same falloff cannot fold the plank: silent, and unchanged.
    let (_, report) = plank_dent(Attenuation::Linear { scale: 1.0 }, 0.075);
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    // The paper's logistic falloff never loses more than half a wall: no warning, even deep.
    let (_, report) = plank_dent(Attenuation::Logistic, 0.3);
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
}

#[test]
fn measured_wall_thickness_is_the_plank_and_thick_targets_are_untouched() {
    let mut plank = mesh::builtin("plank").unwrap();
    let ball = common::sphere_at(Vec3::new(0.0, 0.225, 0.0), 0.1);
    let impact = Impact::head_on(Vec3::new(0.0, 0.125, 0.0), -Vec3::Y);
    let params = DentParams { resolution: Resolution::Fixed(64), ..DentParams::new(0.2) };
    let map = dentbend::dent_map(&ball, &impact, &params, None).unwrap();
    let report = map.apply(&mut plank, &Attenuation::Linear { scale: 1.0 }).unwrap();
    let measured = report.wall_thickness.expect("measured");
    assert!((measured - 0.25).abs() < 1e-4, "{measured}");
    // On the 1-thick block the same falloff and dent cannot fold anything: the result is the
    // plain, unfitted displacement, bit for bit.
    let block = mesh::builtin("block").unwrap();
    let impact = Impact::head_on(Vec3::new(0.0, 0.5, 0.0), -Vec3::Y);
    let ball = common::sphere_at(Vec3::new(0.0, 0.6, 0.0), 0.1);
    let map = dentbend::dent_map(&ball, &impact, &params, None).unwrap();
    let mut fitted = block.clone();
    let linear = Attenuation::Linear { scale: 1.0 };
    let report = map.apply(&mut fitted, &linear).unwrap();
    // Measured (the falloff is steep enough to matter), found 1 thick, so left as it is.
    let measured = report.wall_thickness.expect("measured");
    assert!(report.warnings.is_empty() && (measured - 1.0).abs() < 1e-4, "{report:?}");
    let (kernel, table) = map.displace_params(&linear, block.vertex_count());
    let mut plain = block.positions().to_vec();
    let mut flags = vec![false; plain.len()];
    dentbend::cpu::displace(&kernel, &map.cells, &table, &mut plain, &mut flags);
    assert_eq!(fitted.positions(), &plain[..]);
}

#[test]
fn the_guard_stops_a_dent_pushing_one_body_into_another() {
    // Two 0.1-thick slabs 0.05 apart in one mesh, hit on the top one with d = 0.2.
    let slab = mesh::subdivided_box(Vec3::new(1.0, 0.1, 1.0), [20, 2, 20]).unwrap();
    let two = merged(&slab, &moved(slab.clone(), Vec3::new(0.0, -0.15, 0.0)));
    assert_eq!(two.self_intersections(), vec![]);
    let ball = common::sphere_at(Vec3::new(0.0, 0.25, 0.0), 0.2);
    let impact = Impact::head_on(Vec3::new(0.0, 0.05, 0.0), -Vec3::Y);
    // A falloff that moves everything above depth 0.12 rigidly and nothing below: the top slab
    // keeps its thickness (nothing to fit) and is pushed into the lower one.
    let step = Attenuation::Custom(std::sync::Arc::new(|z: f32, _d: f32| if z < 0.12 { 1.0 } else { 0.0 }));
    let params = DentParams { attenuation: step, resolution: Resolution::Fixed(64), ..DentParams::new(0.2) };
    let mut unguarded = two.clone();
    let off = DentParams { guard_crossings: false, ..params.clone() };
    let report = dent(&mut unguarded, &ball, &impact, &off).unwrap();
    assert_eq!(report.limited_to, None);
    assert!(!unguarded.self_intersections().is_empty(), "the test must be able to fail");

    let mut guarded = two.clone();
    let report = dent(&mut guarded, &ball, &impact, &params).unwrap();
    let kept = report.limited_to.expect("limited");
    assert!(kept > 0.0 && kept < 1.0, "{kept}");
    assert!(report.warnings.iter().any(|w| w.contains("limited")), "{:?}", report.warnings);
    assert_eq!(guarded.self_intersections(), vec![]);
    // Limited, not cancelled: the top slab still moved most of the way to the lower one.
    assert!(report.max_displacement > 0.03, "{}", report.max_displacement);
}

/// Seeded random dents on the current surface of `target`: uniform faces, depth up to 30 % of
/// `thickness`, velocity up to 60° off the normal, a small sphere of radius `ball`. Every
/// `batch` dents go through `dent_batch` (1 = one `dent` call each). Returns the number of dents
/// the guard limited; asserts 0 crossings every 100 dents and at the end. `refine` is the
/// dents' refine setting.
fn accumulate(
    mut target: TriMesh,
    thickness: f32,
    ball: f32,
    batch: usize,
    seed: u64,
    refine: Refine,
) -> (TriMesh, usize) {
    const DENTS: usize = 1000;
    let mut rng = SplitMix64::new(seed);
    let projectile = mesh::icosphere(ball, 2).unwrap();
    let (mut limited, mut applied) = (0, 0);
    let mut done = 0;
    while done < DENTS {
        let mut projectiles = Vec::new();
        let mut impacts = Vec::new();
        for _ in 0..batch.min(DENTS - done) {
            let f = rng.below(target.face_count() as u64) as usize;
            let (point, normal, velocity) = random_hit(&target, f, &mut rng);
            let d = rng.range_f32(0.02, 0.3) * thickness;
            if normal == Vec3::ZERO {
                continue;
            }
            let mut p = projectile.clone();
            p.transform(Affine3A::from_translation(point - velocity * ball)).unwrap();
            projectiles.push((p, d));
            impacts.push(Impact { point, normal: -normal, relative_velocity: velocity });
        }
        let jobs: Vec<DentJob<'_>> = projectiles
            .iter()
            .zip(&impacts)
            .map(|((p, d), impact)| {
                let params = DentParams { refine, ..DentParams::new(*d) };
                DentJob { target: 0, projectile: p, impact: *impact, params }
            })
            .collect();
        let before = done;
        done += jobs.len().max(1);
        let reports = if batch == 1 && jobs.len() == 1 {
            dent(&mut target, jobs[0].projectile, &jobs[0].impact, &jobs[0].params).map(|r| vec![r]).ok()
        } else {
            dent_batch(std::slice::from_mut(&mut target), &jobs).ok()
        };
        if let Some(reports) = reports {
            applied += reports.len();
            limited += reports.iter().filter(|r| r.limited_to.is_some()).count();
        }
        if done / 100 != before / 100 {
            assert_eq!(target.self_intersections(), vec![], "crossings after {done} dents");
        }
    }
    assert!(applied >= DENTS * 9 / 10, "only {applied} of {DENTS} dents applied");
    (target, limited)
}

/// The guard on its own: refinement off, so the block keeps its 57,344 faces.
#[test]
fn a_thousand_dents_on_block_fine_leave_no_crossings() {
    let (dented, limited) = accumulate(mesh::builtin("block-fine").unwrap(), 1.0, 0.15, 1, 18, Refine::Off);
    eprintln!("block-fine: {limited} of 1000 dents limited; volume {}", dented.volume());
    assert_no_crossings(&dented);
}

/// No face pair of `mesh` crosses, by `TriMesh::self_intersections` and by an independent check
/// (segment–triangle tests, counting touches).
fn assert_no_crossings(mesh: &TriMesh) {
    assert_eq!(mesh.self_intersections(), vec![]);
    let all = vec![true; mesh.vertex_count()];
    assert_eq!(common::self_intersections(mesh, &all), vec![]);
}

#[test]
fn a_thousand_dents_on_the_plank_leave_no_crossings() {
    let (dented, limited) = accumulate(mesh::builtin("plank").unwrap(), 0.25, 0.05, 10, 1818, Refine::default());
    eprintln!("plank: {limited} of 1000 dents limited; volume {}", dented.volume());
    assert_no_crossings(&dented);
}

/// The full property with refinement on (the default): 1,000 dents on block-fine, 0 crossings.
/// Refinement grows the block from 57,344 to 105,008 faces. Ignored only for its time (about a
/// minute in release on an idle 2-core VM, several on a loaded one); the non-ignored test below
/// runs the same mechanism on a patch.
/// `cargo test --release --test dent_no_crossings -- --ignored`.
#[test]
#[ignore = "slow: 1,000 refined dents on block-fine take minutes"]
fn a_thousand_refined_dents_on_block_fine_leave_no_crossings() {
    let (dented, _) = accumulate(mesh::builtin("block-fine").unwrap(), 1.0, 0.15, 1, 18, Refine::default());
    eprintln!("block-fine, refined: {} faces after 1000 dents", dented.face_count());
    assert_no_crossings(&dented);
}

/// What [`accumulate_on_patch`] did.
struct PatchRun {
    dented: TriMesh,
    applied: usize,
    /// Triangles the refine stage added, over all dents.
    refined_triangles: usize,
    /// Dents whose refine stage left faces unsplit because splitting them would have made faces
    /// cross.
    held_back: usize,
}

/// `dents` seeded random dents as [`accumulate`] makes them (ball 0.15, depth up to 0.3,
/// glancing up to 60°, default refinement), each on one of the `patch` faces nearest to `centre`
/// on the current surface, so that refined faces are dented again. After every dent, the faces
/// around the vertices it moved or added are checked for crossings.
fn accumulate_on_patch(
    mut target: TriMesh,
    centre: Vec3,
    (patch, dents, seed): (usize, usize, u64),
    refine: Refine,
) -> PatchRun {
    const BALL: f32 = 0.15;
    let mut rng = SplitMix64::new(seed);
    let projectile = mesh::icosphere(BALL, 2).unwrap();
    let (mut applied, mut refined_triangles, mut held_back) = (0, 0, 0);
    for k in 0..dents {
        let centroid = |f: usize| target.faces()[f].iter().map(|&v| target.positions()[v as usize]).sum::<Vec3>() / 3.0;
        let mut nearest: Vec<(f32, usize)> =
            (0..target.face_count()).map(|f| (centroid(f).distance(centre), f)).collect();
        nearest.select_nth_unstable_by(patch - 1, |a, b| a.0.total_cmp(&b.0));
        let f = nearest[rng.below(patch as u64) as usize].1;
        let (point, normal, velocity) = random_hit(&target, f, &mut rng);
        let d = rng.range_f32(0.02, 0.3);
        if normal == Vec3::ZERO {
            continue;
        }
        let mut p = projectile.clone();
        p.transform(Affine3A::from_translation(point - velocity * BALL)).unwrap();
        let impact = Impact { point, normal: -normal, relative_velocity: velocity };
        let before = target.clone();
        let Ok(report) = dent(&mut target, &p, &impact, &DentParams { refine, ..DentParams::new(d) }) else { continue };
        applied += 1;
        refined_triangles += report.refined_triangles;
        held_back += usize::from(report.warnings.iter().any(|w| w.contains("folded flat")));
        let changed: Vec<u32> = (0..target.vertex_count() as u32)
            .filter(|&v| before.positions().get(v as usize) != Some(&target.positions()[v as usize]))
            .collect();
        assert_eq!(target.self_intersections_near(&changed), vec![], "crossings after dent {k}");
    }
    PatchRun { dented: target, applied, refined_triangles, held_back }
}

/// A hit on face `f` of `target`: a point drawn uniformly on the face, its unit normal (zero for
/// a degenerate face), and a unit velocity within 60° of the inward normal, turned about it at
/// random.
fn random_hit(target: &TriMesh, f: usize, rng: &mut SplitMix64) -> (Vec3, Vec3, Vec3) {
    let [a, b, c] = target.faces()[f].map(|v| target.positions()[v as usize]);
    let normal = (b - a).cross(c - a).normalize_or_zero();
    let (mut u, mut v) = (rng.next_f32(), rng.next_f32());
    if u + v > 1.0 {
        (u, v) = (1.0 - u, 1.0 - v);
    }
    let point = a + u * (b - a) + v * (c - a);
    let tilt = rng.range_f32(0.0, 60f32.to_radians());
    let spin = rng.range_f32(0.0, std::f32::consts::TAU);
    let axis = Quat::from_axis_angle(normal, spin) * normal.any_orthonormal_vector();
    let velocity = Quat::from_axis_angle(axis, tilt) * -normal;
    (point, normal, velocity)
}

/// Refinement and accumulated dents on block-fine, cheaply: 40 dents on the 400 faces nearest a
/// top corner, where dents roll the edges over and stretch the faces until the refine stage
/// splits them; three seeds that refine (22, 30 and 31 under the current pipeline; another
/// pipeline may need other seeds). Before the guard limited dents that turn faces over, some
/// dents here folded a patch flat onto itself (two faces back to back, one of them turned over)
/// and the refine stage held those faces back; the guard now stops such folds, and holding back
/// is tested on a captured fold in `mesh::refine_crossings`.
#[test]
fn refined_dents_piled_on_a_corner_of_block_fine_leave_no_crossings() {
    let block = mesh::builtin("block-fine").unwrap();
    let corner = block.support_point(Vec3::new(-1.0, 1.0, 0.0).normalize());
    for seed in [22, 30, 31] {
        let run = accumulate_on_patch(block.clone(), corner, (400, 40, seed), Refine::default());
        eprintln!(
            "seed {seed}: {} dents applied, {} triangles refined, {} held back; {} faces",
            run.applied,
            run.refined_triangles,
            run.held_back,
            run.dented.face_count()
        );
        assert!(run.applied >= 36, "only {} of 40 dents applied", run.applied);
        assert!(run.refined_triangles > 0, "seed {seed}: nothing refined");
        assert_no_crossings(&run.dented);
    }
}
