//! A Rapier server's fracture over the replication stream: the wall of `rapier_wall`, tracked by
//! a `ReplicationServer` fed each step's dents and `BrokenCollider::fracture`s, breaks; a client
//! that applies the messages ends with the server's rest bit for bit, and the pieces it replays
//! are the meshes of the server's piece bodies, with the same ids. Pieces falling on the rest
//! dent it; the stream names them by piece id, and a client that joined after the break (its
//! snapshot carries the pieces) follows those dents bit for bit too. So that one surely does,
//! a piece is dropped on the rest's top as the late client joins.

use dentbend::dent::DentSettings;
use dentbend::mesh::content_hash;
use dentbend::record::replication::{ReplicationClient, ReplicationServer};
use dentbend_rapier::demo::wall::{WALL_DENT, WALL_SIZE, Wall};
use glam::Vec3;

const WALL_ID: u32 = 1;
const BALL_SHAPE: u32 = 1;

#[test]
fn a_broken_wall_replicates_its_rest_and_pieces_bit_for_bit() {
    let mut wall = Wall::new().unwrap();
    let (threshold, gain, cap) = WALL_DENT;
    let settings = DentSettings::new(threshold, gain, cap);
    let base = wall.wall_mesh().unwrap().clone();
    let ball = wall.adapter.dentables.surface(wall.world.bodies[wall.ball].colliders()[0]).unwrap().clone();
    let mut server = ReplicationServer::new();
    server.track(wall.wall, WALL_ID, &base, &settings).unwrap();
    server.add_projectile(BALL_SHAPE, &ball).unwrap();
    let (server_base, server_ball) = (base.clone(), ball.clone());
    let mut client = ReplicationClient::new();
    client.add_body(WALL_ID, base, &settings).unwrap();
    client.add_projectile(BALL_SHAPE, ball).unwrap();
    client.join(&server.snapshot(|h| wall.adapter.dentables.mesh(h)).unwrap().bytes).unwrap();

    let mut server_pieces = Vec::new();
    let mut piece_colliders = Vec::new();
    let mut piece_bodies = Vec::new();
    let mut client_pieces = Vec::new();
    let mut late: Option<ReplicationClient> = None;
    let mut piece_dents_after_join = 0;
    for _ in 0..90 {
        let report = wall.step().unwrap();
        for broken in &report.fractures {
            for p in &broken.pieces {
                let mesh = wall.adapter.dentables.surface(p.collider).expect("a piece's surface");
                server_pieces.push((p.id, content_hash(mesh)));
                piece_colliders.push(p.collider);
                piece_bodies.push(p.body);
            }
        }
        if late.is_some() {
            piece_dents_after_join += report.dents.iter().filter(|d| piece_colliders.contains(&d.projectile)).count();
        }
        let dentables = &wall.adapter.dentables;
        let fractures = report.fractures.iter().map(|b| &b.fracture);
        let Some(message) =
            server.message(&report.dents, fractures, |h| dentables.mesh(h), |h| dentables.surface(h)).unwrap()
        else {
            continue;
        };
        for change in client.apply(&message).unwrap() {
            let replayed = change.fracture.iter().flat_map(|f| &f.pieces);
            client_pieces.extend(replayed.map(|(id, piece)| (*id, content_hash(&piece.mesh))));
        }
        match late.as_mut() {
            Some(late) => {
                late.apply(&message).unwrap();
            }
            None if !server_pieces.is_empty() => {
                let mut joiner = ReplicationClient::new();
                joiner.add_body(WALL_ID, server_base.clone(), &settings).unwrap();
                joiner.add_projectile(BALL_SHAPE, server_ball.clone()).unwrap();
                joiner.join(&server.snapshot(|h| dentables.mesh(h)).unwrap().bytes).unwrap();
                for (id, hash) in &server_pieces {
                    assert_eq!(joiner.piece(*id).map(content_hash), Some(*hash), "the snapshot carries piece {id:?}");
                }
                late = Some(joiner);
                // The last piece, 0.6 m over the rest's top far from the hit, falling at 3 m/s:
                // it lands at about 4.5 m/s, past the rest's 2 m/s dent threshold.
                let piece = &mut wall.world.bodies[*piece_bodies.last().expect("a piece body")];
                piece.set_translation(Vec3::new(-1.2, WALL_SIZE.y + 0.6, 0.0), true);
                piece.set_linvel(Vec3::new(0.0, -3.0, 0.0), true);
                piece.set_angvel(Vec3::ZERO, true);
            }
            None => {}
        }
    }
    assert!(piece_dents_after_join > 0, "pieces dent the rest after the late join");
    assert_eq!(late.expect("a late joiner").mesh(WALL_ID), wall.wall_mesh(), "the late joiner, bit for bit");
    assert!(server_pieces.len() >= 20, "{} piece bodies", server_pieces.len());
    // Every piece body's mesh is among the client's replayed pieces under the same id (slivers
    // with no hull are left out of the bodies, not of the replay).
    for piece in &server_pieces {
        assert!(client_pieces.contains(piece), "piece {:?} differs on the client", piece.0);
    }
    assert_eq!(client.mesh(WALL_ID), wall.wall_mesh(), "the rest, bit for bit");
}
