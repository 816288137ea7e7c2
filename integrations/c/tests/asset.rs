//! Game assets in the damage context: a body made with UVs and authored normals (its vertices
//! split at its hard edges) keeps them through refining dents, fracture and save/restore, so a
//! render mesh read back never loses its texture or cracks.

mod common;

use std::collections::HashMap;

use common::{IDENTITY, falling_ball, last_error, made};
use dentbend::glam::{Vec2, Vec3};
use dentbend::mesh;
use dentbend_c::*;

const SLAB: u64 = 3;
const BALL: u64 = 4;

/// The side of a box a unit normal is on: its axis and sign.
fn side(n: Vec3) -> (usize, bool) {
    let axis = (0..3).max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs())).unwrap();
    (axis, n[axis] > 0.0)
}

/// A point's UV on a side of axis `axis`: its other two coordinates, 2 UV units a metre.
fn uv_on(axis: usize, p: Vec3) -> Vec2 {
    let (a, b) = [(1, 2), (0, 2), (0, 1)][axis];
    Vec2::new(2.0 * p[a], 2.0 * p[b])
}

/// A 4 × 0.5 × 4 m slab of 1 m cells, too coarse for a dent (top at y = 0.25), as a game asset: one vertex per side at its hard
/// edges, each side's normal authored, UVs projected per side at 2 UV units a metre.
fn slab() -> *mut DbMesh {
    let welded = mesh::subdivided_box(Vec3::new(4.0, 0.5, 4.0), [4, 1, 4]).unwrap();
    let (mut points, mut sides, mut faces, mut keys) = (Vec::new(), Vec::new(), Vec::new(), HashMap::new());
    for face in welded.faces() {
        let [a, b, c] = face.map(|v| welded.positions()[v as usize]);
        let s = side((b - a).cross(c - a).normalize());
        faces.push(face.map(|v| {
            *keys.entry((v, s)).or_insert_with(|| {
                points.push(welded.positions()[v as usize]);
                sides.push(s);
                points.len() as u32 - 1
            })
        }));
    }
    let normal = |(axis, positive): (usize, bool)| {
        let mut n = [0.0; 3];
        n[axis] = if positive { 1.0 } else { -1.0 };
        n
    };
    let positions: Vec<f32> = points.iter().flat_map(|p| p.to_array()).collect();
    let normals: Vec<f32> = sides.iter().flat_map(|&s| normal(s)).collect();
    let uvs: Vec<f32> = points.iter().zip(&sides).flat_map(|(&p, s)| uv_on(s.0, p).to_array()).collect();
    let indices: Vec<u32> = faces.iter().flatten().copied().collect();
    // SAFETY: every array as long as the counts say.
    let handle = unsafe {
        db_mesh_new_with_attributes(
            positions.as_ptr(),
            points.len(),
            indices.as_ptr(),
            faces.len(),
            normals.as_ptr(),
            uvs.as_ptr(),
        )
    };
    assert!(!handle.is_null(), "{}", last_error());
    handle
}

/// Body `id`'s array of `width` floats a vertex, copied out.
fn floats(pointer: *const f32, count: usize, width: usize) -> Vec<f32> {
    assert!(!pointer.is_null(), "{}", last_error());
    // SAFETY: the library's array of `count` items.
    unsafe { std::slice::from_raw_parts(pointer, width * count) }.to_vec()
}

fn body(damage: *const DbDamage, id: u64) -> (Vec<Vec3>, Vec<Vec3>, Vec<Vec2>) {
    let (mut n, mut m, mut k) = (0, 0, 0);
    // SAFETY: a live context.
    let (p, normals, uvs) = unsafe {
        (
            db_damage_positions(damage, id, &mut n),
            db_damage_normals(damage, id, &mut m),
            db_damage_uvs(damage, id, &mut k),
        )
    };
    assert_eq!((n, m), (k, k), "one normal and one UV a vertex");
    (
        floats(p, n, 3).chunks(3).map(Vec3::from_slice).collect(),
        floats(normals, m, 3).chunks(3).map(Vec3::from_slice).collect(),
        floats(uvs, k, 2).chunks(2).map(Vec2::from_slice).collect(),
    )
}

fn world(slab: *const DbMesh) -> *mut DbDamage {
    let damage = db_damage_new();
    let settings = db_dent_settings_default(1.0, 0.02, 0.15);
    // SAFETY: live handles and valid structs.
    unsafe {
        assert_eq!(db_damage_add_body(damage, SLAB, slab, IDENTITY.as_ptr(), &settings), DB_OK, "{}", last_error());
        assert_eq!(db_damage_add_projectile(damage, BALL), DB_OK);
    }
    damage
}

