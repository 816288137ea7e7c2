//! Game meshes split vertices at hard edges and UV seams: a dent must treat the vertices that
//! share a position as one point of the surface. Refinement splits both sides of a seam, the
//! volume rim lifts both sides together, so a closed asset stays closed after welding by position
//! (every edge between two faces) and vertices that shared a position still share it bit for
//! bit. A seam whose sides only nearly coincide is refused with the fix named, and snapping it
//! closed makes it dentable.

#[macro_use]
mod common;

use std::collections::HashMap;

use common::cube12;
use common::seams::{key, unpaired_edges};
use dentbend::damage::{CpuBackend, Damage, Hit, TargetSet};
use dentbend::dent::{BodyState, DentSettings, Surface};
use dentbend::glam::{Affine3A, Mat3, Vec3};
use dentbend::mesh::{self, TriMesh};
use dentbend::{DentError, DentParams, Impact, VolumeMode};

/// `mesh` with every face given vertices of its own quad (two faces in a row share theirs): the
/// hard-edged, 24-vertex cube a game engine makes from `cube12`'s 12 triangles.
fn split_faces(mesh: &TriMesh) -> TriMesh {
    let (mut positions, mut faces) = (Vec::new(), Vec::new());
    for pair in mesh.faces().chunks(2) {
        let mut local: HashMap<u32, u32> = HashMap::new();
        for face in pair {
            faces.push(face.map(|v| {
                *local.entry(v).or_insert_with(|| {
                    positions.push(mesh.positions()[v as usize]);
                    positions.len() as u32 - 1
                })
            }));
        }
    }
    TriMesh::new(positions, faces).unwrap()
}

/// A latitude–longitude sphere of `radius` as game engines build it: `sectors + 1` columns (the
/// last one a seam over the first, so UVs can run 0..1) and a row of `sectors + 1` vertices at
/// each pole. `at_two_pi`: the seam column computed at the angle 2π, as engines do (then its
/// vertices lie a few ulps off the first column's, and the south pole's row spreads as much), or
/// copied from the first column (with both poles' rows exactly at the poles).
fn seam_sphere(radius: f32, sectors: u32, stacks: u32, at_two_pi: bool) -> TriMesh {
    let mut positions = Vec::new();
    for i in 0..=stacks {
        let polar = std::f32::consts::PI * i as f32 / stacks as f32;
        let (mut ring, y) = (radius * polar.sin(), radius * polar.cos());
        if !at_two_pi && (i == 0 || i == stacks) {
            ring = 0.0; // sin(π) is not 0 in f32: the pole row would spread
        }
        for j in 0..=sectors {
            let j = if at_two_pi { j } else { j % sectors };
            let azimuth = std::f32::consts::TAU * j as f32 / sectors as f32;
            positions.push(Vec3::new(ring * azimuth.cos(), y, -ring * azimuth.sin()));
        }
    }
    let at = |i: u32, j: u32| i * (sectors + 1) + j;
    let mut faces = Vec::new();
    for i in 0..stacks {
        for j in 0..sectors {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if i != 0 {
                faces.push([a, b, d]);
            }
            if i != stacks - 1 {
                faces.push([d, b, c]);
            }
        }
    }
    TriMesh::new(positions, faces).unwrap()
}

/// The first pair of vertices that shared a position in `before` and no longer do in `after`
/// (which may have more vertices appended).
fn torn_apart(before: &TriMesh, after: &TriMesh) -> Option<(usize, usize, f32)> {
    let mut first: HashMap<[u32; 3], usize> = HashMap::new();
    for (v, &p) in before.positions().iter().enumerate() {
        let f = *first.entry(key(p)).or_insert(v);
        let (a, b) = (after.positions()[f], after.positions()[v]);
        if key(a) != key(b) {
            return Some((f, v, a.distance(b)));
        }
    }
    None
}

/// Groups of vertices that share a position in `mesh`, among those past `from` (new vertices).
fn shared_among_new(mesh: &TriMesh, from: usize) -> usize {
    let mut count: HashMap<[u32; 3], usize> = HashMap::new();
    mesh.positions()[from..].iter().for_each(|&p| *count.entry(key(p)).or_insert(0) += 1);
    count.values().filter(|&&n| n > 1).count()
}

/// A ball of `radius` touching `point` from outside along `-normal`.
fn ball_touching(point: Vec3, normal: Vec3, radius: f32) -> TriMesh {
    let mut ball = mesh::builtin("sphere").unwrap();
    let centre = point - normal * radius;
    ball.transform(Affine3A::from_scale_rotation_translation(Vec3::splat(radius), Default::default(), centre)).unwrap();
    ball
}

/// Body 1 (`ball`, world coordinates) falling at 10 m/s on body 0 (fixed) at `point`, the
/// normal straight down into it.
fn hit_from_above(point: Vec3, ball: &TriMesh) -> Hit<'_, u32> {
    let state = BodyState::moving(point + 0.25 * Vec3::Y, -10.0 * Vec3::Y, Vec3::ZERO, 1.0, Mat3::IDENTITY);
    Hit {
        target: 0,
        projectile: 1,
        impact: Impact::from_contact(point, -Vec3::Y, &BodyState::FIXED, &state).unwrap(),
        target_state: BodyState::FIXED,
        projectile_state: state,
        projectile_surface: Surface { mesh: ball, to_world: Affine3A::IDENTITY },
    }
}

