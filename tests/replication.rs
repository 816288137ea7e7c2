//! Network replication through the engine-neutral API: a server denting with `damage::Damage`
//! sends each step's dents as messages; a client that joined at the start and one that joined
//! late (from a snapshot) end with meshes bit-identical to the server's, at most 64 bytes a
//! dent on the wire, and a late join no bigger than the meshes sent whole. Out-of-order,
//! repeated, truncated and foreign messages, a missing base mesh and other settings are each
//! refused with a typed error and change nothing.

mod common;

use common::SplitMix64;
use dentbend::damage::{CpuBackend, Damage, DentTargets, Hit, TargetSet};
use dentbend::dent::{BodyState, DentSettings, Impact, Surface};
use dentbend::glam::{Affine3A, Mat3, Quat, Vec3};
use dentbend::mesh::{self, TriMesh, content_hash};
use dentbend::record::replication::{ReplicationClient, ReplicationError, ReplicationServer};

/// Wire ids (the caller's keys are the same numbers here).
const PLATE: u32 = 1;
const BLOCK: u32 = 2;
const SOFT: u32 = 3;
const BALL: u32 = 10;
const BALL_SHAPE: u32 = 7;

struct Game {
    set: TargetSet<u32>,
    damage: Damage<u32>,
    ball: TriMesh,
    server: ReplicationServer<u32>,
    bases: Vec<(u32, TriMesh, DentSettings)>,
    messages: Vec<Vec<u8>>,
    dents: usize,
    /// Dents made on each body: plate, block, soft.
    dents_on: [usize; 3],
    step: u64,
    rng: SplitMix64,
}

fn settings(progressive: bool) -> DentSettings {
    let mut s = DentSettings::new(1.0, 0.02, 0.08);
    s.params.resolution = dentbend::Resolution::Auto { min: 25, max: 90 };
    s.progressive = progressive;
    s
}

impl Game {
    fn new() -> Self {
        Self::with(|_| {}, |m| m)
    }

    /// The game with every body's settings changed by `change` and its mesh by `author`.
    fn with(change: impl Fn(&mut DentSettings), author: impl Fn(TriMesh) -> TriMesh) -> Self {
        let plate = mesh::subdivided_box(Vec3::new(2.0, 0.2, 2.0), [16, 2, 16]).unwrap();
        let block = mesh::subdivided_box(Vec3::new(1.0, 0.6, 1.0), [8, 5, 8]).unwrap();
        let soft = mesh::subdivided_box(Vec3::new(1.0, 0.4, 1.0), [8, 3, 8]).unwrap();
        let poses = [
            Affine3A::from_translation(Vec3::new(0.0, 0.0, 0.0)),
            Affine3A::from_rotation_translation(Quat::from_rotation_y(0.7), Vec3::new(3.0, 0.2, 0.0)),
            Affine3A::from_translation(Vec3::new(-3.0, 0.1, 0.0)),
        ];
        let mut bases =
            vec![(PLATE, plate, settings(false)), (BLOCK, block, settings(false)), (SOFT, soft, settings(true))];
        for b in &mut bases {
            change(&mut b.2);
            b.1 = author(b.1.clone());
        }
        let mut set = TargetSet::new();
        let mut server = ReplicationServer::new();
        for ((id, mesh, s), pose) in bases.iter().zip(poses) {
            set.insert(*id, mesh.clone(), pose, s.clone()).unwrap();
            server.track(*id, *id, mesh, s).unwrap();
        }
        set.insert_rigid(BALL);
        let ball = mesh::icosphere(0.25, 2).unwrap();
        server.add_projectile(BALL_SHAPE, &ball).unwrap();
        let rng = SplitMix64::new(29);
        Self {
            set,
            damage: Damage::new(),
            ball,
            server,
            bases,
            messages: Vec::new(),
            dents: 0,
            dents_on: [0; 3],
            step: 0,
            rng,
        }
    }

