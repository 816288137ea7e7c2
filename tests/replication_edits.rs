//! A replication server in mesh-edit mode (`ReplicationServer::with_mesh_edits`), for servers
//! whose dents run on a GPU: a plate and a block dented by balls on the server's backend (the
//! CPU, and the GPU when there is one) reach a client there from the start and a late joiner as
//! exact mesh edits; both end bit-identical to the server's meshes, whatever backend made them.

mod common;

use common::hits;
use dentbend::damage::{CpuBackend, Damage, DentBackend, DentTargets, TargetSet};
use dentbend::dent::{BodyState, DentSettings};
use dentbend::glam::{Affine3A, Mat3, Vec3};
use dentbend::gpu::{GpuBackend, GpuContext};
use dentbend::mesh::{self, TriMesh, content_hash};
use dentbend::record::replication::{ReplicationClient, ReplicationServer};

const PLATE: u32 = 1;
const BLOCK: u32 = 2;
const BALL: u32 = 10;
const BALL_SHAPE: u32 = 3;

fn settings() -> DentSettings {
    DentSettings::new(1.0, 0.02, 0.06)
}

fn bases() -> Vec<(u32, TriMesh, Affine3A)> {
    vec![
        (PLATE, mesh::subdivided_box(Vec3::new(2.0, 0.2, 2.0), [16, 2, 16]).unwrap(), Affine3A::IDENTITY),
        (
            BLOCK,
            mesh::subdivided_box(Vec3::new(1.0, 0.6, 1.0), [8, 5, 8]).unwrap(),
            Affine3A::from_translation(Vec3::new(3.0, 0.2, 0.0)),
        ),
    ]
}

fn client(ball: &TriMesh) -> ReplicationClient {
    let mut c = ReplicationClient::new();
    for (id, base, _) in bases() {
        c.add_body(id, base, &settings()).unwrap();
    }
    c.add_projectile(BALL_SHAPE, ball.clone()).unwrap();
    c
}

/// Eight steps of one ball each on the top faces of the plate and the block, dented on
/// `backend`; a client joins at the start and another after four steps.
fn edits_replicate(backend: &mut dyn DentBackend<u32>) {
    let ball = mesh::icosphere(0.2, 2).unwrap();
    let mut set = TargetSet::new();
    let mut server = ReplicationServer::new().with_mesh_edits();
    for (id, base, pose) in bases() {
        set.insert(id, base.clone(), pose, settings()).unwrap();
        server.track(id, id, &base, &settings()).unwrap();
    }
    set.insert_rigid(BALL);
    server.add_projectile(BALL_SHAPE, &ball).unwrap();
    let mut early = client(&ball);
    early.join(&server.snapshot(|k| set.mesh(k)).unwrap().bytes).unwrap();
    let mut late: Option<ReplicationClient> = None;
    let mut damage = Damage::new();
    let mut dents = 0;
    for step in 1..=8u64 {
        let id = if step % 2 == 0 { PLATE } else { BLOCK };
        // On the top face (y = 0.1 for the plate, 0.3 for the block), 10 cm apart.
        let x = 0.1 * step as f32 - 0.4;
        let top = if id == PLATE { 0.1 } else { 0.3 };
        let point = set.target(id).unwrap().to_world.transform_point3(Vec3::new(x, top, -0.2 * x));
        let centre = point + Vec3::Y * 0.2;
        let state = BodyState::moving(centre, Vec3::new(0.3, -4.0, 0.0), Vec3::ZERO, 1.0, Mat3::IDENTITY * 60.0);
        let hit = hits::on_fixed(id, BALL, &ball, point, -Vec3::Y, state);
        let plan = damage.plan(&set, &[hit], step, backend).unwrap();
        dents += plan.dents.len();
        set.apply(plan.targets);
        let message = server.message(&plan.dents, &plan.fractures, |k| set.mesh(k), |_| Some(&ball)).unwrap();
        let Some(message) = message else { continue };
        early.apply(&message).unwrap();
        if let Some(late) = late.as_mut() {
            late.apply(&message).unwrap();
        }
        if step == 4 {
            let mut joiner = client(&ball);
            joiner.join(&server.snapshot(|k| set.mesh(k)).unwrap().bytes).unwrap();
            late = Some(joiner);
        }
    }
    assert_eq!(dents, 8, "every ball dents");
    for c in [&early, late.as_ref().unwrap()] {
        for (id, base, _) in bases() {
            let (server_mesh, client_mesh) = (set.mesh(id).unwrap(), c.mesh(id).unwrap());
            assert_ne!(content_hash(server_mesh), content_hash(&base), "body {id} was dented");
            assert_eq!(client_mesh.positions(), server_mesh.positions(), "body {id}, bit for bit");
            assert_eq!(client_mesh.faces(), server_mesh.faces());
        }
    }
}

fn mesh_edits_replicate_a_cpu_servers_dents_bit_for_bit() {
    edits_replicate(&mut CpuBackend);
}

fn mesh_edits_replicate_a_gpu_servers_dents_bit_for_bit(context: &'static GpuContext) {
    edits_replicate(&mut GpuBackend::new(context));
}

gpu_test_main! {
    plain: [mesh_edits_replicate_a_cpu_servers_dents_bit_for_bit],
    gpu: [mesh_edits_replicate_a_gpu_servers_dents_bit_for_bit],
}
