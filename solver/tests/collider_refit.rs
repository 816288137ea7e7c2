//! Collider refits after a dent: a refitted parry3d triangle mesh answers
//! queries exactly as a fresh build on the dented vertices does; bad updates are refused and
//! leave the shape as it was; the world's dented colliders follow their meshes.

use dentbend::collider::{RefitError, VertexMap, refit_shared_trimesh, refit_trimesh};
use dentbend::dent::moved_vertices;
use dentbend::glam::{Affine3A, Vec3};
use dentbend::{DentParams, Impact, TriMesh, dent, mesh};
use dentbend_solver::coupling::Simulation;
use dentbend_solver::sim::{BodyDesc, BodyKind, ColliderKind, DentSettings, World, WorldSettings};
use parry3d::query::{PointQuery, Ray, RayCast};
use parry3d::shape::{SharedShape, TriMesh as ParryMesh, TriMeshFlags};

/// dentbend's world collider flags: pseudo-normals, and parry renumbers the vertices.
fn world_flags() -> TriMeshFlags {
    TriMeshFlags::DEFORMABLE | TriMeshFlags::DELETE_DEGENERATE_TRIANGLES | TriMeshFlags::FIX_INTERNAL_EDGES
}

fn collider(mesh: &TriMesh, flags: TriMeshFlags) -> ParryMesh {
    ParryMesh::with_flags(mesh.positions().to_vec(), mesh.faces().to_vec(), flags).unwrap()
}

/// A unit UV sphere of 24,960 triangles, and the same sphere dented 0.15 deep at its top by a ball
/// of radius 0.2.
fn dented_sphere() -> (TriMesh, TriMesh) {
    let target = mesh::uv_sphere(1.0, 160, 79).unwrap();
    assert_eq!(target.face_count(), 24_960);
    let mut ball = mesh::icosphere(0.2, 3).unwrap();
    ball.transform(Affine3A::from_translation(Vec3::new(0.0, 1.2, 0.0))).unwrap();
    let impact = Impact { point: Vec3::Y, normal: -Vec3::Y, relative_velocity: -Vec3::Y };
    let mut dented = target.clone();
    let report = dent(&mut dented, &ball, &impact, &DentParams::new(0.15)).unwrap();
    assert!(report.moved_vertices > 100 && report.max_displacement > 0.1, "{report:?}");
    (target, dented)
}

/// Query points: a Fibonacci sphere of directions at radii inside, on and outside the surface,
/// plus a dense patch around the dent at the top.
fn probes() -> Vec<Vec3> {
    let n = 400;
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let mut points = Vec::new();
    for i in 0..n {
        let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
        let r = (1.0 - y * y).sqrt();
        let dir = Vec3::new(r * (golden * i as f32).cos(), y, r * (golden * i as f32).sin());
        points.extend([0.5, 0.97, 1.0, 1.03, 1.5].map(|s| dir * s));
    }
    for i in -10..=10 {
        for k in -10..=10 {
            for y in [0.8, 0.88, 0.95, 1.02] {
                points.push(Vec3::new(i as f32 * 0.03, y, k as f32 * 0.03));
            }
        }
    }
    points
}

/// Asserts `a` and `b` answer every query alike. Same triangles, same arithmetic: the times of
/// impact and distances agree to 1e-6 (only which of two tied triangles a traversal reports
/// first may differ, not the value).
fn assert_same_queries(a: &ParryMesh, b: &ParryMesh) {
    assert_eq!(a.local_aabb(), b.local_aabb());
    for p in probes() {
        for solid in [true, false] {
            let (pa, pb) = (a.project_local_point(p, solid), b.project_local_point(p, solid));
            assert!(
                (pa.point - pb.point).length() < 1e-6 || (p.distance(pa.point) - p.distance(pb.point)).abs() < 1e-6
            );
            assert_eq!(pa.is_inside, pb.is_inside, "inside at {p} (solid {solid})");
        }
        assert_eq!(a.contains_local_point(p), b.contains_local_point(p), "contains {p}");
        for dir in [-p.normalize_or(Vec3::Y), Vec3::NEG_Y, Vec3::new(0.3, -1.0, 0.2).normalize()] {
            let ray = Ray::new(p + Vec3::Y * 2.0, dir);
            let (ta, tb) = (a.cast_local_ray(&ray, 10.0, true), b.cast_local_ray(&ray, 10.0, true));
            match (ta, tb) {
                (Some(ta), Some(tb)) => assert!((ta - tb).abs() < 1e-6, "ray from {}: {ta} vs {tb}", ray.origin),
                (ta, tb) => assert_eq!(ta, tb, "ray from {}", ray.origin),
            }
        }
    }
}

