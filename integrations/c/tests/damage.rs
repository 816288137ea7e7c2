//! `db_damage_*`: bodies keyed by 64-bit ids, one step's hits dented and applied at once, the
//! results read back; bad steps refused with a message, no body changed.

mod common;

use common::{IDENTITY, falling_ball, last_error, made};
use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_c::*;

const FLOOR: u64 = 10;
const BALL: u64 = 1 << 40;

/// A 4 × 0.5 × 4 m floor (top at y = 0.25) that dents 2 cm per m/s above 1 m/s, at most 15 cm,
/// and a ball projectile of radius 0.3 m.
fn world() -> (*mut DbDamage, *mut DbMesh) {
    let floor = made(&mesh::subdivided_box(Vec3::new(4.0, 0.5, 4.0), [32, 4, 32]).unwrap());
    let ball = made(&mesh::icosphere(0.3, 3).unwrap());
    let damage = db_damage_new();
    let settings = db_dent_settings_default(1.0, 0.02, 0.15);
    // SAFETY: live handles and valid arrays.
    unsafe {
        assert_eq!(db_damage_add_body(damage, FLOOR, floor, IDENTITY.as_ptr(), &settings), DB_OK, "{}", last_error());
        assert_eq!(db_damage_add_projectile(damage, BALL), DB_OK);
        db_mesh_free(floor);
    }
    (damage, ball)
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
    let hits = [falling_ball(FLOOR, BALL, ball, 0.0, 0.0, 8.0)];
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
    let mut unknown = falling_ball(FLOOR, BALL, ball, 0.0, 0.0, 8.0);
    unknown.target = 99;
    let mut nan = falling_ball(FLOOR, BALL, ball, 0.0, 0.0, 8.0);
    nan.projectile_state.linear_velocity[1] = f32::NAN;
    let mut no_surface = falling_ball(FLOOR, BALL, ball, 0.0, 0.0, 8.0);
    no_surface.projectile_surface = std::ptr::null();
    let mut nan_mass = falling_ball(FLOOR, BALL, ball, 0.0, 0.0, 8.0);
    nan_mass.projectile_state.mass = f32::NAN;
    let mut bad_pose = falling_ball(FLOOR, BALL, ball, 0.0, 0.0, 8.0);
    bad_pose.projectile_to_world[9] = f32::INFINITY;
    let cases = [
        ("unknown body", unknown, "99"),
        ("NaN velocity", nan, "hit 1"),
        ("no surface", no_surface, "projectile_surface is null"),
        ("infinite pose", bad_pose, "not finite"),
        ("NaN mass", nan_mass, "mass"),
    ];
    for (what, bad, says) in cases {
        let hits = [falling_ball(FLOOR, BALL, ball, 0.0, 0.0, 8.0), bad];
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
        let mut bad = db_dent_settings_default(1.0, 0.02, 0.15);
        bad.max_depth = f32::NAN;
        assert_eq!(db_damage_add_body(damage, 5, ball, IDENTITY.as_ptr(), &bad), DB_ERR_INVALID_ARGUMENT);
        assert_eq!(db_damage_add_body(damage, 5, ball, std::ptr::null(), &bad), DB_ERR_NULL_POINTER);
        db_damage_free(damage);
        db_mesh_free(ball);
    }
}
