//! The C API called as C calls it: meshes in and out through flat arrays, a dent, and every
//! kind of bad call refused with a status and a message, changing nothing.

mod common;

use common::{last_error, made};
use dentbend::mesh;
use dentbend_c::*;

/// The positions of `mesh`, copied out.
fn positions(mesh: *const DbMesh) -> Vec<f32> {
    // SAFETY: a live mesh; the pointer holds 3 floats a vertex.
    unsafe { std::slice::from_raw_parts(db_mesh_positions(mesh), 3 * db_mesh_vertex_count(mesh)).to_vec() }
}

/// A unit sphere and a 0.3 m ball resting on its top.
fn pair() -> (*mut DbMesh, *mut DbMesh) {
    let target = made(&mesh::icosphere(1.0, 3).unwrap());
    let mut ball = mesh::icosphere(0.3, 2).unwrap();
    ball.transform(dentbend::glam::Affine3A::from_translation(dentbend::glam::Vec3::new(0.0, 1.3, 0.0))).unwrap();
    (target, made(&ball))
}

const DOWN: DbImpact =
    DbImpact { point: [0.0, 1.0, 0.0], normal: [0.0, -1.0, 0.0], relative_velocity: [0.0, -3.0, 0.0] };

#[test]
fn a_dent_through_the_c_api_moves_what_it_reports() {
    let (target, ball) = pair();
    let before = positions(target);
    let options = db_dent_options_default(0.1);
    let mut report = DbDentReport::default();
    // SAFETY: live, distinct meshes and valid structs.
    let status = unsafe { db_dent_ex(target, ball, &DOWN, &options, &mut report) };
    assert_eq!(status, DB_OK, "{}", last_error());
    let after = positions(target);
    // The deepest move is the dent distance, 0.1 m (f32 rounding of a unit sphere's top).
    assert!(report.max_displacement > 0.05 && report.max_displacement <= 0.1 + 1e-5, "{report:?}");
    // SAFETY: live mesh; the pointer holds `db_mesh_moved_count` indices.
    let moved = unsafe { std::slice::from_raw_parts(db_mesh_moved(target), db_mesh_moved_count(target)) };
    assert_eq!(moved.len(), report.moved_vertices + report.added_vertices);
    for v in 0..before.len() / 3 {
        let changed = before[3 * v..3 * v + 3] != after[3 * v..3 * v + 3];
        assert_eq!(changed, moved.binary_search(&(v as u32)).is_ok(), "vertex {v}: listed as moved iff it moved");
    }
    // SAFETY: live meshes, freed once.
    unsafe {
        db_mesh_free(target);
        db_mesh_free(ball);
    }
}

/// Where handles are tracked, a handle of one kind passed as another is refused, and freeing
/// it as the wrong kind leaves it alone.
#[cfg(any(debug_assertions, feature = "track-handles"))]
#[test]
fn a_handle_of_another_kind_is_caught_where_handles_are_tracked() {
    let (target, ball) = pair();
    let posing_as_damage = target.cast::<DbDamage>();
    // SAFETY: the wrong kind of handle is what tracked builds catch.
    unsafe {
        assert_eq!(db_damage_step(posing_as_damage, std::ptr::null(), 0), DB_ERR_INVALID_ARGUMENT);
        assert!(last_error().contains("another kind"), "{}", last_error());
        db_damage_free(posing_as_damage);
        assert_eq!(db_mesh_vertex_count(target), 642, "the mesh is still there");
        db_mesh_free(target);
        db_mesh_free(ball);
    }
}