#[test]
fn a_refitted_collider_answers_like_a_fresh_build() {
    let (target, dented) = dented_sphere();
    // The containment checks only bite with ORIENTED (parry's inside test needs it).
    for flags in [world_flags(), TriMeshFlags::DEFORMABLE, world_flags() | TriMeshFlags::ORIENTED] {
        let mut shape = collider(&target, flags);
        let map = VertexMap::new(&shape, target.positions(), target.faces()).unwrap();
        let (moved, positions) = map.moved_between(target.positions(), dented.positions());
        assert!(!moved.is_empty() && moved.len() < shape.vertices().len() / 2, "{} moved", moved.len());
        let stats = refit_trimesh(&mut shape, &moved, &positions).unwrap();
        assert_eq!(stats.moved_vertices, moved.len());
        assert_eq!(stats.pseudo_normals_recomputed, flags != TriMeshFlags::DEFORMABLE);
        let fresh = collider(&dented, flags);
        assert_eq!(shape.vertices(), fresh.vertices(), "{flags:?}");
        assert_eq!(
            shape.pseudo_normals().map(|p| (&p.vertices_pseudo_normal, &p.edges_pseudo_normal)),
            fresh.pseudo_normals().map(|p| (&p.vertices_pseudo_normal, &p.edges_pseudo_normal)),
        );
        assert_same_queries(&shape, &fresh);
    }
}

/// Guards the test above: the dent is visible to queries, so a skipped refit would fail it.
#[test]
fn an_unrefitted_collider_misses_the_dent() {
    let (target, dented) = dented_sphere();
    // ORIENTED: parry only tells inside from outside with oriented pseudo-normals.
    let flags = world_flags() | TriMeshFlags::ORIENTED;
    let (stale, fresh) = (collider(&target, flags), collider(&dented, flags));
    let ray = Ray::new(Vec3::new(0.0, 3.0, 0.0), Vec3::NEG_Y);
    let (ts, tf) = (stale.cast_local_ray(&ray, 10.0, true).unwrap(), fresh.cast_local_ray(&ray, 10.0, true).unwrap());
    assert!(tf - ts > 0.1, "stale {ts}, fresh {tf}");
    // Between the old top and the dented one.
    let below_the_old_top = Vec3::new(0.0, 3.0 - 0.5 * (ts + tf), 0.0);
    assert!(
        stale.contains_local_point(below_the_old_top) && !fresh.contains_local_point(below_the_old_top),
        "{below_the_old_top}: stale {}, fresh {}",
        stale.contains_local_point(below_the_old_top),
        fresh.contains_local_point(below_the_old_top)
    );
}

#[test]
fn moved_vertices_lists_exactly_the_changed_ones_and_an_empty_update_is_free() {
    let (target, dented) = dented_sphere();
    let moved = moved_vertices(target.positions(), dented.positions());
    let expected: Vec<u32> = (0..target.vertex_count() as u32)
        .filter(|&i| target.positions()[i as usize] != dented.positions()[i as usize])
        .collect();
    assert_eq!(moved, expected);
    // Plain flags keep parry's numbering equal to the mesh's: the indices apply directly.
    let mut shape = collider(&target, TriMeshFlags::DEFORMABLE);
    let positions: Vec<Vec3> = moved.iter().map(|&i| dented.positions()[i as usize]).collect();
    refit_trimesh(&mut shape, &moved, &positions).unwrap();
    assert_eq!(shape.vertices(), dented.positions());
    assert_eq!(refit_trimesh(&mut shape, &[], &[]).unwrap().refitted_leaves, 0);
}