    /// One step: up to three balls on random up-facing points of random bodies (one of them
    /// on the block by the plate itself, when `plate_hits_block`), then the message.
    fn step(&mut self) -> Result<(), ReplicationError> {
        self.step += 1;
        let mut hits = Vec::new();
        let ids = [PLATE, BLOCK, SOFT];
        let mut states = Vec::new();
        for _ in 0..3 {
            let id = ids[self.rng.below(3) as usize];
            let mesh = self.set.mesh(id).unwrap().clone();
            let pose = self.set.target(id).unwrap().to_world;
            let v = loop {
                let v = self.rng.below(mesh.vertex_count() as u64) as usize;
                if pose.transform_vector3(mesh.normals()[v]).y > 0.7 {
                    break v;
                }
            };
            let outward = pose.transform_vector3(mesh.normals()[v]).normalize();
            let point = pose.transform_point3(mesh.positions()[v]);
            let tangent = outward.any_orthonormal_vector() * self.rng.range_f32(-0.6, 0.6);
            let speed = self.rng.range_f32(2.0, 5.0);
            let spin = Quat::from_rotation_x(self.rng.range_f32(-3.0, 3.0));
            let centre = point + 0.25 * outward;
            let state = BodyState::moving(centre, (tangent - outward) * speed, Vec3::ZERO, 1.0, Mat3::IDENTITY * 40.0);
            states.push((id, point, outward, state, spin));
        }
        for &(id, point, outward, state, spin) in &states {
            hits.push(Hit {
                target: id,
                projectile: BALL,
                impact: Impact::from_contact(point, -outward, &BodyState::FIXED, &state).unwrap(),
                target_state: BodyState::FIXED,
                projectile_state: state,
                projectile_surface: Surface {
                    mesh: &self.ball,
                    to_world: Affine3A::from_rotation_translation(spin, state.center_of_mass),
                },
            });
        }
        let plan = self.damage.plan(&self.set, &hits, self.step, &mut CpuBackend).unwrap();
        self.dents += plan.dents.len();
        for d in &plan.dents {
            self.dents_on[(d.target - 1) as usize] += 1;
        }
        let dents = plan.dents.clone();
        self.set.apply(plan.targets);
        let (set, ball) = (&self.set, &self.ball);
        let message = self.server.message(
            &dents,
            &plan.fractures,
            |k| set.mesh(k),
            |k| if k == BALL { Some(ball) } else { set.mesh(k) },
        )?;
        if let Some(m) = message {
            self.messages.push(m);
        }
        Ok(())
    }

    fn client(&self) -> ReplicationClient {
        let mut c = ReplicationClient::new();
        for (id, mesh, s) in &self.bases {
            c.add_body(*id, mesh.clone(), s).unwrap();
        }
        c.add_projectile(BALL_SHAPE, self.ball.clone()).unwrap();
        c
    }

    fn snapshot(&self) -> Vec<u8> {
        self.server.snapshot(|k| self.set.mesh(k)).unwrap().bytes
    }

    /// Every body's content hash on the server.
    fn hashes(&self) -> Vec<u64> {
        [PLATE, BLOCK, SOFT].map(|id| content_hash(self.set.mesh(id).unwrap())).to_vec()
    }
}

fn hashes(c: &ReplicationClient) -> Vec<u64> {
    [PLATE, BLOCK, SOFT].map(|id| content_hash(c.mesh(id).unwrap())).to_vec()
}

