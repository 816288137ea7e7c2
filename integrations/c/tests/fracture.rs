//! `db_damage_set_fracture` and the fracture read-back: a hard hit breaks a breakable body
//! along its pattern, the pieces and the rest come back with their mass, a replica gets the
//! same pieces bit for bit, and bad settings or a step that cannot be carried change nothing.

mod common;

use common::{IDENTITY, falling_ball, last_error, made};
use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_c::*;

const FLOOR: u64 = 10;
const BALL: u64 = 1 << 40;
const WIRE_FLOOR: u32 = 3;
const BALL_SHAPE: u32 = 9;

/// A static 4 × 0.5 × 4 m floor (top at y = 0.25, 8 m³) that dents 2 cm per m/s above 1 m/s
/// and breaks, within 0.6 m of the hit, when an impact removes 50 J; and a ball of radius
/// 0.3 m.
fn world() -> (*mut DbDamage, *mut DbMesh, *mut DbMesh) {
    let floor = made(&mesh::subdivided_box(Vec3::new(4.0, 0.5, 4.0), [16, 2, 16]).unwrap());
    let ball = made(&mesh::icosphere(0.3, 2).unwrap());
    let damage = db_damage_new();
    let settings = db_dent_settings_default(1.0, 0.02, 0.15);
    let fracture = db_fracture_settings_default(12, 7, 0.6, 50.0, f32::INFINITY);
    // SAFETY: live handles and valid structs.
    unsafe {
        assert_eq!(db_damage_add_body(damage, FLOOR, floor, IDENTITY.as_ptr(), &settings), DB_OK, "{}", last_error());
        assert_eq!(db_damage_set_fracture(damage, FLOOR, &fracture), DB_OK, "{}", last_error());
        assert_eq!(db_damage_add_projectile(damage, BALL), DB_OK);
    }
    (damage, floor, ball)
}

/// Body `id`'s positions, copied out (empty for a body the context does not have).
fn positions(damage: *const DbDamage, id: u64) -> Vec<f32> {
    let mut count = 0;
    // SAFETY: live context; the pointer holds 3 floats a vertex.
    unsafe {
        let p = db_damage_positions(damage, id, &mut count);
        if p.is_null() { Vec::new() } else { std::slice::from_raw_parts(p, 3 * count).to_vec() }
    }
}

/// A piece's arrays, copied out: positions, hull points, indices.
fn piece_arrays(piece: &DbPiece) -> (Vec<f32>, Vec<f32>, Vec<u32>) {
    // SAFETY: the library's arrays of the counts it gives.
    unsafe {
        (
            std::slice::from_raw_parts(piece.positions, 3 * piece.vertex_count).to_vec(),
            std::slice::from_raw_parts(piece.hull_points, 3 * piece.vertex_count).to_vec(),
            std::slice::from_raw_parts(piece.indices, 3 * piece.triangle_count).to_vec(),
        )
    }
}

fn bytes(pointer: *const u8, length: usize) -> Vec<u8> {
    // SAFETY: the library's array of `length` bytes (or null with 0).
    if pointer.is_null() { Vec::new() } else { unsafe { std::slice::from_raw_parts(pointer, length) }.to_vec() }
}