#[test]
fn bad_updates_are_refused_and_change_nothing() {
    let (target, _) = dented_sphere();
    let original = collider(&target, world_flags());
    let n = original.vertices().len();
    let cases: [(&[u32], &[Vec3], RefitError); 5] = [
        (&[1, 2], &[Vec3::ONE], RefitError::LengthMismatch { moved: 2, positions: 1 }),
        (
            &[1, n as u32],
            &[Vec3::ONE, Vec3::ONE],
            RefitError::UnknownVertex { entry: 1, index: n as u32, vertex_count: n },
        ),
        (&[5, 5], &[Vec3::ONE, Vec3::ONE], RefitError::DuplicateVertex { entry: 1, index: 5 }),
        (
            &[0, 7],
            &[Vec3::ZERO, Vec3::new(0.0, f32::NAN, 0.0)],
            RefitError::NonFinite { entry: 1, index: 7, position: Vec3::new(0.0, f32::NAN, 0.0) },
        ),
        (
            &[3],
            &[Vec3::new(f32::INFINITY, 0.0, 0.0)],
            RefitError::NonFinite { entry: 0, index: 3, position: Vec3::new(f32::INFINITY, 0.0, 0.0) },
        ),
    ];
    for (moved, positions, expected) in cases {
        let mut shape = original.clone();
        let error = refit_trimesh(&mut shape, moved, positions).unwrap_err();
        // NaN != NaN: compare the printed errors.
        assert_eq!(error.to_string(), expected.to_string());
        assert_eq!(shape.vertices(), original.vertices());
        assert_eq!(shape.local_aabb(), original.local_aabb());
        let mut shared = SharedShape::new(original.clone());
        let before = shared.clone();
        assert_eq!(refit_shared_trimesh(&mut shared, moved, positions).unwrap_err().to_string(), expected.to_string());
        assert_eq!(shared.as_trimesh().unwrap().vertices(), before.as_trimesh().unwrap().vertices());
    }
    let mut ball = SharedShape::ball(1.0);
    assert_eq!(refit_shared_trimesh(&mut ball, &[0], &[Vec3::ONE]), Err(RefitError::NotTriMesh));
}

#[test]
fn a_shared_refit_copies_on_write() {
    let (target, dented) = dented_sphere();
    let mut shared = SharedShape::new(collider(&target, world_flags()));
    let other = shared.clone();
    let map = VertexMap::new(shared.as_trimesh().unwrap(), target.positions(), target.faces()).unwrap();
    let (moved, positions) = map.moved_between(target.positions(), dented.positions());
    refit_shared_trimesh(&mut shared, &moved, &positions).unwrap();
    assert_eq!(shared.as_trimesh().unwrap().vertices(), collider(&dented, world_flags()).vertices());
    assert_eq!(other.as_trimesh().unwrap().vertices(), collider(&target, world_flags()).vertices());
}

/// The world's dented triangle-mesh collider equals a fresh build from the body's dented mesh
/// (parry renumbers the collider's vertices: the refit must map them, not copy in mesh order).
#[test]
fn the_worlds_dented_collider_follows_the_mesh() {
    let settings = WorldSettings { gravity: Vec3::ZERO, sleep_time: 0.0, ..Default::default() };
    let mut world = World::new(settings).unwrap();
    let sphere = mesh::uv_sphere(1.0, 48, 24).unwrap();
    let target = world
        .add(
            BodyDesc::new("target", sphere)
                .kind(BodyKind::Static)
                .collider(ColliderKind::TriMesh)
                .dentable(DentSettings::new(1.0, 0.04, 0.3)),
        )
        .unwrap();
    let ball = mesh::icosphere(0.3, 3).unwrap();
    world
        .add(
            BodyDesc::new("ball", ball)
                .at(Vec3::new(0.05, 1.6, 0.02))
                .velocity(Vec3::new(0.0, -6.0, 0.0))
                .collider(ColliderKind::Ball),
        )
        .unwrap();
    let mut sim = Simulation::new(world, None).unwrap();
    for _ in 0..60 {
        sim.step().unwrap();
    }
    assert!(!sim.dents().is_empty(), "no dent");
    let body = &sim.world().bodies()[target];
    let fresh = ColliderKind::TriMesh.build_for(BodyKind::Static, body.mesh()).unwrap();
    let (shape, fresh) = (body.shape().as_trimesh().unwrap(), fresh.as_trimesh().unwrap());
    assert_eq!(shape.vertices(), fresh.vertices());
    assert_same_queries(shape, fresh);
}
