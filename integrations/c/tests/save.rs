//! `db_damage_record` / `db_damage_save` / `db_damage_restore`: a saved body's mesh comes back
//! bit for bit with no simulation; a file for another mesh, a truncated file or a name it does
//! not have is refused and changes nothing.

use std::ffi::CString;

mod common;

use common::{IDENTITY, falling_ball, last_error, made};
use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_c::*;

const FLOOR: u64 = 3;
const BALL: u64 = 4;

/// A context with `floor` as body FLOOR and the ball as a projectile.
fn context(floor: *const DbMesh) -> *mut DbDamage {
    let damage = db_damage_new();
    let settings = db_dent_settings_default(1.0, 0.02, 0.15);
    // SAFETY: live handles and valid arrays.
    unsafe {
        assert_eq!(db_damage_add_body(damage, FLOOR, floor, IDENTITY.as_ptr(), &settings), DB_OK);
        assert_eq!(db_damage_add_projectile(damage, BALL), DB_OK);
    }
    damage
}

fn positions(damage: *const DbDamage) -> Vec<f32> {
    let mut n = 0;
    // SAFETY: live context; 3 floats a vertex.
    unsafe { std::slice::from_raw_parts(db_damage_positions(damage, FLOOR, &mut n), 3 * n) }.to_vec()
}

#[test]
fn a_saved_body_is_restored_bit_for_bit_and_bad_files_are_refused() {
    let floor_mesh = mesh::subdivided_box(Vec3::new(4.0, 0.5, 4.0), [32, 4, 32]).unwrap();
    let (floor, ball) = (made(&floor_mesh), made(&mesh::icosphere(0.3, 2).unwrap()));
    let name = CString::new("floor").unwrap();
    let server = context(floor);
    // SAFETY: live handles, valid arrays, strings and structs throughout.
    unsafe {
        assert_eq!(db_damage_record(server, FLOOR, name.as_ptr()), DB_OK, "{}", last_error());
        for (x, speed) in [(-1.0, 6.0), (1.0, 9.0)] {
            let hits = [falling_ball(FLOOR, BALL, ball, x, 0.0, speed)];
            assert_eq!(db_damage_step(server, hits.as_ptr(), 1), DB_OK, "{}", last_error());
        }
        let mut length = 0;
        let file = std::slice::from_raw_parts(db_damage_save(server, &mut length), length).to_vec();
        assert!(!file.is_empty());

        let restored = context(floor);
        let before = positions(restored);
        assert_ne!(before, positions(server), "the server's floor is dented");
        // Refused, nothing changed: truncated, a name the file lacks, another mesh.
        let other_floor = made(&mesh::subdivided_box(Vec3::new(4.0, 0.5, 4.0), [16, 4, 16]).unwrap());
        let other = context(other_floor);
        let other_before = positions(other);
        let wrong = CString::new("wall").unwrap();
        assert_eq!(
            db_damage_restore(restored, FLOOR, file.as_ptr(), file.len() / 2, name.as_ptr()),
            DB_ERR_INVALID_ARGUMENT
        );
        assert_eq!(
            db_damage_restore(restored, FLOOR, file.as_ptr(), file.len(), wrong.as_ptr()),
            DB_ERR_INVALID_ARGUMENT
        );
        assert!(last_error().contains("wall"), "{}", last_error());
        assert_eq!(db_damage_restore(other, FLOOR, file.as_ptr(), file.len(), name.as_ptr()), DB_ERR_INVALID_ARGUMENT);
        assert_eq!(positions(restored), before);
        assert_eq!(positions(other), other_before, "a file for another mesh changes nothing");
        assert_eq!(db_damage_restore(restored, FLOOR, std::ptr::null(), 10, name.as_ptr()), DB_ERR_NULL_POINTER);
        // A body on a replication stream is refused: its clients would dent the mesh they have.
        let carried = context(floor);
        assert_eq!(db_damage_replicate(carried, FLOOR, 1), DB_OK);
        assert_eq!(
            db_damage_restore(carried, FLOOR, file.as_ptr(), file.len(), name.as_ptr()),
            DB_ERR_INVALID_ARGUMENT
        );
        assert!(last_error().contains("replication stream"), "{}", last_error());
        db_damage_free(carried);
        // Restored: the server's mesh, bit for bit.
        assert_eq!(
            db_damage_restore(restored, FLOOR, file.as_ptr(), file.len(), name.as_ptr()),
            DB_OK,
            "{}",
            last_error()
        );
        assert_eq!(positions(restored), positions(server));
        let mut moved = 0;
        assert!(!db_damage_moved(restored, FLOOR, &mut moved).is_null() && moved > 0);
        for handle in [server, restored, other] {
            db_damage_free(handle);
        }
        for mesh in [floor, ball, other_floor] {
            db_mesh_free(mesh);
        }
    }
}