#[test]
fn a_hard_hit_breaks_the_floor_into_pieces_with_their_mass() {
    let (damage, floor, ball) = world();
    // 2 kg at 8 m/s into a static body: 64 J removed along the normal, past the 50 J toughness.
    let hits = [falling_ball(FLOOR, BALL, ball, 0.5, -0.5, 8.0)];
    // SAFETY: live handles and valid structs throughout.
    unsafe {
        assert_eq!(db_damage_step(damage, hits.as_ptr(), 1), DB_OK, "{}", last_error());
        assert_eq!(db_damage_fracture_count(damage), 1);
        let mut f = DbFracture::default();
        assert_eq!(db_damage_fracture(damage, 0, &mut f), DB_OK, "{}", last_error());
        assert_eq!((f.body, f.projectile, f.number, f.cause, f.whole), (FLOOR, BALL, 0, DB_FRACTURE_ENERGY, 0));
        assert!((f.energy - 64.0).abs() < 0.5, "0.5 m v² = 64 J: {}", f.energy);
        assert_eq!(f.to_world, IDENTITY);
        assert!(f.piece_count >= 2, "{f:?}");
        assert_eq!(f.has_projectile_velocity, 1, "the ball goes on through the floor that gave way");
        let speed_after = Vec3::from_array(f.projectile_linear_velocity).length();
        assert!(speed_after > 0.0 && speed_after < 8.0, "slower than before: {speed_after}");

        // Mass: rest and pieces together are the dented floor's 8 m³ at 1000 kg/m³, less the
        // dent (under pi × 0.3² m² × 0.15 m = 0.043 m³); pieces and rest are closed solids.
        let mut total = f.rest_mass;
        for k in 0..f.piece_count {
            let mut piece = std::mem::MaybeUninit::<DbPiece>::uninit();
            assert_eq!(db_damage_piece(damage, 0, k, piece.as_mut_ptr()), DB_OK, "{}", last_error());
            let piece = piece.assume_init();
            assert_eq!((piece.fracture, piece.index), (0, k as u32));
            assert!(piece.mass > 0.0 && piece.triangle_count >= 4, "piece {k}: {piece:?}");
            total += piece.mass;
            // Its collider points: the vertices 3 % closer to its centre of mass.
            let (points, hull, _) = piece_arrays(&piece);
            let centre = Vec3::from_array(piece.center_of_mass);
            for (p, h) in points.chunks(3).zip(hull.chunks(3)) {
                let expected = centre + (Vec3::from_slice(p) - centre) * 0.97;
                assert!((Vec3::from_slice(h) - expected).length() < 1e-5, "piece {k}: {h:?} vs {expected}");
            }
            // Within the pattern's reach of the hit (0.6 m, and the floor's half-thickness).
            assert!((centre - Vec3::new(0.5, 0.0, -0.5)).length() < 0.6 + 0.25 + 1e-3, "piece {k} at {centre}");
        }
        assert!(total / 1000.0 > 8.0 - 0.043 && total / 1000.0 < 8.0 + 1e-3, "volume {} m³", total / 1000.0);

        // The floor is the rest now: every vertex listed as new.
        let rest = positions(damage, FLOOR);
        let mut n = 0;
        let moved = db_damage_moved(damage, FLOOR, &mut n);
        assert_eq!(n, rest.len() / 3, "every vertex of the rest is new");
        assert_eq!(std::slice::from_raw_parts(moved, n).last(), Some(&(n as u32 - 1)));

        // A piece, copied as a mesh, becomes a body that dents.
        let piece_mesh = db_damage_piece_mesh(damage, 0, 0);
        assert!(!piece_mesh.is_null(), "{}", last_error());
        let mut piece = std::mem::MaybeUninit::<DbPiece>::uninit();
        assert_eq!(db_damage_piece(damage, 0, 0, piece.as_mut_ptr()), DB_OK);
        assert_eq!(db_mesh_vertex_count(piece_mesh), piece.assume_init().vertex_count);
        let settings = db_dent_settings_default(1.0, 0.02, 0.15);
        assert_eq!(db_damage_add_body(damage, 77, piece_mesh, f.to_world.as_ptr(), &settings), DB_OK);

        // Read-back out of range or into nothing is refused.
        assert_eq!(db_damage_fracture(damage, 1, &mut f), DB_ERR_INVALID_ARGUMENT);
        assert!(last_error().contains("fracture 1 of 1"), "{}", last_error());
        assert_eq!(db_damage_piece(damage, 0, f.piece_count, piece.as_mut_ptr()), DB_ERR_INVALID_ARGUMENT);
        assert_eq!(db_damage_fracture(damage, 0, std::ptr::null_mut()), DB_ERR_NULL_POINTER);
        assert!(db_damage_piece_mesh(damage, 3, 0).is_null());

        // The next step breaks nothing: the read-back is of the last step.
        assert_eq!(db_damage_step(damage, std::ptr::null(), 0), DB_OK);
        assert_eq!(db_damage_fracture_count(damage), 0);
        db_mesh_free(piece_mesh);
        db_damage_free(damage);
        db_mesh_free(floor);
        db_mesh_free(ball);
    }
}

