//! Hostile replication bytes on a client that has joined a small world: arbitrary bytes as a
//! message or a snapshot, or the world's first real message (a dent and a fracture) with bytes
//! flipped. A refused call leaves the client's meshes bit for bit and its place in the stream
//! as they were; an accepted one leaves every vertex and normal finite, or the plate removed (a
//! snapshot that says a fracture took it whole).
#![no_main]

use std::sync::OnceLock;

use dentbend::damage::{CpuBackend, Damage, Hit, TargetSet};
use dentbend::dent::{BodyState, DentSettings, Impact, Surface};
use dentbend::fracture::{FractureSettings, PatternParams};
use dentbend::glam::{Affine3A, Mat3, Vec3};
use dentbend::mesh;
use dentbend::record::replication::{ReplicationClient, ReplicationServer};
use dentbend_fuzz::{assert_finite_mesh, fingerprint};
use libfuzzer_sys::fuzz_target;

/// The plate's wire id.
const PLATE: u32 = 1;
/// The ball's projectile id.
const BALL: u32 = 2;

/// A client joined at the start of a plate's stream, and the stream's first messages.
struct World {
    client: ReplicationClient,
    messages: Vec<Vec<u8>>,
}

fn world() -> &'static World {
    static WORLD: OnceLock<World> = OnceLock::new();
    WORLD.get_or_init(|| {
        let plate = mesh::subdivided_box(Vec3::new(1.0, 0.2, 1.0), [6, 1, 6]).expect("a box");
        let ball = mesh::icosphere(0.2, 1).expect("a sphere");
        let mut settings = DentSettings::new(1.0, 0.02, 0.08);
        settings.params.resolution = dentbend::Resolution::Auto { min: 16, max: 32 };
        let mut set = TargetSet::new();
        set.insert(PLATE, plate.clone(), Affine3A::IDENTITY, settings.clone()).expect("a target");
        // The first hit (18 J) breaks a 0.3 m pattern out of the plate; the others (8 J) dent it.
        let pattern = PatternParams { cells: 6, seed: 1, radius: 0.3 };
        let fracture = FractureSettings::new(pattern, Some(12.0), None).expect("fracture settings");
        set.set_fracture(PLATE, Some(fracture)).expect("a breakable plate");
        set.insert_rigid(BALL);
        let mut server = ReplicationServer::new();
        server.track(PLATE, PLATE, &plate, &settings).expect("tracked");
        server.add_projectile(BALL, &ball).expect("registered");
        let mut client = ReplicationClient::new();
        client.add_body(PLATE, plate, &settings).expect("a body");
        client.add_projectile(BALL, ball.clone()).expect("a projectile");
        client.join(&server.snapshot(|k| set.mesh(k)).expect("a snapshot").bytes).expect("joined");
        let mut damage = Damage::new();
        let mut messages = Vec::new();
        for (step, (x, speed)) in [(-0.2f32, 6.0f32), (0.3, 4.0), (0.35, 4.0)].into_iter().enumerate() {
            let velocity = Vec3::new(0.5, -speed, 0.0);
            let state = BodyState::moving(Vec3::new(x, 0.3, 0.0), velocity, Vec3::ZERO, 1.0, Mat3::IDENTITY);
            let point = Vec3::new(x, 0.1, 0.0);
            let hit = Hit {
                target: PLATE,
                projectile: BALL,
                impact: Impact::from_contact(point, -Vec3::Y, &BodyState::FIXED, &state).expect("an impact"),
                target_state: BodyState::FIXED,
                projectile_state: state,
                projectile_surface: Surface { mesh: &ball, to_world: Affine3A::from_translation(state.center_of_mass) },
            };
            let plan = damage.plan(&set, &[hit], step as u64 + 1, &mut CpuBackend).expect("a plan");
            let dents = plan.dents.clone();
            set.apply(plan.targets);
            assert_eq!(plan.fractures.len(), usize::from(step == 0), "only the first hit breaks the plate");
            assert!(plan.fractures.iter().all(|f| f.rest.is_some()), "the plate keeps a rest");
            plan.fractures.iter().for_each(|f| set.apply_fracture(f));
            let ball = &ball;
            let message = server.message(&dents, &plan.fractures, |k| set.mesh(k), |k| (k == BALL).then_some(ball)).expect("a message");
            messages.extend(message);
        }
        World { client, messages }
    })
}

fuzz_target!(|data: &[u8]| {
    let Some((&mode, rest)) = data.split_first() else { return };
    let world = world();
    let mut client = world.client.clone();
    let before = fingerprint(client.mesh(PLATE).expect("the plate"));
    let next = client.next_message();
    let result = match mode % 3 {
        0 => client.apply(rest),
        1 => client.join(rest),
        _ => {
            // A real message with the rest of the input XORed over it from its second byte.
            let Some(message) = world.messages.first() else { return };
            let mut bytes = message.clone();
            for (b, flip) in bytes.iter_mut().skip(1).zip(rest) {
                *b ^= flip;
            }
            client.apply(&bytes)
        }
    };
    let plate = client.mesh(PLATE);
    match result {
        Err(_) => {
            let plate = plate.expect("a refused call keeps the plate");
            assert_eq!(fingerprint(plate), before, "a refused call changed the mesh");
            assert_eq!(client.next_message(), next, "a refused call moved the client in the stream");
        }
        // A snapshot may say a fracture took the plate whole: the client removes it then.
        Ok(_) => plate.into_iter().for_each(assert_finite_mesh),
    }
});