#[test]
fn clients_from_the_start_and_late_joiners_end_bit_identical_to_the_server() {
    let mut game = Game::new();
    let mut early = game.client();
    early.join(&game.snapshot()).unwrap();
    while game.dents < 60 {
        game.step().unwrap();
    }
    let before_join = game.messages.len();
    let snapshot = game.server.snapshot(|k| game.set.mesh(k)).unwrap();
    let mut late = game.client();
    late.join(&snapshot.bytes).unwrap();
    assert_eq!(late.next_message(), Some(before_join as u64));
    // The late joiner's snapshot is bounded by the meshes, whatever the hits before it.
    assert!(
        snapshot.bytes.len() <= snapshot.full_mesh_bytes,
        "late join {} bytes, meshes whole {}",
        snapshot.bytes.len(),
        snapshot.full_mesh_bytes
    );
    while game.dents < 100 {
        game.step().unwrap();
    }
    for m in &game.messages {
        early.apply(m).unwrap();
    }
    for m in &game.messages[before_join..] {
        late.apply(m).unwrap();
    }
    assert_eq!(hashes(&early), game.hashes(), "the client that joined at the start");
    assert_eq!(hashes(&late), game.hashes(), "the late joiner");
    for id in [PLATE, BLOCK, SOFT] {
        let (c, s) = (early.mesh(id).unwrap(), game.set.mesh(id).unwrap());
        assert_eq!(c.faces(), s.faces());
        let bits = |m: &TriMesh| m.positions().iter().map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(c), bits(s), "body {id}: positions bit for bit");
    }
    assert!(game.dents_on.iter().all(|&n| n > 0), "every body dented: {:?}", game.dents_on);
}

#[test]
fn plain_dents_cost_at_most_64_bytes_each_on_the_wire() {
    // The stream carries the plate and the block: every group is dents.
    let mut game = Game::new();
    game.server.forget(SOFT);
    let mut client = game.client();
    client.join(&game.snapshot()).unwrap();
    while game.dents_on[0] + game.dents_on[1] < 60 {
        game.step().unwrap();
    }
    for m in &game.messages {
        client.apply(m).unwrap();
    }
    for id in [PLATE, BLOCK] {
        assert_eq!(content_hash(client.mesh(id).unwrap()), content_hash(game.set.mesh(id).unwrap()), "body {id}");
    }
    let sent: usize = game.messages.iter().map(Vec::len).sum();
    let dents = game.dents_on[0] + game.dents_on[1];
    let per_dent = sent as f64 / dents as f64;
    println!("{sent} bytes in {} messages for {dents} dents: {per_dent:.1} bytes a dent", game.messages.len());
    assert!(per_dent <= 64.0, "{per_dent:.1} bytes a dent");
}

/// A client that has applied `k` of the game's messages, and the game.
fn game_with_client(steps_until_dents: usize) -> (Game, ReplicationClient) {
    let mut game = Game::new();
    let mut client = game.client();
    client.join(&game.snapshot()).unwrap();
    while game.dents < steps_until_dents {
        game.step().unwrap();
    }
    (game, client)
}

/// Applies `bytes`, expecting a refusal that `check` accepts, and that the client is unchanged.
fn refused(client: &mut ReplicationClient, bytes: &[u8], check: impl Fn(&ReplicationError) -> bool) {
    let (hashes_before, next_before) = (hashes(client), client.next_message());
    match client.apply(bytes) {
        Ok(_) => panic!("accepted"),
        Err(e) => assert!(check(&e), "unexpected error: {e}"),
    }
    assert_eq!(hashes(client), hashes_before, "the meshes changed");
    assert_eq!(client.next_message(), next_before, "the position in the stream changed");
}

#[test]
fn out_of_order_repeated_and_truncated_messages_are_refused_and_change_nothing() {
    let (game, mut client) = game_with_client(12);
    assert!(game.messages.len() >= 3);
    refused(&mut client, &game.messages[1], |e| matches!(e, ReplicationError::OutOfOrder { expected: 0, found: 1 }));
    client.apply(&game.messages[0]).unwrap();
    refused(&mut client, &game.messages[0], |e| matches!(e, ReplicationError::Repeated { expected: 1, found: 0 }));
    let m = &game.messages[1];
    for cut in 0..m.len() {
        refused(&mut client, &m[..cut], |e| {
            matches!(e, ReplicationError::Truncated { .. } | ReplicationError::Malformed(_))
        });
    }
    let mut longer = m.clone();
    longer.push(0);
    refused(&mut client, &longer, |e| matches!(e, ReplicationError::Malformed(_)));
    client.apply(m).unwrap();
    assert_eq!(client.next_message(), Some(2));
}