#[test]
fn bad_calls_are_refused_with_a_message_and_change_nothing() {
    let (target, ball) = pair();
    let before = positions(target);
    let nan_point = DbImpact { point: [f32::NAN, 1.0, 0.0], ..DOWN };
    let mut bad_sigma = db_dent_options_default(0.1);
    bad_sigma.sigma = -1.0;
    let refused = |what: &str, status: std::ffi::c_int, expected: std::ffi::c_int, says: &str| {
        assert_eq!(status, expected, "{what}: {}", last_error());
        assert!(last_error().contains(says), "{what}: {}", last_error());
        assert_eq!(positions(target), before, "{what}: nothing changed");
    };
    let (null, invalid) = (DB_ERR_NULL_POINTER, DB_ERR_INVALID_ARGUMENT);
    // SAFETY: each call passes live meshes or null, and valid structs or null.
    unsafe {
        refused("null target", db_dent(std::ptr::null_mut(), ball, &DOWN, 0.1), null, "target is null");
        refused("null projectile", db_dent(target, std::ptr::null(), &DOWN, 0.1), null, "projectile is null");
        refused("null impact", db_dent(target, ball, std::ptr::null(), 0.1), null, "impact is null");
        let no_options = std::ptr::null();
        refused("null options", db_dent_ex(target, ball, &DOWN, no_options, std::ptr::null_mut()), null, "options");
        refused("itself", db_dent(target, target, &DOWN, 0.1), invalid, "same mesh");
        refused("NaN distance", db_dent(target, ball, &DOWN, f32::NAN), invalid, "dent_distance");
        refused("infinite distance", db_dent(target, ball, &DOWN, f32::INFINITY), invalid, "dent_distance");
        refused("negative distance", db_dent(target, ball, &DOWN, -0.1), invalid, "dent_distance");
        refused("NaN point", db_dent(target, ball, &nan_point, 0.1), invalid, "not finite");
        refused("negative sigma", db_dent_ex(target, ball, &DOWN, &bad_sigma, std::ptr::null_mut()), invalid, "sigma");
    }
    // SAFETY: live meshes, freed once.
    unsafe {
        db_mesh_free(target);
        db_mesh_free(ball);
    }
}

#[test]
fn bad_meshes_are_refused_with_a_message() {
    let tri = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let mut nan = tri;
    nan[4] = f32::NAN;
    let mut huge = tri;
    huge[0] = 1e30;
    let face = [0u32, 1, 2];
    let far = [0u32, 1, 3];
    let refused = |what: &str, handle: *mut DbMesh, says: &str| {
        assert!(handle.is_null(), "{what}: refused");
        assert!(last_error().contains(says), "{what}: {}", last_error());
    };
    // SAFETY: each array is as long as its count says, or the pointer is null.
    unsafe {
        refused("NaN", db_mesh_new(nan.as_ptr(), 3, face.as_ptr(), 1), "non-finite");
        refused("huge", db_mesh_new(huge.as_ptr(), 3, face.as_ptr(), 1), "beyond");
        refused("index", db_mesh_new(tri.as_ptr(), 3, far.as_ptr(), 1), "vertex 3");
        refused("null positions", db_mesh_new(std::ptr::null(), 3, face.as_ptr(), 1), "positions is null");
        refused("null indices", db_mesh_new(tri.as_ptr(), 3, std::ptr::null(), 1), "indices is null");
        refused("empty", db_mesh_new(std::ptr::null(), 0, std::ptr::null(), 0), "empty");
        refused("absurd count", db_mesh_new(tri.as_ptr(), usize::MAX / 2, face.as_ptr(), 1), "garbage");
    }
    // SAFETY: null handles are allowed.
    unsafe {
        assert_eq!(db_mesh_vertex_count(std::ptr::null()), 0);
        assert!(db_mesh_positions(std::ptr::null()).is_null());
        db_mesh_free(std::ptr::null_mut());
    }
}

/// Debug builds of the library (and the `track-handles` feature) track live meshes: a second
/// free, or a freed mesh used, is an error with a message instead of undefined behaviour.
#[cfg(any(debug_assertions, feature = "track-handles"))]
#[test]
fn a_mesh_freed_twice_is_caught_in_debug_builds() {
    let (target, ball) = pair();
    // SAFETY: the second free and the use after it are what debug builds catch.
    unsafe {
        db_mesh_free(target);
        db_mesh_free(target);
        assert!(last_error().contains("not alive"), "{}", last_error());
        assert_eq!(db_dent(target, ball, &DOWN, 0.1), DB_ERR_INVALID_ARGUMENT);
        assert!(last_error().contains("target is not alive"), "{}", last_error());
        db_mesh_free(ball);
    }
}