fn game_params(d: f32) -> DentParams {
    DentParams { volume: VolumeMode::Preserve, ..DentParams::new(d) }
}

/// A 0.25 m ball 0.1 m from the top edge of the hard-edged cube, d = 0.15 m: the dent and its
/// rim reach over the edge onto the side face, and refinement splits faces on both sides.
#[test]
fn a_dent_near_a_hard_edge_keeps_the_cube_closed() {
    let cube = split_faces(&cube12());
    assert_eq!((cube.vertex_count(), unpaired_edges(&cube)), (24, 0));
    let point = Vec3::new(0.9, 1.0, 0.1);
    let impact = Impact { point, normal: -Vec3::Y, relative_velocity: -Vec3::Y };
    let mut dented = cube.clone();
    let report = dentbend::dent::dent(&mut dented, &ball_touching(point, -Vec3::Y, 0.25), &impact, &game_params(0.15))
        .expect("the dent is made");
    assert!(report.refined_triangles > 0 && report.moved_vertices > 0, "{report:?}");
    assert!(report.limited_to.is_none_or(|s| s > 0.5), "the dent was cut back: {report:?}");
    assert_eq!(unpaired_edges(&dented), 0, "the seams along the cube's edges cracked");
    assert_eq!(torn_apart(&cube, &dented), None, "corner vertices that shared a position moved apart");
    assert!(shared_among_new(&dented, cube.vertex_count()) > 0, "no new vertex was made on both sides of an edge");
}

/// The same through the damage API (`Damage::plan`, then `TargetSet::apply`), twice at the same
/// edge: a later dent starts from a refined, dented, hard-edged mesh.
#[test]
fn repeated_dents_through_the_damage_api_keep_the_cube_closed() {
    let cube = split_faces(&cube12());
    let settings = DentSettings { params: game_params(0.1), ..DentSettings::new(0.0, 0.02, 0.1) };
    let mut set = TargetSet::new();
    set.insert(0u32, cube.clone(), Affine3A::IDENTITY, settings).unwrap();
    set.insert_rigid(1);
    let mut damage = Damage::new();
    for (step, (x, z)) in [(0.9, 0.1), (0.85, -0.2)].into_iter().enumerate() {
        let point = Vec3::new(x, 1.0, z);
        let ball = ball_touching(point, -Vec3::Y, 0.25);
        let plan = damage.plan(&set, &[hit_from_above(point, &ball)], step as u64, &mut CpuBackend).expect("planned");
        assert_eq!(plan.dents.len(), 1, "no dent at step {step}");
        set.apply(plan.targets);
    }
    let dented = set.mesh(0).unwrap();
    assert!(dented.vertex_count() > cube.vertex_count(), "the damage API refined nothing");
    assert_eq!(unpaired_edges(dented), 0, "the seams along the cube's edges cracked");
    assert_eq!(torn_apart(&cube, dented), None);
}

/// A dent across a UV sphere's seam column, with the volume rim: both sides of the seam rise
/// together (before, the rim lifted them along their own sides' normals, up to 8 mm apart).
#[test]
fn a_dent_across_a_uv_seam_keeps_the_sphere_closed() {
    let sphere = seam_sphere(1.0, 32, 16, false);
    assert_eq!(unpaired_edges(&sphere), 0);
    // The seam runs along azimuth 0: the +x side of the sphere.
    let point = Vec3::new(1.0, 0.0, 0.0);
    let impact = Impact { point, normal: -Vec3::X, relative_velocity: -Vec3::X };
    let mut dented = sphere.clone();
    let report = dentbend::dent::dent(&mut dented, &ball_touching(point, -Vec3::X, 0.3), &impact, &game_params(0.15))
        .expect("the dent is made");
    assert!(report.moved_vertices > 0 && report.limited_to.is_none_or(|s| s > 0.5), "{report:?}");
    assert!(report.volume_change.abs() <= 0.02 * report.cavity_volume, "{report:?}");
    assert_eq!(torn_apart(&sphere, &dented), None, "the seam opened");
    assert_eq!(unpaired_edges(&dented), 0);
}

