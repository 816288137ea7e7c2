//! Fractures over the replication stream: a server whose walls dent and then break (one keeps a
//! rest, one is taken whole, on plain and progressive settings) sends each break as data; a
//! client there from the start replays it and gets the server's rest and pieces bit for bit
//! (meshes, mass properties, ids), the whole-taken wall removed; a client that joins after the
//! breaks gets the rest and drops the removed wall. A break that does not replay to the
//! server's result is refused with a typed error and changes nothing.

mod common;

use common::hits;
use dentbend::damage::{BodyFracture, CpuBackend, Damage, DentTargets, TargetSet};
use dentbend::dent::{BodyState, DentSettings};
use dentbend::fracture::{FractureSettings, PatternParams};
use dentbend::glam::{Affine3A, Mat3, Vec3};
use dentbend::mesh::{self, TriMesh, content_hash};
use dentbend::record::replication::{ReplicaChange, ReplicationClient, ReplicationError, ReplicationServer};

/// A 3 × 2 × 0.2 m wall that keeps a rest when a 0.6 m pattern breaks it.
const WALL: u32 = 1;
/// A 0.5 × 0.5 × 0.2 m panel the same pattern takes whole.
const PANEL: u32 = 2;
const BALL: u32 = 10;
const BALL_SHAPE: u32 = 3;

/// Dents 0.02 m per m/s above 1 m/s (cap 0.05 m), breaks at 100 J.
fn dent_settings(progressive: bool) -> DentSettings {
    let mut s = DentSettings::new(1.0, 0.02, 0.05);
    s.progressive = progressive;
    s
}

/// A server world: the wall at the origin, the panel 4 m to its right, both fixed.
struct World {
    set: TargetSet<u32>,
    damage: Damage<u32>,
    server: ReplicationServer<u32>,
    ball: TriMesh,
    bases: Vec<(u32, TriMesh)>,
    progressive: bool,
    step: u64,
}

impl World {
    fn new(progressive: bool) -> Self {
        let bases = vec![
            (WALL, mesh::subdivided_box(Vec3::new(3.0, 2.0, 0.2), [30, 20, 2]).unwrap()),
            (PANEL, mesh::subdivided_box(Vec3::new(0.5, 0.5, 0.2), [5, 5, 2]).unwrap()),
        ];
        let mut set = TargetSet::new();
        let mut server = ReplicationServer::new();
        let fracture =
            FractureSettings::new(PatternParams { cells: 10, seed: 5, radius: 0.6 }, Some(100.0), None).unwrap();
        for (id, base) in &bases {
            let to_world = Affine3A::from_translation(Vec3::new(if *id == WALL { 0.0 } else { 4.0 }, 0.0, 0.0));
            set.insert(*id, base.clone(), to_world, dent_settings(progressive)).unwrap();
            set.set_fracture(*id, Some(fracture.clone())).unwrap();
            server.track(*id, *id, base, &dent_settings(progressive)).unwrap();
        }
        set.insert_rigid(BALL);
        let ball = mesh::icosphere(0.2, 3).unwrap();
        server.add_projectile(BALL_SHAPE, &ball).unwrap();
        Self { set, damage: Damage::new(), server, ball, bases, progressive, step: 0 }
    }

    /// A 5 kg ball at `speed` m/s head-on into the front face (z = 0.1) of body `id` at `x` m
    /// from its centre; returns the step's message and its fractures.
    fn throw(&mut self, id: u32, x: f32, speed: f32) -> (Vec<u8>, Vec<BodyFracture<u32>>) {
        self.step += 1;
        let point = self.set.target(id).unwrap().to_world.transform_point3(Vec3::new(x, 0.0, 0.1));
        let centre = point + Vec3::Z * 0.2;
        let state = BodyState::moving(centre, -Vec3::Z * speed, Vec3::ZERO, 5.0, Mat3::IDENTITY / 0.2);
        let hit = hits::on_fixed(id, BALL, &self.ball, point, -Vec3::Z, state);
        let plan = self.damage.plan(&self.set, &[hit], self.step, &mut CpuBackend).unwrap();
        assert!(!plan.dents.is_empty(), "every throw dents");
        self.set.apply(plan.targets);
        plan.fractures.iter().for_each(|f| self.set.apply_fracture(f));
        let (set, ball) = (&self.set, &self.ball);
        let message = self.server.message(&plan.dents, &plan.fractures, |k| set.mesh(k), |_| Some(ball));
        (message.unwrap().expect("a message"), plan.fractures)
    }

    fn client(&self) -> ReplicationClient {
        let mut c = ReplicationClient::new();
        for (id, base) in &self.bases {
            c.add_body(*id, base.clone(), &dent_settings(self.progressive)).unwrap();
        }
        c.add_projectile(BALL_SHAPE, self.ball.clone()).unwrap();
        c
    }

    fn snapshot(&self) -> Vec<u8> {
        self.server.snapshot(|k| self.set.mesh(k)).unwrap().bytes
    }
}