/// A head-on dent from above refines the top and moves its vertices straight down (x and z
/// kept): every top vertex, new ones included, keeps the UV of its x and z (within 1e-5, f32
/// interpolation); the other sides' vertices keep their side's normal within 0.02 rad (the hard
/// edges hold: smoothed, they would turn 45°; the bottom's bend under the dent is 3e-3 rad) and the top's stay unit.
#[test]
fn a_refining_dent_keeps_uvs_and_hard_edges() {
    let slab = slab();
    let damage = world(slab);
    let (before, before_normals, _) = body(damage, SLAB);
    let ball = made(&mesh::icosphere(0.3, 2).unwrap());
    let hits = [falling_ball(SLAB, BALL, ball, 0.3, -0.4, 8.0)];
    // SAFETY: live handles and a valid hit.
    unsafe { assert_eq!(db_damage_step(damage, hits.as_ptr(), 1), DB_OK, "{}", last_error()) };
    let (after, normals, uvs) = body(damage, SLAB);
    assert!(after.len() > before.len(), "the dent refined the top: {} -> {} vertices", before.len(), after.len());
    let mut top = 0;
    for v in 0..after.len() {
        let on_top = match before_normals.get(v) {
            Some(&n) => side(n) == (1, true),
            None => true,
        };
        if on_top {
            top += 1;
            let expected = uv_on(1, after[v]);
            assert!((uvs[v] - expected).abs().max_element() < 1e-5, "vertex {v}: UV {} not {expected}", uvs[v]);
            assert!((normals[v].length() - 1.0).abs() < 1e-5);
        } else {
            // A hard edge smoothed over would turn it 45°; the dent's reach through the slab
            // moves the bottom's middle by about 0.2 mm, turning it 3e-3 rad.
            let angle = normals[v].angle_between(before_normals[v]);
            assert!(angle < 0.02, "vertex {v} off the top turned {angle} rad from its side's normal");
        }
    }
    assert!(top > 25 + 20, "{top} top vertices checked, new ones among them");
    // SAFETY: live handles.
    unsafe {
        db_damage_free(damage);
        db_mesh_free(slab);
        db_mesh_free(ball);
    }
}

/// The slab breaks; the rest and every piece come with one normal and one UV a vertex, finite,
/// the normals unit; a piece copied as a mesh keeps them.
#[test]
fn pieces_and_the_rest_carry_uvs_and_normals() {
    let slab = slab();
    let damage = world(slab);
    let ball = made(&mesh::icosphere(0.3, 2).unwrap());
    let hits = [falling_ball(SLAB, BALL, ball, 0.3, -0.4, 8.0)];
    let breaks = db_fracture_settings_default(10, 2, 0.6, 50.0, f32::INFINITY);
    // SAFETY: live handles and valid structs throughout.
    unsafe {
        assert_eq!(db_damage_set_fracture(damage, SLAB, &breaks), DB_OK, "{}", last_error());
        assert_eq!(db_damage_step(damage, hits.as_ptr(), 1), DB_OK, "{}", last_error());
        let mut f = DbFracture::default();
        assert_eq!(db_damage_fracture(damage, 0, &mut f), DB_OK);
        let (rest, normals, uvs) = body(damage, SLAB);
        assert!(!rest.is_empty() && uvs.iter().all(|u| u.is_finite()));
        assert!(normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4));
        for k in 0..f.piece_count {
            let mut piece = std::mem::MaybeUninit::<DbPiece>::uninit();
            assert_eq!(db_damage_piece(damage, 0, k, piece.as_mut_ptr()), DB_OK);
            let piece = piece.assume_init();
            let normals = floats(piece.normals, piece.vertex_count, 3);
            let uvs = floats(piece.uvs, piece.vertex_count, 2);
            assert!(uvs.iter().all(|u| u.is_finite()), "piece {k}");
            assert!(normals.chunks(3).all(|n| (Vec3::from_slice(n).length() - 1.0).abs() < 1e-4), "piece {k}");
        }
        let copy = db_damage_piece_mesh(damage, 0, 0);
        assert!(!db_mesh_uvs(copy).is_null() && db_mesh_vertex_count(copy) > 0, "the copy keeps its UVs");
        db_mesh_free(copy);
        db_damage_free(damage);
        db_mesh_free(slab);
        db_mesh_free(ball);
    }
}

