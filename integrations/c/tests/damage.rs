//! `db_damage_*`: bodies keyed by 64-bit ids, one step's hits dented and applied at once, the
//! results read back; bad steps refused with a message, no body changed.

use std::ffi::CStr;

use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_c::*;

const FLOOR: u64 = 10;
const BALL: u64 = 1 << 40;

fn last_error() -> String {
    // SAFETY: the library's message, NUL-terminated.
    unsafe { CStr::from_ptr(db_last_error()) }.to_string_lossy().into_owned()
}

fn made(m: &dentbend::TriMesh) -> *mut DbMesh {
    let positions: Vec<f32> = m.positions().iter().flat_map(|p| p.to_array()).collect();
    let indices: Vec<u32> = m.faces().iter().flatten().copied().collect();
    // SAFETY: both arrays are as long as the counts say.
    unsafe { db_mesh_new(positions.as_ptr(), m.vertex_count(), indices.as_ptr(), m.face_count()) }
}

/// A 4 × 0.5 × 4 m floor (top at y = 0.25) that dents 2 cm per m/s above 1 m/s, at most 15 cm,
/// and a ball projectile of radius 0.3 m.
fn world() -> (*mut DbDamage, *mut DbMesh) {
    let floor = made(&mesh::subdivided_box(Vec3::new(4.0, 0.5, 4.0), [32, 4, 32]).unwrap());
    let ball = made(&mesh::icosphere(0.3, 3).unwrap());
    let damage = db_damage_new();
    let identity = [1.0f32, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
    let settings = db_dent_settings_default(1.0, 0.02, 0.15);
    // SAFETY: live handles and valid arrays.
    unsafe {
        assert_eq!(db_damage_add_body(damage, FLOOR, floor, identity.as_ptr(), &settings), DB_OK, "{}", last_error());
        assert_eq!(db_damage_add_projectile(damage, BALL), DB_OK);
        db_mesh_free(floor);
    }
    (damage, ball)
}

/// The ball, 2 kg, centre 0.55 m up, falling at 8 m/s onto the floor's top.
fn hit(ball: *const DbMesh) -> DbHit {
    let inverse_inertia = 1.0 / (0.4 * 2.0 * 0.3 * 0.3);
    let fixed = DbBodyState {
        center_of_mass: [0.0; 3],
        linear_velocity: [0.0; 3],
        angular_velocity: [0.0; 3],
        mass: 0.0,
        inverse_inertia: [0.0; 9],
    };
    let falling = DbBodyState {
        center_of_mass: [0.0, 0.55, 0.0],
        linear_velocity: [0.0, -8.0, 0.0],
        mass: 2.0,
        inverse_inertia: [inverse_inertia, 0.0, 0.0, 0.0, inverse_inertia, 0.0, 0.0, 0.0, inverse_inertia],
        ..fixed
    };
    DbHit {
        target: FLOOR,
        projectile: BALL,
        point: [0.0, 0.25, 0.0],
        normal: [0.0, -1.0, 0.0],
        target_state: fixed,
        projectile_state: falling,
        projectile_surface: ball,
        projectile_to_world: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.55, 0.0],
    }
}

/// Body `id`'s positions, copied out.
fn positions(damage: *const DbDamage, id: u64) -> Vec<f32> {
    let mut count = 0;
    // SAFETY: live context; the pointer holds 3 floats a vertex.
    unsafe {
        let p = db_damage_positions(damage, id, &mut count);
        std::slice::from_raw_parts(p, 3 * count).to_vec()
    }
}