/// A seam computed at 2π lies a few ulps off: refused, naming the fix, the sphere unchanged;
/// `snap_seams` closes it, and then it dents.
#[test]
fn a_seam_that_nearly_coincides_is_refused_until_snapped() {
    let mut sphere = seam_sphere(1.0, 32, 16, true);
    let point = Vec3::new(1.0, 0.0, 0.0);
    let impact = Impact { point, normal: -Vec3::X, relative_velocity: -Vec3::X };
    let ball = ball_touching(point, -Vec3::X, 0.3);
    let before = sphere.clone();
    let error = dentbend::dent::dent(&mut sphere, &ball, &impact, &game_params(0.15)).expect_err("a near seam");
    assert!(matches!(error, DentError::NearlyCoincidentVertices { distance, .. } if distance > 0.0), "{error}");
    assert!(error.to_string().contains("weld the seam"), "{error}");
    assert_eq!(sphere, before, "a refused dent changed the mesh");

    // The seam and the poles' rows lie within 1e-6 of the first column and the pole.
    let snapped = sphere.snap_seams(1e-6).unwrap();
    assert!(snapped >= 16, "only {snapped} vertices snapped");
    assert_eq!(unpaired_edges(&sphere), 0);
    let report = dentbend::dent::dent(&mut sphere, &ball, &impact, &game_params(0.15)).expect("dents once snapped");
    assert!(report.moved_vertices > 0);
    assert!(sphere.snap_seams(f32::NAN).is_err());
}

/// The hard-edged cube with its authored normals: each side's vertices carry their face's normal.
fn flat_shaded_cube() -> TriMesh {
    let cube = split_faces(&cube12());
    let mut normals = vec![Vec3::ZERO; cube.vertex_count()];
    for f in cube.faces() {
        let [a, b, c] = f.map(|v| cube.positions()[v as usize]);
        f.iter().for_each(|&v| normals[v as usize] = (b - a).cross(c - a).normalize());
    }
    TriMesh::with_normals(cube.positions().to_vec(), cube.faces().to_vec(), normals).unwrap()
}

/// Authored normals survive a refined dent wherever nothing moved, bit for bit: the sides keep
/// their axis normals (hard edges stay hard), new vertices away from the dent get their parents'
/// normal, and only the normals around moved vertices are recomputed.
#[test]
fn authored_normals_stay_where_nothing_moved() {
    let cube = flat_shaded_cube();
    let settings = DentSettings { params: game_params(0.1), ..DentSettings::new(0.0, 0.01, 0.1) };
    let mut set = TargetSet::new();
    set.insert(0u32, cube.clone(), Affine3A::IDENTITY, settings).unwrap();
    set.insert_rigid(1);
    let point = Vec3::new(0.0, 1.0, 0.0);
    let ball = ball_touching(point, -Vec3::Y, 0.25);
    let plan = Damage::new().plan(&set, &[hit_from_above(point, &ball)], 0, &mut CpuBackend).expect("planned");
    let dented = &plan.targets[0];
    assert!(!dented.refinement.is_empty(), "the crate was not refined: the test checks no new vertex");
    // Where each vertex was before the displacement: new ones halfway along their parents, as
    // refinement computes them (a seam's sides from the same bits).
    let undented = dented.refinement.interpolate(cube.positions(), |a, b, _| *a * 0.5 + *b * 0.5).unwrap();
    let mesh = &dented.mesh;
    let moved: Vec<bool> = mesh.positions().iter().zip(&undented).map(|(p, q)| p != q).collect();
    assert!(moved.iter().any(|&m| m), "the dent moved nothing");
    let mut near = moved.clone();
    for f in mesh.faces().iter().filter(|f| f.iter().any(|&v| moved[v as usize])) {
        f.iter().for_each(|&v| near[v as usize] = true);
    }
    let base = cube.vertex_count();
    for v in (0..base).filter(|&v| !near[v]) {
        assert_eq!(mesh.normals()[v], cube.normals()[v], "base vertex {v}'s authored normal changed");
    }
    // New vertices away from the dent whose parents are too (the parents' normals then are the
    // ones they were interpolated from).
    let parents = |v: usize| dented.refinement.vertices[v - base].parents;
    let far_new: Vec<usize> =
        (base..mesh.vertex_count()).filter(|&v| !near[v] && parents(v).iter().all(|&p| !near[p as usize])).collect();
    assert!(!far_new.is_empty(), "every new vertex is near the dent: the check below tests nothing");
    for v in far_new {
        let [a, b] = parents(v).map(|p| mesh.normals()[p as usize]);
        assert_eq!(mesh.normals()[v], a.lerp(b, 0.5).normalize_or_zero(), "new vertex {v}, away from the dent");
        let flat = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
        assert!(flat.contains(&mesh.normals()[v]), "new vertex {v} left its side's flat normal: {}", mesh.normals()[v]);
    }
    // Around the dent the normals follow the crater: some tilt away from +y.
    assert!((0..mesh.vertex_count()).any(|v| moved[v] && mesh.normals()[v].y < 0.99));
}

#[test]
fn authored_normals_of_the_wrong_length_or_not_finite_are_refused() {
    let cube = split_faces(&cube12());
    let (p, f) = (cube.positions().to_vec(), cube.faces().to_vec());
    let short = TriMesh::with_normals(p.clone(), f.clone(), vec![Vec3::Y; 23]);
    assert!(matches!(short, Err(dentbend::MeshError::LengthMismatch { expected: 24, actual: 23 })), "{short:?}");
    let mut normals = vec![Vec3::Y; 24];
    normals[5] = Vec3::NAN;
    assert!(TriMesh::with_normals(p, f, normals).is_err());
}