/// Damage saved from a game asset and restored on a fresh one gives the same mesh bit for bit
/// and the same UVs and normals (within 1e-6 and 1e-5: a replay interpolates each new vertex
/// from its edge's ends in the order the file tells them).
#[test]
fn a_restored_asset_has_the_saved_uvs_and_normals() {
    let slab = slab();
    let damage = world(slab);
    let ball = made(&mesh::icosphere(0.3, 2).unwrap());
    let breaks = db_fracture_settings_default(10, 2, 0.6, 50.0, f32::INFINITY);
    let mut length = 0;
    // SAFETY: live handles and valid structs throughout.
    unsafe {
        assert_eq!(db_damage_record(damage, SLAB, c"slab".as_ptr()), DB_OK);
        assert_eq!(db_damage_set_fracture(damage, SLAB, &breaks), DB_OK);
        // One dent, two in one step, then the break.
        for hits in [
            vec![falling_ball(SLAB, BALL, ball, -1.0, 1.0, 4.0)],
            vec![falling_ball(SLAB, BALL, ball, 1.2, 0.8, 5.0), falling_ball(SLAB, BALL, ball, -1.2, -1.0, 5.0)],
            vec![falling_ball(SLAB, BALL, ball, 0.3, -0.4, 8.0)],
        ] {
            assert_eq!(db_damage_step(damage, hits.as_ptr(), hits.len()), DB_OK, "{}", last_error());
        }
        assert_eq!(db_damage_fracture_count(damage), 1, "the last hit broke it");
        let saved = std::slice::from_raw_parts(db_damage_save(damage, &mut length), length).to_vec();
        let other = world(slab);
        assert_eq!(
            db_damage_restore(other, SLAB, saved.as_ptr(), saved.len(), c"slab".as_ptr()),
            DB_OK,
            "{}",
            last_error()
        );
        let (p, n, uv) = body(damage, SLAB);
        let (q, m, wv) = body(other, SLAB);
        assert_eq!(p, q, "the mesh, bit for bit");
        for v in 0..p.len() {
            assert!((uv[v] - wv[v]).abs().max_element() < 1e-6, "vertex {v}: UV {} vs {}", uv[v], wv[v]);
            assert!((n[v] - m[v]).abs().max_element() < 1e-5, "vertex {v}: normal {} vs {}", n[v], m[v]);
        }
        db_damage_free(other);
        db_damage_free(damage);
        db_mesh_free(slab);
        db_mesh_free(ball);
    }
}

/// The replica's body `wire_id`: positions, normals and UVs, copied out.
fn replica_body(replica: *const DbReplica, wire_id: u32) -> (Vec<f32>, Vec<f32>, Vec<f32>) {
    let (mut n, mut m, mut k) = (0, 0, 0);
    // SAFETY: a live replica.
    unsafe {
        let p = db_replica_positions(replica, wire_id, &mut n);
        let normals = db_replica_normals(replica, wire_id, &mut m);
        let uvs = db_replica_uvs(replica, wire_id, &mut k);
        assert_eq!((n, m), (k, k), "one normal and one UV a vertex");
        (floats(p, n, 3), floats(normals, m, 3), floats(uvs, k, 2))
    }
}

/// The server's body as the replica's arrays are laid out.
fn server_body(damage: *const DbDamage) -> (Vec<f32>, Vec<f32>, Vec<f32>) {
    let (p, n, uv) = body(damage, SLAB);
    (
        p.iter().flat_map(|v| v.to_array()).collect(),
        n.iter().flat_map(|v| v.to_array()).collect(),
        uv.iter().flat_map(|v| v.to_array()).collect(),
    )
}

/// Both sides' arrays agree: positions bit for bit, normals within 1e-5 and UVs within 1e-6
/// (the replica interpolates each new vertex from its edge's ends as the meshes tell them).
fn same(a: &(Vec<f32>, Vec<f32>, Vec<f32>), b: &(Vec<f32>, Vec<f32>, Vec<f32>), what: &str) {
    assert_eq!(a.0, b.0, "{what}: positions");
    assert!(a.1.iter().zip(&b.1).all(|(x, y)| (x - y).abs() < 1e-5), "{what}: normals");
    assert!(a.2.iter().zip(&b.2).all(|(x, y)| (x - y).abs() < 1e-6), "{what}: UVs");
}