/// The server's fracture as the client should have replayed it: the same pieces (ids, meshes,
/// mass properties) bit for bit.
fn assert_same_pieces(change: &ReplicaChange, fracture: &BodyFracture<u32>) {
    let replayed = change.fracture.as_ref().expect("the change carries the fracture");
    assert_eq!(replayed.number, fracture.number);
    assert_eq!(replayed.pieces.len(), fracture.pieces.len());
    for ((id, piece), server) in replayed.pieces.iter().zip(&fracture.pieces) {
        assert_eq!(*id, server.id);
        assert_eq!(piece.mesh, server.mesh, "piece {id:?}'s mesh");
        assert_eq!(piece.mass, server.mass, "piece {id:?}'s mass properties");
    }
}

/// Dents, a break that leaves a rest, a dent on the rest, a break that takes the panel whole:
/// the early client follows every step bit for bit; a late joiner starts from the rest.
fn breaks_replicate(progressive: bool) {
    let mut world = World::new(progressive);
    let mut early = world.client();
    early.join(&world.snapshot()).unwrap();

    let (message, fractures) = world.throw(WALL, 0.5, 3.0);
    assert!(fractures.is_empty(), "22.5 J dents a 100 J wall without breaking it");
    early.apply(&message).unwrap();

    let (message, fractures) = world.throw(WALL, -0.2, 12.0);
    assert_eq!(fractures.len(), 1, "360 J breaks it");
    assert!(fractures[0].rest.is_some() && fractures[0].pieces.len() >= 4);
    if !progressive {
        // One dent (54 bytes) and one break (46 bytes) in one group, under 64 bytes each.
        assert!(message.len() <= 8 + 64 * 2, "{} bytes for a dent and a break", message.len());
    }
    let changes = early.apply(&message).unwrap();
    assert_eq!(changes.len(), 1);
    assert!(changes[0].topology_changed && !changes[0].removed);
    assert_same_pieces(&changes[0], &fractures[0]);
    assert_eq!(early.mesh(WALL), world.set.mesh(WALL), "the rest, bit for bit");

    let (message, _) = world.throw(WALL, 1.0, 3.0);
    early.apply(&message).unwrap();
    assert_eq!(early.mesh(WALL), world.set.mesh(WALL), "a dent on the rest");

    let (message, fractures) = world.throw(PANEL, 0.0, 12.0);
    assert!(fractures[0].rest.is_none(), "the pattern takes the panel whole");
    let changes = early.apply(&message).unwrap();
    assert!(changes[0].removed);
    assert_same_pieces(&changes[0], &fractures[0]);
    assert!(early.mesh(PANEL).is_none(), "the panel is gone");

    let mut late = world.client();
    let changes = late.join(&world.snapshot()).unwrap();
    assert!(changes.iter().any(|c| c.id == PANEL && c.removed), "{changes:?}");
    assert_eq!(late.mesh(WALL).map(content_hash), world.set.mesh(WALL).map(content_hash));
    assert!(late.mesh(PANEL).is_none(), "a late joiner drops the panel too");

    // Both clients go on together after the breaks.
    let (message, _) = world.throw(WALL, -1.0, 4.0);
    early.apply(&message).unwrap();
    late.apply(&message).unwrap();
    for client in [&early, &late] {
        assert_eq!(client.mesh(WALL), world.set.mesh(WALL));
    }
}

#[test]
fn breaks_replicate_bit_for_bit_and_a_late_joiner_starts_from_the_rest() {
    breaks_replicate(false);
}

#[test]
fn breaks_of_progressive_bodies_replicate_bit_for_bit() {
    breaks_replicate(true);
}

/// A message whose break is changed (its check, its seed) is refused with a typed error, and
/// the client keeps its mesh and its place in the stream.
#[test]
fn a_break_that_does_not_replay_to_the_servers_result_is_refused() {
    let mut world = World::new(false);
    let mut client = world.client();
    client.join(&world.snapshot()).unwrap();
    let (message, fractures) = world.throw(WALL, 0.0, 12.0);
    assert_eq!(fractures.len(), 1);
    let before = client.mesh(WALL).cloned();
    // The last four bytes are the break's check; the 8 bytes of the seed start 42 bytes
    // before the end (seed, radius, point, normal, density, check: 8 + 4 + 12 + 12 + 4 + 4).
    let n = message.len();
    for (at, what) in [(n - 1, "check"), (n - 42, "seed")] {
        let mut bad = message.clone();
        bad[at] ^= 0x5a;
        let error = client.apply(&bad).expect_err(what);
        assert!(matches!(error, ReplicationError::OtherMesh { id: WALL, .. }), "{what}: {error}");
        assert_eq!(client.mesh(WALL).cloned(), before, "{what}: the mesh is unchanged");
        assert_eq!(client.next_message(), Some(0), "{what}: the place in the stream is unchanged");
    }
    client.apply(&message).unwrap();
    assert_eq!(client.mesh(WALL), world.set.mesh(WALL));
}