#[test]
fn a_message_for_another_mesh_is_refused() {
    let (game, _) = game_with_client(6);
    // A client whose plate is another mesh (moved by a millimetre) joins a server that
    // tracks it as such, then gets this game's messages.
    let mut other = ReplicationClient::new();
    let mut server = ReplicationServer::<u32>::new();
    let mut set = TargetSet::new();
    for (id, mesh, s) in &game.bases {
        let mut mesh = mesh.clone();
        mesh.transform(Affine3A::from_translation(Vec3::new(0.001, 0.0, 0.0))).unwrap();
        other.add_body(*id, mesh.clone(), s).unwrap();
        server.track(*id, *id, &mesh, s).unwrap();
        set.insert(*id, mesh, Affine3A::IDENTITY, s.clone()).unwrap();
    }
    other.add_projectile(BALL_SHAPE, game.ball.clone()).unwrap();
    other.join(&server.snapshot(|k| set.mesh(k)).unwrap().bytes).unwrap();
    refused(&mut other, &game.messages[0], |e| matches!(e, ReplicationError::OtherMesh { .. }));
    // Joining this game's stream with the moved meshes is refused too.
    let (hashes_before, next_before) = (hashes(&other), other.next_message());
    let error = other.join(&game.snapshot()).unwrap_err();
    assert!(matches!(error, ReplicationError::OtherMesh { what: "the base mesh", .. }), "{error}");
    assert_eq!((hashes(&other), other.next_message()), (hashes_before, next_before));
}

#[test]
fn a_client_without_a_base_mesh_or_with_other_settings_is_refused() {
    let game = Game::new();
    let mut client = ReplicationClient::new();
    client.add_body(PLATE, game.bases[0].1.clone(), &game.bases[0].2).unwrap();
    let error = client.join(&game.snapshot()).unwrap_err();
    assert!(matches!(error, ReplicationError::MissingBase { id: BLOCK }), "{error}");
    assert_eq!(client.next_message(), None);
    let error = client.apply(&[0xD1, 0, 0]).unwrap_err();
    assert!(matches!(error, ReplicationError::NotJoined), "{error}");

    let mut client = ReplicationClient::new();
    for (id, mesh, s) in &game.bases {
        let mut s = s.clone();
        s.params.heat_iters += 1;
        client.add_body(*id, mesh.clone(), &s).unwrap();
    }
    let error = client.join(&game.snapshot()).unwrap_err();
    assert!(matches!(error, ReplicationError::OtherMesh { what: "the dent settings' digest", .. }), "{error}");

    // A projectile the client was not given.
    let (game, _) = game_with_client(3);
    let mut client = ReplicationClient::new();
    for (id, mesh, s) in &game.bases {
        client.add_body(*id, mesh.clone(), s).unwrap();
    }
    client.join(&Game::new().snapshot()).unwrap();
    let first_dents = game.messages.iter().position(|m| m.len() > 40).unwrap();
    let mut at = client.clone();
    for m in &game.messages[..first_dents] {
        at.apply(m).unwrap();
    }
    refused(&mut at, &game.messages[first_dents], |e| matches!(e, ReplicationError::UnknownProjectile(_)));
}

#[test]
fn hostile_bytes_never_panic() {
    let (game, client) = game_with_client(6);
    let mut rng = SplitMix64::new(5);
    for m in game.messages.iter().take(4).chain(std::iter::once(&game.snapshot())) {
        for _ in 0..300 {
            let mut bytes = m.clone();
            for _ in 0..1 + rng.below(4) {
                let k = rng.below(bytes.len() as u64) as usize;
                bytes[k] ^= 1 << rng.below(8);
            }
            let mut c = client.clone();
            let _ = c.apply(&bytes);
            let mut c = client.clone();
            let _ = c.join(&bytes);
        }
    }
}