/// A replica of a game asset follows the server's refining dents (one and two a step) and its
/// break with the same UVs and normals, message by message: it computes the dents itself, so
/// it knows each new vertex's edge. A late joiner given the asset's attributes after refining
/// dents is refused (a snapshot does not tell those edges), changing nothing; one without them
/// joins.
#[test]
fn a_replica_keeps_the_assets_uvs_through_messages() {
    let slab = slab();
    let damage = world(slab);
    let ball = made(&mesh::icosphere(0.3, 2).unwrap());
    let settings = db_dent_settings_default(1.0, 0.02, 0.15);
    let breaks = db_fracture_settings_default(10, 2, 0.6, 50.0, f32::INFINITY);
    let client = db_replica_new();
    let mut length = 0;
    let bytes = |p: *const u8, n: usize| {
        if p.is_null() { Vec::new() } else { unsafe { std::slice::from_raw_parts(p, n) }.to_vec() }
    };
    // SAFETY: live handles and valid structs throughout.
    unsafe {
        assert_eq!(db_damage_set_fracture(damage, SLAB, &breaks), DB_OK);
        assert_eq!(db_damage_replicate(damage, SLAB, 1), DB_OK);
        assert_eq!(db_damage_add_wire_projectile(damage, 2, ball), DB_OK);
        assert_eq!(db_replica_add_body(client, 1, slab, &settings), DB_OK);
        assert_eq!(db_replica_add_projectile(client, 2, ball), DB_OK);
        let start = bytes(db_damage_snapshot(damage, &mut length), length);
        assert_eq!(db_replica_join(client, start.as_ptr(), start.len()), DB_OK, "{}", last_error());
        // One dent a step, then two in one step (one message).
        for hits in [
            vec![falling_ball(SLAB, BALL, ball, -1.0, 1.0, 4.0)],
            vec![falling_ball(SLAB, BALL, ball, 1.2, 0.8, 5.0), falling_ball(SLAB, BALL, ball, -1.2, -1.0, 5.0)],
        ] {
            assert_eq!(db_damage_step(damage, hits.as_ptr(), hits.len()), DB_OK, "{}", last_error());
            let message = bytes(db_damage_message(damage, &mut length), length);
            assert_eq!(db_replica_apply(client, message.as_ptr(), message.len()), DB_OK, "{}", last_error());
            same(&replica_body(client, 1), &server_body(damage), "after a dent");
        }
        // A late joiner after refining dents: the snapshot's mesh does not say which edge each
        // new vertex split. Given the asset's attributes it is refused with the fix, nothing
        // changed; given the plain mesh it joins.
        let snapshot = bytes(db_damage_snapshot(damage, &mut length), length);
        let refused = db_replica_new();
        assert_eq!(db_replica_add_body(refused, 1, slab, &settings), DB_OK);
        assert_eq!(db_replica_join(refused, snapshot.as_ptr(), snapshot.len()), DB_ERR_INVALID_ARGUMENT);
        assert!(last_error().contains("join before the body is damaged"), "{}", last_error());
        assert_eq!(replica_body_positions(refused).len() / 3, db_mesh_vertex_count(slab), "nothing changed");
        db_replica_free(refused);
        let (vertices, triangles) = (db_mesh_vertex_count(slab), db_mesh_triangle_count(slab));
        let plain_mesh = db_mesh_new(db_mesh_positions(slab), vertices, db_mesh_indices(slab), triangles);
        let late = db_replica_new();
        assert_eq!(db_replica_add_body(late, 1, plain_mesh, &settings), DB_OK);
        assert_eq!(db_replica_add_projectile(late, 2, ball), DB_OK);
        assert_eq!(db_replica_join(late, snapshot.as_ptr(), snapshot.len()), DB_OK, "{}", last_error());
        assert_eq!(replica_body_positions(late), server_body(damage).0, "a plain late joiner");

        let hits = [falling_ball(SLAB, BALL, ball, 0.3, -0.4, 8.0)];
        assert_eq!(db_damage_step(damage, hits.as_ptr(), 1), DB_OK, "{}", last_error());
        assert_eq!(db_damage_fracture_count(damage), 1);
        let message = bytes(db_damage_message(damage, &mut length), length);
        for replica in [client, late] {
            assert_eq!(db_replica_apply(replica, message.as_ptr(), message.len()), DB_OK, "{}", last_error());
        }
        same(&replica_body(client, 1), &server_body(damage), "the rest");
        assert_eq!(replica_body_positions(late), server_body(damage).0, "the plain joiner's rest");
        let mut f = DbFracture::default();
        assert_eq!(db_damage_fracture(damage, 0, &mut f), DB_OK);
        for k in 0..f.piece_count {
            let (mut mine, mut theirs) = (std::mem::MaybeUninit::uninit(), std::mem::MaybeUninit::uninit());
            assert_eq!(db_replica_piece(client, 0, k, mine.as_mut_ptr()), DB_OK);
            assert_eq!(db_damage_piece(damage, 0, k, theirs.as_mut_ptr()), DB_OK);
            let (mine, theirs): (DbPiece, DbPiece) = (mine.assume_init(), theirs.assume_init());
            let uv = |p: &DbPiece| floats(p.uvs, p.vertex_count, 2);
            assert!(uv(&mine).iter().zip(uv(&theirs)).all(|(a, b)| (a - b).abs() < 1e-6), "piece {k}'s UVs");
        }
        for r in [late, client] {
            db_replica_free(r);
        }
        db_mesh_free(plain_mesh);
        db_damage_free(damage);
        db_mesh_free(slab);
        db_mesh_free(ball);
    }
}

fn replica_body_positions(replica: *const DbReplica) -> Vec<f32> {
    let mut n = 0;
    // SAFETY: a live replica.
    floats(unsafe { db_replica_positions(replica, 1, &mut n) }, n, 3)
}