#[test]
fn a_step_dents_the_floor_and_reports_it() {
    let (damage, ball) = world();
    let before = positions(damage, FLOOR);
    let hits = [hit(ball)];
    // SAFETY: live handles and one valid hit.
    unsafe {
        assert_eq!(db_damage_step(damage, hits.as_ptr(), hits.len()), DB_OK, "{}", last_error());
        assert_eq!(db_damage_dent_count(damage), 1);
        let mut dent = DbAppliedDent::default();
        assert_eq!(db_damage_dent(damage, 0, &mut dent), DB_OK);
        assert_eq!((dent.target, dent.projectile), (FLOOR, BALL));
        // 8 m/s normal speed: (8 − 1) m/s × 2 cm per m/s = 14 cm, under the 15 cm cap.
        assert!((dent.dent_distance - 0.14).abs() < 1e-4, "{dent:?}");
        assert!(dent.depth_made > 0.07 && dent.depth_made <= dent.dent_distance + 1e-5, "{dent:?}");
        let mut n = 0;
        let moved = std::slice::from_raw_parts(db_damage_moved(damage, FLOOR, &mut n), n).to_vec();
        let after = positions(damage, FLOOR);
        assert!(!moved.is_empty());
        for v in 0..before.len().min(after.len()) / 3 {
            let changed = before[3 * v..3 * v + 3] != after[3 * v..3 * v + 3];
            assert_eq!(changed, moved.binary_search(&(v as u32)).is_ok(), "vertex {v}: listed iff it moved");
        }
        // An empty step dents nothing and moves nothing.
        assert_eq!(db_damage_step(damage, std::ptr::null(), 0), DB_OK);
        assert_eq!(db_damage_dent_count(damage), 0);
        assert!(db_damage_moved(damage, FLOOR, &mut n).is_null() && n == 0);
        db_damage_free(damage);
        db_mesh_free(ball);
    }
}

#[test]
fn bad_steps_are_refused_and_change_no_body() {
    let (damage, ball) = world();
    let before = positions(damage, FLOOR);
    let mut unknown = hit(ball);
    unknown.target = 99;
    let mut nan = hit(ball);
    nan.projectile_state.linear_velocity[1] = f32::NAN;
    let mut no_surface = hit(ball);
    no_surface.projectile_surface = std::ptr::null();
    let mut bad_pose = hit(ball);
    bad_pose.projectile_to_world[9] = f32::INFINITY;
    let cases = [
        ("unknown body", unknown, "99"),
        ("NaN velocity", nan, "hit 1"),
        ("no surface", no_surface, "projectile_surface is null"),
        ("infinite pose", bad_pose, "not finite"),
    ];
    for (what, bad, says) in cases {
        let hits = [hit(ball), bad];
        // SAFETY: live handles; the hits are what each case says.
        let status = unsafe { db_damage_step(damage, hits.as_ptr(), hits.len()) };
        assert_eq!(status, DB_ERR_INVALID_ARGUMENT, "{what}: {}", last_error());
        assert!(last_error().contains(says), "{what}: {}", last_error());
        assert_eq!(positions(damage, FLOOR), before, "{what}: the good hit beside it was not made either");
    }
    // SAFETY: null and absurd arguments are refused.
    unsafe {
        assert_eq!(db_damage_step(damage, std::ptr::null(), 1), DB_ERR_NULL_POINTER);
        assert_eq!(db_damage_step(std::ptr::null_mut(), std::ptr::null(), 0), DB_ERR_NULL_POINTER);
        assert_eq!(db_damage_step(damage, std::ptr::null(), usize::MAX), DB_ERR_INVALID_ARGUMENT);
        assert_eq!(db_damage_dent(damage, 0, std::ptr::null_mut()), DB_ERR_INVALID_ARGUMENT, "no dent 0 yet");
        let mut n = 7;
        assert!(db_damage_positions(damage, 12345, &mut n).is_null() && n == 0, "an unknown body reads as empty");
        let identity = [1.0f32, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
        let mut bad = db_dent_settings_default(1.0, 0.02, 0.15);
        bad.max_depth = f32::NAN;
        assert_eq!(db_damage_add_body(damage, 5, ball, identity.as_ptr(), &bad), DB_ERR_INVALID_ARGUMENT);
        assert_eq!(db_damage_add_body(damage, 5, ball, std::ptr::null(), &bad), DB_ERR_NULL_POINTER);
        db_damage_free(damage);
        db_mesh_free(ball);
    }
}