#[test]
fn a_body_inside_the_pattern_breaks_whole_and_is_removed() {
    let ball = made(&mesh::icosphere(0.3, 2).unwrap());
    let small = made(&mesh::subdivided_box(Vec3::new(0.4, 0.5, 0.4), [4, 4, 4]).unwrap());
    let damage = db_damage_new();
    let settings = db_dent_settings_default(1.0, 0.02, 0.15);
    // The pattern's 2 m reach takes the whole 0.4 m block.
    let fracture = db_fracture_settings_default(6, 1, 2.0, 10.0, f32::INFINITY);
    let hits = [falling_ball(FLOOR, BALL, ball, 0.0, 0.0, 8.0)];
    // SAFETY: live handles and valid structs.
    unsafe {
        assert_eq!(db_damage_add_body(damage, FLOOR, small, IDENTITY.as_ptr(), &settings), DB_OK);
        assert_eq!(db_damage_add_projectile(damage, BALL), DB_OK);
        assert_eq!(db_damage_set_fracture(damage, FLOOR, &fracture), DB_OK, "{}", last_error());
        assert_eq!(db_damage_record(damage, FLOOR, c"block".as_ptr()), DB_OK);
        assert_eq!(db_damage_step(damage, hits.as_ptr(), 1), DB_OK, "{}", last_error());
        let mut f = DbFracture::default();
        assert_eq!(db_damage_fracture(damage, 0, &mut f), DB_OK);
        assert_eq!((f.whole, f.rest_mass), (1, 0.0));
        assert!(f.piece_count >= 1);
        assert!(positions(damage, FLOOR).is_empty(), "the body is gone");
        assert_eq!(db_damage_set_pose(damage, FLOOR, IDENTITY.as_ptr()), DB_ERR_INVALID_ARGUMENT);
        // Nothing of it is left to record: its record ends, and the file saves without it.
        let mut length = 0;
        let saved = String::from_utf8(bytes(db_damage_save(damage, &mut length), length)).unwrap();
        assert!(saved.starts_with('{') && !saved.contains("\"block\""), "{saved}");
        // The id is free again.
        assert_eq!(db_damage_add_body(damage, FLOOR, small, IDENTITY.as_ptr(), &settings), DB_OK);
        db_damage_free(damage);
        db_mesh_free(small);
        db_mesh_free(ball);
    }
}

#[test]
fn bad_fracture_settings_are_refused_and_change_nothing() {
    let (damage, floor, ball) = world();
    let good = db_fracture_settings_default(12, 7, 0.6, 50.0, f32::INFINITY);
    let with = |change: fn(&mut DbFractureSettings)| {
        let mut s = good;
        change(&mut s);
        s
    };
    let cases = [
        ("NaN toughness", with(|s| s.toughness = f32::NAN), "toughness"),
        ("negative dent limit", with(|s| s.dent_limit = -1.0), "dent_limit"),
        ("neither limit", with(|s| s.toughness = f32::INFINITY), "toughness"),
        ("no cells", with(|s| s.cells = 0), "cells"),
        ("too many cells", with(|s| s.cells = 1000), "cells"),
        ("infinite radius", with(|s| s.radius = f32::INFINITY), "radius"),
        ("zero density", with(|s| s.density = 0.0), "density"),
        ("no pieces", with(|s| s.max_pieces = 0), "max_pieces"),
    ];
    // SAFETY: live handles and valid structs throughout.
    unsafe {
        // The floor breaks as `world` set it (50 J); each refused setting must leave that so.
        for (what, settings, says) in cases {
            assert_eq!(db_damage_set_fracture(damage, FLOOR, &settings), DB_ERR_INVALID_ARGUMENT, "{what}");
            assert!(last_error().contains(says), "{what}: {}", last_error());
        }
        assert_eq!(db_damage_set_fracture(damage, 99, &good), DB_ERR_INVALID_ARGUMENT, "an unknown body");
        assert!(last_error().contains("99"), "{}", last_error());
        assert_eq!(db_damage_set_fracture(std::ptr::null_mut(), FLOOR, &good), DB_ERR_NULL_POINTER);
        // An open mesh bounds no solid to break.
        let open = made(
            &mesh::TriMesh::new(
                vec![Vec3::ZERO, Vec3::X, Vec3::Z, Vec3::new(1.0, 0.0, 1.0)],
                vec![[0, 2, 1], [1, 2, 3]],
            )
            .unwrap(),
        );
        let settings = db_dent_settings_default(1.0, 0.02, 0.15);
        assert_eq!(db_damage_add_body(damage, 5, open, IDENTITY.as_ptr(), &settings), DB_OK);
        assert_eq!(db_damage_set_fracture(damage, 5, &good), DB_ERR_INVALID_ARGUMENT);
        assert!(last_error().contains("closed"), "{}", last_error());
        // The 50 J setting held: the 64 J hit breaks the floor.
        let hits = [falling_ball(FLOOR, BALL, ball, 0.5, -0.5, 8.0)];
        assert_eq!(db_damage_step(damage, hits.as_ptr(), 1), DB_OK, "{}", last_error());
        assert_eq!(db_damage_fracture_count(damage), 1, "the refused settings replaced nothing");
        // A null setting makes the rest unbreakable: the same hit again only dents it.
        assert_eq!(db_damage_set_fracture(damage, FLOOR, std::ptr::null()), DB_OK);
        assert_eq!(db_damage_step(damage, hits.as_ptr(), 1), DB_OK, "{}", last_error());
        assert_eq!((db_damage_dent_count(damage), db_damage_fracture_count(damage)), (1, 0));
        db_mesh_free(open);
        db_damage_free(damage);
        db_mesh_free(floor);
        db_mesh_free(ball);
    }
}

