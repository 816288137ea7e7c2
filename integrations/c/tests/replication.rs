//! `db_damage_replicate` / `db_replica_*`: a server context's messages make a client's meshes
//! the server's bit for bit, a late joiner's snapshot too; a message out of order, repeated or
//! truncated is refused and changes nothing.

mod common;

use common::{IDENTITY, falling_ball, last_error, made};
use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_c::*;

const FLOOR: u64 = 10;
const BALL: u64 = 20;
const WIRE_FLOOR: u32 = 1;
const BALL_SHAPE: u32 = 7;

fn bytes(pointer: *const u8, length: usize) -> Vec<u8> {
    // SAFETY: the library's array of `length` bytes (or null with 0).
    if pointer.is_null() { Vec::new() } else { unsafe { std::slice::from_raw_parts(pointer, length) }.to_vec() }
}

/// A body's positions on the server and on a replica.
fn server_positions(damage: *const DbDamage) -> Vec<f32> {
    let mut n = 0;
    // SAFETY: live context; 3 floats a vertex.
    unsafe { std::slice::from_raw_parts(db_damage_positions(damage, FLOOR, &mut n), 3 * n) }.to_vec()
}

fn replica_positions(replica: *mut DbReplica) -> Vec<f32> {
    let mut n = 0;
    // SAFETY: live replica; 3 floats a vertex.
    unsafe { std::slice::from_raw_parts(db_replica_positions(replica, WIRE_FLOOR, &mut n), 3 * n) }.to_vec()
}

#[test]
fn clients_follow_the_server_bit_for_bit_and_refuse_bad_messages() {
    let floor = made(&mesh::subdivided_box(Vec3::new(4.0, 0.5, 4.0), [32, 4, 32]).unwrap());
    let ball = made(&mesh::icosphere(0.3, 2).unwrap());
    let settings = db_dent_settings_default(1.0, 0.02, 0.15);
    let damage = db_damage_new();
    let client = db_replica_new();
    // SAFETY: live handles, valid arrays and structs throughout.
    unsafe {
        assert_eq!(db_damage_add_body(damage, FLOOR, floor, IDENTITY.as_ptr(), &settings), DB_OK);
        assert_eq!(db_damage_add_projectile(damage, BALL), DB_OK);
        assert_eq!(db_damage_replicate(damage, FLOOR, WIRE_FLOOR), DB_OK, "{}", last_error());
        assert_eq!(db_damage_add_wire_projectile(damage, BALL_SHAPE, ball), DB_OK, "{}", last_error());
        assert_eq!(db_replica_add_body(client, WIRE_FLOOR, floor, &settings), DB_OK, "{}", last_error());
        assert_eq!(db_replica_add_projectile(client, BALL_SHAPE, ball), DB_OK);
        let mut length = 0;
        let start = bytes(db_damage_snapshot(damage, &mut length), length);
        assert_eq!(db_replica_join(client, start.as_ptr(), start.len()), DB_OK, "{}", last_error());
        let mut messages = Vec::new();
        for (k, (x, z)) in [(-1.0, -1.0), (1.0, 0.5), (0.0, 1.2)].into_iter().enumerate() {
            let hits = [falling_ball(FLOOR, BALL, ball, x, z, 6.0 + k as f32)];
            assert_eq!(db_damage_step(damage, hits.as_ptr(), 1), DB_OK, "{}", last_error());
            let message = bytes(db_damage_message(damage, &mut length), length);
            assert!(!message.is_empty() && message.len() < 200, "one dent's message: {} bytes", message.len());
            assert_eq!(db_replica_apply(client, message.as_ptr(), message.len()), DB_OK, "{}", last_error());
            assert_eq!(replica_positions(client), server_positions(damage), "after step {k}, bit for bit");
            messages.push(message);
        }
        // Repeated, truncated, out of order: refused, nothing changed.
        let now = replica_positions(client);
        let last = messages.last().unwrap();
        for (what, bad) in [("repeated", last.clone()), ("truncated", last[..last.len() / 2].to_vec())] {
            assert_eq!(db_replica_apply(client, bad.as_ptr(), bad.len()), DB_ERR_INVALID_ARGUMENT, "{what}");
            assert_eq!(replica_positions(client), now, "{what}: nothing changed");
        }
        assert_eq!(db_replica_apply(client, std::ptr::null(), 4), DB_ERR_NULL_POINTER);
        assert_eq!(db_replica_apply(client, last.as_ptr(), usize::MAX), DB_ERR_INVALID_ARGUMENT);
        // A late joiner starts from the snapshot, then follows the next message.
        let snapshot = bytes(db_damage_snapshot(damage, &mut length), length);
        let late = db_replica_new();
        assert_eq!(db_replica_add_body(late, WIRE_FLOOR, floor, &settings), DB_OK);
        assert_eq!(db_replica_add_projectile(late, BALL_SHAPE, ball), DB_OK);
        let early = messages[0].clone();
        assert_eq!(db_replica_join(late, snapshot.as_ptr(), snapshot.len()), DB_OK, "{}", last_error());
        assert_eq!(replica_positions(late), server_positions(damage), "the late joiner, bit for bit");
        assert_eq!(db_replica_apply(late, early.as_ptr(), early.len()), DB_ERR_INVALID_ARGUMENT, "an old message");
        let hits = [falling_ball(FLOOR, BALL, ball, 1.2, -1.2, 8.0)];
        assert_eq!(db_damage_step(damage, hits.as_ptr(), 1), DB_OK);
        let message = bytes(db_damage_message(damage, &mut length), length);
        for replica in [client, late] {
            assert_eq!(db_replica_apply(replica, message.as_ptr(), message.len()), DB_OK, "{}", last_error());
            assert_eq!(replica_positions(replica), server_positions(damage));
        }
        let mut moved = 0;
        assert!(!db_replica_moved(late, WIRE_FLOOR, &mut moved).is_null() && moved > 0);
        db_replica_free(late);
        db_replica_free(client);
        db_damage_free(damage);
        db_mesh_free(floor);
        db_mesh_free(ball);
    }
}