#[test]
fn a_server_refuses_an_unregistered_projectile_and_duplicate_ids() {
    let mut game = Game::new();
    let other_ball = mesh::icosphere(0.25, 1).unwrap();
    game.ball = other_ball;
    let next = game.server.next_message();
    let error = loop {
        let before = game.dents;
        let result = game.step();
        if game.dents > before {
            break result.unwrap_err();
        }
    };
    assert!(matches!(error, ReplicationError::UnknownProjectile(_)), "{error}");
    assert_eq!(game.server.next_message(), next, "no message numbered");
    let plate = game.bases[0].1.clone();
    let error = game.server.track(99, PLATE, &plate, &settings(false)).unwrap_err();
    assert!(matches!(error, ReplicationError::DuplicateId { what: "body", id: PLATE }), "{error}");
    let error = game.server.add_projectile(BALL_SHAPE, &plate).unwrap_err();
    assert!(matches!(error, ReplicationError::DuplicateId { what: "projectile", .. }), "{error}");
}

#[test]
fn a_dent_deeper_than_the_bodys_cap_is_refused_before_it_is_computed() {
    // A hostile message asking for a 1 km dent would take the client minutes; the server never
    // sends one deeper than the body's cap (8 cm here).
    let mut game = Game::new();
    game.server.forget(SOFT);
    let mut client = game.client();
    client.join(&game.snapshot()).unwrap();
    while game.messages.is_empty() {
        game.step().unwrap();
    }
    let mut bytes = game.messages[0].clone();
    // Tag, number 0, one group, body id, group header, check (4), flags, projectile id: the
    // first dent's distance starts at byte 11.
    assert_eq!(f32::from_le_bytes(bytes[11..15].try_into().unwrap()).to_bits() >> 31, 0);
    assert!(f32::from_le_bytes(bytes[11..15].try_into().unwrap()) <= 0.08);
    bytes[11..15].copy_from_slice(&1000.0f32.to_le_bytes());
    refused(&mut client, &bytes, |e| matches!(e, ReplicationError::Malformed(m) if m.contains("cap")));
    client.apply(&game.messages[0]).unwrap();
}

#[test]
fn a_late_joiner_of_bodies_that_keep_their_volume_ends_bit_identical_normals_included() {
    // The rim of VolumeMode::Preserve pushes along the vertex normals, which a dent refreshes
    // only around what it moved, and a late joiner rebuilds its meshes from positions and
    // faces: its normals, and so its next dents, must still be the server's (here with
    // authored normals, an asset's, tilted 0.1 rad).
    let authored = |m: TriMesh| {
        let normals = m.normals().iter().map(|n| (*n + 0.1 * Vec3::X).normalize()).collect();
        TriMesh::with_normals(m.positions().to_vec(), m.faces().to_vec(), normals).unwrap()
    };
    let mut game = Game::with(|s| s.params.volume = dentbend::dent::VolumeMode::Preserve, authored);
    game.server.forget(SOFT);
    while game.dents_on[0] + game.dents_on[1] < 40 {
        game.step().unwrap();
    }
    let before_join = game.messages.len();
    let mut late = game.client();
    late.join(&game.snapshot()).unwrap();
    while game.dents_on[0] + game.dents_on[1] < 80 {
        game.step().unwrap();
    }
    for m in &game.messages[before_join..] {
        late.apply(m).unwrap();
    }
    let bits = |v: &[Vec3]| v.iter().map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>();
    for id in [PLATE, BLOCK] {
        let (c, s) = (late.mesh(id).unwrap(), game.set.mesh(id).unwrap());
        assert_eq!(content_hash(c), content_hash(s), "body {id}");
        assert_eq!(bits(c.normals()), bits(s.normals()), "body {id}: normals bit for bit");
    }
}