#[test]
fn a_break_too_many_pieces_for_the_limit_fails_the_step_and_changes_nothing() {
    let (damage, floor, ball) = world();
    let mut settings = db_fracture_settings_default(12, 7, 0.6, 50.0, f32::INFINITY);
    settings.max_pieces = 1;
    let hits = [falling_ball(FLOOR, BALL, ball, 0.5, -0.5, 8.0)];
    // SAFETY: live handles and valid structs.
    unsafe {
        assert_eq!(db_damage_set_fracture(damage, FLOOR, &settings), DB_OK);
        let before = positions(damage, FLOOR);
        assert_eq!(db_damage_step(damage, hits.as_ptr(), 1), DB_ERR_DENT);
        assert!(last_error().contains("pieces"), "{}", last_error());
        assert_eq!(positions(damage, FLOOR), before, "no dent, no break");
        assert_eq!(db_damage_fracture_count(damage), 0);
        db_damage_free(damage);
        db_mesh_free(floor);
        db_mesh_free(ball);
    }
}

#[test]
fn a_replica_gets_the_servers_pieces_bit_for_bit() {
    let (damage, floor, ball) = world();
    let client = db_replica_new();
    let settings = db_dent_settings_default(1.0, 0.02, 0.15);
    let hits = [falling_ball(FLOOR, BALL, ball, 0.5, -0.5, 8.0)];
    let mut length = 0;
    // SAFETY: live handles and valid structs throughout.
    unsafe {
        assert_eq!(db_damage_replicate(damage, FLOOR, WIRE_FLOOR), DB_OK, "{}", last_error());
        assert_eq!(db_replica_add_body(client, WIRE_FLOOR, floor, &settings), DB_OK);
        assert_eq!(db_replica_add_projectile(client, BALL_SHAPE, ball), DB_OK);
        let start = bytes(db_damage_snapshot(damage, &mut length), length);
        assert_eq!(db_replica_join(client, start.as_ptr(), start.len()), DB_OK, "{}", last_error());

        // The ball's shape is not on the stream yet: the step's message cannot name it, so the
        // step fails as a whole and the floor neither dents nor breaks.
        let before = positions(damage, FLOOR);
        assert_eq!(db_damage_step(damage, hits.as_ptr(), 1), DB_ERR_INVALID_ARGUMENT);
        assert!(last_error().contains("projectile"), "{}", last_error());
        assert_eq!(positions(damage, FLOOR), before, "nothing changed");
        assert_eq!(db_damage_fracture_count(damage), 0);

        assert_eq!(db_damage_add_wire_projectile(damage, BALL_SHAPE, ball), DB_OK);
        assert_eq!(db_damage_step(damage, hits.as_ptr(), 1), DB_OK, "{}", last_error());
        let message = bytes(db_damage_message(damage, &mut length), length);
        assert_eq!(db_replica_apply(client, message.as_ptr(), message.len()), DB_OK, "{}", last_error());
        assert_eq!(db_replica_fracture_count(client), 1);
        let mut f = DbReplicaFracture::default();
        assert_eq!(db_replica_fracture(client, 0, &mut f), DB_OK);
        let mut server = DbFracture::default();
        assert_eq!(db_damage_fracture(damage, 0, &mut server), DB_OK);
        assert_eq!((f.body, f.whole, f.number, f.piece_count), (WIRE_FLOOR, 0, server.number, server.piece_count));
        assert_eq!(server.number, 0, "the failed step made no fracture");
        let (mut a, mut b) = (0, 0);
        let (mine, theirs) = (db_replica_moved(client, WIRE_FLOOR, &mut a), db_damage_moved(damage, FLOOR, &mut b));
        assert_eq!(
            std::slice::from_raw_parts(mine, a),
            std::slice::from_raw_parts(theirs, b),
            "moved: every vertex of the rest on both sides"
        );
        for k in 0..f.piece_count {
            let (mut mine, mut theirs) = (std::mem::MaybeUninit::uninit(), std::mem::MaybeUninit::uninit());
            assert_eq!(db_replica_piece(client, 0, k, mine.as_mut_ptr()), DB_OK, "{}", last_error());
            assert_eq!(db_damage_piece(damage, 0, k, theirs.as_mut_ptr()), DB_OK);
            let (mine, theirs): (DbPiece, DbPiece) = (mine.assume_init(), theirs.assume_init());
            assert_eq!(piece_arrays(&mine), piece_arrays(&theirs), "piece {k}, bit for bit");
            assert_eq!((mine.mass, mine.center_of_mass), (theirs.mass, theirs.center_of_mass));
            assert_eq!(mine.linear_velocity, [0.0; 3], "velocities are the game's to replicate");
        }
        let mut n = 0;
        let rest = std::slice::from_raw_parts(db_replica_positions(client, WIRE_FLOOR, &mut n), 3 * n);
        assert_eq!(rest, positions(damage, FLOOR).as_slice(), "the rest, bit for bit");
        assert_eq!(db_replica_forget_piece(client, server.number, 0), DB_OK);
        assert_eq!(db_damage_forget_piece(damage, server.number, 0), DB_OK);
        assert_eq!(db_replica_fracture(client, 1, &mut f), DB_ERR_INVALID_ARGUMENT);
        // A step that changes no carried body has an empty message, which changes nothing.
        assert_eq!(db_damage_step(damage, std::ptr::null(), 0), DB_OK);
        assert!(db_damage_message(damage, &mut length).is_null() && length == 0);
        let now = positions(damage, FLOOR);
        assert_eq!(db_replica_apply(client, std::ptr::null(), 0), DB_OK, "{}", last_error());
        assert_eq!(std::slice::from_raw_parts(db_replica_positions(client, WIRE_FLOOR, &mut n), 3 * n), now.as_slice());
        assert_eq!(db_replica_fracture_count(client), 0);
        db_replica_free(client);
        db_damage_free(damage);
        db_mesh_free(floor);
        db_mesh_free(ball);
    }
}