/// A game asset through the C API: the built-in crate (24 vertices split at its hard edges, UV
/// mapped) with its authored normals and UVs. A dent near an edge refines it; the UVs and
/// normals follow (one per vertex, finite, unit normals), and vertices that shared a position
/// still do: the seams do not crack.
#[test]
fn uvs_and_hard_edges_follow_a_dent_without_cracks() {
    let asset = mesh::builtin_asset("crate").unwrap();
    let m = asset.mesh();
    let positions: Vec<f32> = m.positions().iter().flat_map(|p| p.to_array()).collect();
    let indices: Vec<u32> = m.faces().iter().flatten().copied().collect();
    let normals: Vec<f32> = asset.attributes().normals.as_ref().unwrap().iter().flat_map(|n| n.to_array()).collect();
    let uvs: Vec<f32> = asset.attributes().uvs[0].iter().flat_map(|uv| uv.to_array()).collect();
    let (lo, hi) = m.bounds();
    // SAFETY: every array is as long as the counts say.
    let target = unsafe {
        db_mesh_new_with_attributes(
            positions.as_ptr(),
            m.vertex_count(),
            indices.as_ptr(),
            m.face_count(),
            normals.as_ptr(),
            uvs.as_ptr(),
        )
    };
    assert!(!target.is_null(), "{}", last_error());
    // A 0.2 m ball on the top face, near an edge.
    let top = hi.y;
    let mut ball = mesh::icosphere(0.2 * (hi.x - lo.x), 2).unwrap();
    let at = dentbend::glam::Vec3::new(0.3 * hi.x, top + 0.2 * (hi.x - lo.x), 0.0);
    ball.transform(dentbend::glam::Affine3A::from_translation(at)).unwrap();
    let ball = made(&ball);
    let impact = DbImpact { point: [at.x, top, 0.0], normal: [0.0, -1.0, 0.0], relative_velocity: [0.0, -3.0, 0.0] };
    let options = DbDentOptions { preserve_volume: 1, ..db_dent_options_default(0.1 * (hi.y - lo.y)) };
    let mut report = DbDentReport::default();
    // SAFETY: live meshes and valid structs; every array read back is `vertex_count` long.
    unsafe {
        assert_eq!(db_dent_ex(target, ball, &impact, &options, &mut report), DB_OK, "{}", last_error());
        assert!(report.added_vertices > 0, "the 12-triangle crate is refined under the dent: {report:?}");
        let n = db_mesh_vertex_count(target);
        let after = std::slice::from_raw_parts(db_mesh_positions(target), 3 * n);
        let uv = std::slice::from_raw_parts(db_mesh_uvs(target), 2 * n);
        let normal = std::slice::from_raw_parts(db_mesh_normals(target), 3 * n);
        assert!(uv.iter().all(|x| x.is_finite()), "every vertex has finite UVs");
        for v in 0..n {
            let length = (normal[3 * v].powi(2) + normal[3 * v + 1].powi(2) + normal[3 * v + 2].powi(2)).sqrt();
            assert!((length - 1.0).abs() < 1e-3, "vertex {v}'s normal has length {length}");
        }
        // Seams: vertices that shared a position before the dent share it after.
        let before = m.positions();
        for a in 0..before.len() {
            for b in a + 1..before.len() {
                if before[a] == before[b] {
                    assert_eq!(after[3 * a..3 * a + 3], after[3 * b..3 * b + 3], "vertices {a} and {b} cracked apart");
                }
            }
        }
        db_mesh_free(target);
        db_mesh_free(ball);
    }
}