#[test]
fn one_step_dents_one_carried_body_and_breaks_another_whole() {
    const BLOCK: u64 = 11;
    const WIRE_BLOCK: u32 = 4;
    let (damage, floor, ball) = world();
    let block = made(&mesh::subdivided_box(Vec3::new(0.4, 0.5, 0.4), [4, 4, 4]).unwrap());
    let settings = db_dent_settings_default(1.0, 0.02, 0.15);
    // The floor only dents; the block, 3 m along x, breaks whole under a 2 m pattern.
    let mut beside = IDENTITY;
    beside[9] = 3.0;
    let whole = db_fracture_settings_default(6, 1, 2.0, 10.0, f32::INFINITY);
    let client = db_replica_new();
    let mut length = 0;
    // SAFETY: live handles and valid structs throughout.
    unsafe {
        assert_eq!(db_damage_set_fracture(damage, FLOOR, std::ptr::null()), DB_OK);
        assert_eq!(db_damage_add_body(damage, BLOCK, block, beside.as_ptr(), &settings), DB_OK);
        assert_eq!(db_damage_set_fracture(damage, BLOCK, &whole), DB_OK, "{}", last_error());
        assert_eq!(db_damage_replicate(damage, FLOOR, WIRE_FLOOR), DB_OK);
        assert_eq!(db_damage_replicate(damage, BLOCK, WIRE_BLOCK), DB_OK);
        assert_eq!(db_damage_add_wire_projectile(damage, BALL_SHAPE, ball), DB_OK);
        assert_eq!(db_replica_add_body(client, WIRE_FLOOR, floor, &settings), DB_OK);
        assert_eq!(db_replica_add_body(client, WIRE_BLOCK, block, &settings), DB_OK);
        assert_eq!(db_replica_add_projectile(client, BALL_SHAPE, ball), DB_OK);
        let start = bytes(db_damage_snapshot(damage, &mut length), length);
        assert_eq!(db_replica_join(client, start.as_ptr(), start.len()), DB_OK, "{}", last_error());

        let hits = [falling_ball(FLOOR, BALL, ball, -0.5, 0.5, 8.0), falling_ball(BLOCK, BALL, ball, 3.0, 0.0, 8.0)];
        assert_eq!(db_damage_step(damage, hits.as_ptr(), 2), DB_OK, "{}", last_error());
        assert_eq!((db_damage_dent_count(damage), db_damage_fracture_count(damage)), (2, 1));
        let mut f = DbFracture::default();
        assert_eq!(db_damage_fracture(damage, 0, &mut f), DB_OK);
        assert_eq!((f.body, f.whole), (BLOCK, 1));
        assert_eq!(f.to_world, beside, "the pose the pieces are placed by");
        let message = bytes(db_damage_message(damage, &mut length), length);
        assert_eq!(db_replica_apply(client, message.as_ptr(), message.len()), DB_OK, "{}", last_error());
        let mut n = 0;
        let dented = std::slice::from_raw_parts(db_replica_positions(client, WIRE_FLOOR, &mut n), 3 * n);
        assert_eq!(dented, positions(damage, FLOOR).as_slice(), "the dented floor, bit for bit");
        assert!(db_replica_positions(client, WIRE_BLOCK, &mut n).is_null() && n == 0, "the block is gone");
        let mut r = DbReplicaFracture::default();
        assert_eq!(db_replica_fracture(client, 0, &mut r), DB_OK);
        assert_eq!((r.body, r.whole, r.piece_count), (WIRE_BLOCK, 1, f.piece_count));

        // A late joiner, from a snapshot after the break: the floor as it is, no block.
        let snapshot = bytes(db_damage_snapshot(damage, &mut length), length);
        let late = db_replica_new();
        assert_eq!(db_replica_add_body(late, WIRE_FLOOR, floor, &settings), DB_OK);
        assert_eq!(db_replica_add_projectile(late, BALL_SHAPE, ball), DB_OK);
        assert_eq!(db_replica_join(late, snapshot.as_ptr(), snapshot.len()), DB_OK, "{}", last_error());
        let joined = std::slice::from_raw_parts(db_replica_positions(late, WIRE_FLOOR, &mut n), 3 * n);
        assert_eq!(joined, positions(damage, FLOOR).as_slice());
        // Both follow the next dent.
        let hits = [falling_ball(FLOOR, BALL, ball, 1.0, 1.0, 6.0)];
        assert_eq!(db_damage_step(damage, hits.as_ptr(), 1), DB_OK, "{}", last_error());
        let message = bytes(db_damage_message(damage, &mut length), length);
        for replica in [client, late] {
            assert_eq!(db_replica_apply(replica, message.as_ptr(), message.len()), DB_OK, "{}", last_error());
            let now = std::slice::from_raw_parts(db_replica_positions(replica, WIRE_FLOOR, &mut n), 3 * n);
            assert_eq!(now, positions(damage, FLOOR).as_slice());
        }
        db_replica_free(late);
        db_replica_free(client);
        db_damage_free(damage);
        db_mesh_free(block);
        db_mesh_free(floor);
        db_mesh_free(ball);
    }
}
