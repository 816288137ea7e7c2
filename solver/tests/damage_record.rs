//! Damage as data through the engine-neutral API: a `damage::Damage` user records the dents it
//! applies (`record::DamageRecorder`), writes them as a damage file and replays them onto a
//! fresh copy of the base mesh — bit-identical as mesh edits and as impacts (the multiplayer
//! form), and refused with a typed error, changing nothing, when the file is truncated, of
//! another version, from another mesh, tampered with or absurd. A simulation's fracture (scene
//! `wall`) replays with its pieces bit for bit, and a tampered fracture record is refused.

mod common;

use common::SplitMix64;
use dentbend::damage::{CpuBackend, Damage, Hit, TargetSet};
use dentbend::dent::{BodyState, DentSettings, Impact, Surface};
use dentbend::glam::{Affine3A, Mat3, Quat, Vec3};
use dentbend::mesh::{self, TriMesh, content_hash};
use dentbend::record::{
    BodyDamage, DamageFile, DamageRecord, DamageRecorder, DentForm, Projectiles, RecordError, RecordForms, SceneRef,
    base64_decode, base64_encode, decode_records, encode_records, replay_body,
};
use dentbend_solver::coupling::{DamageLog, Simulation};
use dentbend_solver::scene::{SceneSize, builtin_scene};
use dentbend_solver::sim::World;

const TARGET: u32 = 1;
const BALL: u32 = 2;

/// A damaged body: its base mesh, its final mesh as the damage API left it, what was recorded,
/// and the projectile meshes.
struct Damaged {
    base: TriMesh,
    last: TriMesh,
    file: DamageFile,
    projectiles: Projectiles,
}

/// Bitwise equality of positions, faces and normals, with the first difference named.
fn assert_bit_identical(a: &TriMesh, b: &TriMesh, what: &str) {
    assert_eq!(a.faces(), b.faces(), "{what}: faces");
    let bits = |m: &TriMesh, k: usize| {
        (m.positions()[k].to_array().map(f32::to_bits), m.normals()[k].to_array().map(f32::to_bits))
    };
    assert_eq!(a.vertex_count(), b.vertex_count(), "{what}: vertex count");
    if let Some(k) = (0..a.vertex_count()).find(|&k| bits(a, k) != bits(b, k)) {
        panic!("{what}: vertex {k} differs: {:?} vs {:?}", bits(a, k), bits(b, k));
    }
}

/// `dents` random dents (in plans of up to 3 hits: Jacobi batches) by a 0.25 m ball on `base`
/// posed at `pose`: each at a random vertex whose outward normal faces up-ish (so the ball sits
/// outside), glancing up to about 40°, 2–6 m/s.
fn damage(base: TriMesh, pose: Affine3A, dents: usize, seed: u64) -> Damaged {
    let mut settings = DentSettings::new(1.0, 0.02, 0.08);
    settings.params.resolution = dentbend::Resolution::Auto { min: 25, max: 120 };
    let mut set = TargetSet::new();
    set.insert(TARGET, base.clone(), pose, settings).unwrap();
    set.insert_rigid(BALL);
    let ball = mesh::icosphere(0.25, 2).unwrap();
    let mut projectiles = Projectiles::new();
    projectiles.insert(ball.clone());
    let mut recorder = DamageRecorder::new(RecordForms::BOTH);
    recorder.track(TARGET, "target", &base);
    let mut rng = SplitMix64::new(seed);
    let mut damage = Damage::new();
    let (mut made, mut step) = (0, 0);
    while made < dents {
        step += 1;
        let mesh = set.mesh(TARGET).unwrap().clone();
        let mut hits = Vec::new();
        let mut poses = Vec::new();
        for _ in 0..3 {
            let v = loop {
                let v = rng.below(mesh.vertex_count() as u64) as usize;
                if pose.transform_vector3(mesh.normals()[v]).y > 0.5 {
                    break v;
                }
            };
            let outward = pose.transform_vector3(mesh.normals()[v]).normalize();
            let point = pose.transform_point3(mesh.positions()[v]);
            let tangent = outward.any_orthonormal_vector() * rng.range_f32(-0.8, 0.8);
            let speed = rng.range_f32(2.0, 6.0);
            let centre = point + 0.25 * outward;
            let state = BodyState::moving(centre, (tangent - outward) * speed, Vec3::ZERO, 1.0, Mat3::IDENTITY * 40.0);
            poses.push((point, outward, state));
        }
        for &(point, outward, state) in &poses {
            hits.push(Hit {
                target: TARGET,
                projectile: BALL,
                impact: Impact::from_contact(point, -outward, &BodyState::FIXED, &state).unwrap(),
                target_state: BodyState::FIXED,
                projectile_state: state,
                projectile_surface: Surface { mesh: &ball, to_world: Affine3A::from_translation(state.center_of_mass) },
            });
        }
        let plan = damage.plan(&set, &hits, step, &mut CpuBackend).unwrap();
        recorder.record(&set, &hits, &plan).unwrap();
        made += plan.dents.len();
        set.apply(plan.targets);
    }
    Damaged { base, last: set.mesh(TARGET).unwrap().clone(), file: recorder.file(), projectiles }
}

/// `file` without its dents' mesh edits: what a multiplayer client is sent.
fn impacts_only(file: &DamageFile) -> DamageFile {
    let mut out = file.clone();
    for body in &mut out.bodies {
        for record in &mut body.records {
            if let DamageRecord::Dents(batch) = record {
                batch.edit = None;
            }
        }
    }
    out
}

fn check_round_trip(d: &Damaged, name: &str) {
    let bytes = d.file.to_json().unwrap();
    let file = DamageFile::from_json(&bytes).unwrap();
    let body = &file.bodies[0];
    let dents = body.dents();
    assert!(dents >= 30, "{name}: {dents} dents");
    assert_eq!(body.final_mesh.hash, content_hash(&d.last));
    let from_edits = replay_body(body, &d.base, DentForm::Edits, &d.projectiles).unwrap().mesh;
    assert_bit_identical(&from_edits, &d.last, &format!("{name}, edits"));
    let from_impacts = replay_body(body, &d.base, DentForm::Impacts, &d.projectiles).unwrap().mesh;
    assert_bit_identical(&from_impacts, &d.last, &format!("{name}, impacts"));
    let small = impacts_only(&file).to_json().unwrap();
    let client = DamageFile::from_json(&small).unwrap();
    let on_client = replay_body(&client.bodies[0], &d.base, DentForm::Edits, &d.projectiles).unwrap().mesh;
    assert_bit_identical(&on_client, &d.last, &format!("{name}, impacts-only file"));
    let (both, impacts) = (bytes.len() as f64 / dents as f64, small.len() as f64 / dents as f64);
    eprintln!("{name}: {dents} dents; edits + impacts {both:.0} bytes/dent, impacts only {impacts:.0} bytes/dent");
    // An impact record is 182 bytes of binary (impact 36, two poses 96, projectile hash 8,
    // reach 4, flags 2, parameters 35 or so), 243 in base64; batch headers and JSON add a few.
    assert!(impacts < 300.0, "{name}: impacts form takes {impacts:.0} bytes/dent");
}

#[test]
fn block_fine_damage_replays_bit_identically_as_edits_and_as_impacts() {
    let d = damage(mesh::builtin("block-fine").unwrap(), Affine3A::IDENTITY, 36, 18);
    check_round_trip(&d, "block-fine");
}

#[test]
fn posed_bunny_damage_replays_bit_identically_as_edits_and_as_impacts() {
    let pose = Affine3A::from_rotation_translation(Quat::from_rotation_y(0.7), Vec3::new(3.0, -1.0, 2.0));
    let bunny = mesh::builtin("bunny").unwrap();
    // The bunny is about 10 across: scale it to 2 so that 0.08 m dents matter.
    let mut small = bunny.clone();
    small.transform(Affine3A::from_scale(Vec3::splat(0.2))).unwrap();
    let d = damage(small, pose, 36, 5);
    check_round_trip(&d, "bunny");
}

/// A small recording: three plans on the coarse block.
fn small_damage() -> Damaged {
    damage(mesh::builtin("block").unwrap(), Affine3A::IDENTITY, 6, 3)
}

/// Replays `file`'s first body onto `base` and returns the error, checking that `base` did not
/// change.
fn refused(file: &DamageFile, base: &TriMesh, projectiles: &Projectiles) -> RecordError {
    let before = content_hash(base);
    let error = replay_body(&file.bodies[0], base, DentForm::Edits, projectiles).unwrap_err();
    assert_eq!(content_hash(base), before, "a refused replay changed its base");
    error
}

#[test]
fn truncated_files_are_refused_with_a_typed_error() {
    let d = small_damage();
    let bytes = d.file.to_json().unwrap();
    for cut in [1, bytes.len() / 3, bytes.len() / 2, bytes.len() - 2] {
        match DamageFile::from_json(&bytes[..cut]) {
            Err(RecordError::Truncated { .. }) => {}
            other => panic!("cut at {cut} of {}: {other:?}", bytes.len()),
        }
    }
    // A records string cut at a base64 boundary: the binary records end early.
    let text = String::from_utf8(bytes).unwrap();
    let records = d.file.bodies[0].records.len();
    assert!(records > 0);
    let start = text.find("\"records\":\"").unwrap() + 11;
    let end = start + text[start..].find('"').unwrap();
    let cut = format!("{}{}", &text[..end - 40], &text[end..]);
    assert!(matches!(DamageFile::from_json(cut.as_bytes()), Err(RecordError::Truncated { .. })));
}

#[test]
fn another_version_or_format_is_refused() {
    let d = small_damage();
    let text = String::from_utf8(d.file.to_json().unwrap()).unwrap();
    assert!(text.contains("\"version\":3"), "written as version 3");
    let newer = text.replacen("\"version\":3", "\"version\":4", 1);
    assert!(matches!(DamageFile::from_json(newer.as_bytes()), Err(RecordError::Version { found: 4, supported: 3 })));
    let older = text.replacen("\"version\":3", "\"version\":0", 1);
    assert!(matches!(DamageFile::from_json(older.as_bytes()), Err(RecordError::Version { found: 0, supported: 3 })));
    // Version 2 (before refinements were recorded) still reads.
    let previous = text.replacen("\"version\":3", "\"version\":2", 1);
    assert!(DamageFile::from_json(previous.as_bytes()).is_ok());
    let other = text.replacen("dentbend-damage", "something-else", 1);
    assert!(matches!(DamageFile::from_json(other.as_bytes()), Err(RecordError::Malformed(_))));
}

#[test]
fn damage_from_another_mesh_is_refused() {
    let d = small_damage();
    let other = mesh::builtin("block-fine").unwrap();
    assert!(matches!(refused(&d.file, &other, &d.projectiles), RecordError::BaseMismatch { .. }));
    // One ulp of one coordinate is another mesh too.
    let mut positions = d.base.positions().to_vec();
    positions[0].x = f32::from_bits(positions[0].x.to_bits() + 1);
    let nudged = TriMesh::new(positions, d.base.faces().to_vec()).unwrap();
    assert!(matches!(refused(&d.file, &nudged, &d.projectiles), RecordError::BaseMismatch { .. }));
}

#[test]
fn tampered_files_are_refused() {
    let d = small_damage();
    // A moved vertex put elsewhere: the batch's result hash no longer matches.
    let mut moved = d.file.clone();
    let DamageRecord::Dents(batch) = &mut moved.bodies[0].records[0] else { panic!("a dent batch first") };
    batch.edit.as_mut().unwrap().moved[0].1[1] += 1000;
    let reread = DamageFile::from_json(&moved.to_json().unwrap()).unwrap();
    assert!(matches!(refused(&reread, &d.base, &d.projectiles), RecordError::Tampered { record: 0, .. }));
    // A moved vertex index beyond the mesh: the edit does not apply.
    let mut beyond = d.file.clone();
    let DamageRecord::Dents(batch) = &mut beyond.bodies[0].records[0] else { panic!() };
    let edit = batch.edit.as_mut().unwrap();
    edit.moved.last_mut().unwrap().0 = edit.base_vertices + 5;
    let reread = DamageFile::from_json(&beyond.to_json().unwrap()).unwrap();
    assert!(matches!(refused(&reread, &d.base, &d.projectiles), RecordError::Tampered { record: 0, .. }));
    // A final hash that is not the records' result.
    let mut last = d.file.clone();
    last.bodies[0].final_mesh.hash ^= 1;
    let records = last.bodies[0].records.len();
    let error = refused(&last, &d.base, &d.projectiles);
    assert!(matches!(error, RecordError::Tampered { record, .. } if record == records), "{error}");
    // An impact moved: the recomputed dent is not the recorded one.
    let mut aimed = impacts_only(&d.file);
    let DamageRecord::Dents(batch) = &mut aimed.bodies[0].records[1] else { panic!() };
    batch.impacts[0].impact.point.x += 0.01;
    assert!(matches!(refused(&aimed, &d.base, &d.projectiles), RecordError::Tampered { record: 1, .. }));
    // An impact whose projectile the replay was not given.
    let client = impacts_only(&d.file);
    assert!(matches!(refused(&client, &d.base, &Projectiles::new()), RecordError::MissingProjectile { .. }));
}

/// Builds a file whose first body's records are `records` (binary, before base64).
fn with_records(file: &DamageFile, records: &[u8]) -> Vec<u8> {
    let text = String::from_utf8(file.to_json().unwrap()).unwrap();
    let start = text.find("\"records\":\"").unwrap() + 11;
    let end = start + text[start..].find('"').unwrap();
    format!("{}{}{}", &text[..start], base64_encode(records), &text[end..]).into_bytes()
}

#[test]
fn absurd_counts_are_refused_before_allocating() {
    let d = small_damage();
    let base = &d.file.bodies[0];
    // The body's own records decode (the splice itself is sound).
    let text = String::from_utf8(d.file.to_json().unwrap()).unwrap();
    let start = text.find("\"records\":\"").unwrap() + 11;
    let end = start + text[start..].find('"').unwrap();
    let own = base64_decode(&text[start..end], "records").unwrap();
    assert!(DamageFile::from_json(&with_records(&d.file, &own)).is_ok());
    let varint = |mut v: u64, out: &mut Vec<u8>| {
        while v >= 0x80 {
            out.push((v as u8) | 0x80);
            v >>= 7;
        }
        out.push(v as u8);
    };
    // 2⁶² records.
    let mut many = Vec::new();
    varint(1 << 62, &mut many);
    assert!(matches!(DamageFile::from_json(&with_records(&d.file, &many)), Err(RecordError::TooLarge { .. })));
    // One dent batch whose edit claims 2²⁷ moved vertices in a few bytes.
    let mut huge = Vec::new();
    varint(1, &mut huge); // one record
    huge.push(1); // a dent batch
    varint(1, &mut huge); // of one dent
    varint(0, &mut huge); // no impacts
    huge.push(1); // an edit
    varint(u64::from(base.base.vertices), &mut huge);
    varint(u64::from(base.base.faces), &mut huge);
    varint(1 << 27, &mut huge); // moved vertices
    huge.extend_from_slice(&[0; 16]);
    match DamageFile::from_json(&with_records(&d.file, &huge)) {
        Err(RecordError::Truncated { needed, .. }) => assert!(needed >= 4 << 27),
        other => panic!("{other:?}"),
    }
    // An unknown record kind.
    let mut unknown = Vec::new();
    varint(1, &mut unknown);
    unknown.extend_from_slice(&[99, 0, 0]);
    assert!(matches!(DamageFile::from_json(&with_records(&d.file, &unknown)), Err(RecordError::Malformed(_))));
}

#[test]
fn a_client_replays_a_binary_impact_message_with_a_built_in_projectile() {
    // A block dented by the built-in sphere, recorded as impacts naming it.
    let mut set = TargetSet::new();
    let block = mesh::builtin("block-fine").unwrap();
    set.insert(TARGET, block.clone(), Affine3A::IDENTITY, DentSettings::new(1.0, 0.02, 0.1)).unwrap();
    set.insert_rigid(BALL);
    let ball = mesh::builtin("sphere").unwrap();
    let mut recorder = DamageRecorder::new(RecordForms::IMPACTS);
    recorder.track(TARGET, "block", &block);
    recorder.name_projectile(&ball, "sphere").unwrap();
    assert!(recorder.name_projectile(&ball, "block").is_err(), "the name must be the mesh's");
    let state = BodyState::moving(Vec3::new(0.3, 1.5, 0.0), Vec3::new(1.0, -5.0, 0.0), Vec3::ZERO, 2.0, Mat3::IDENTITY);
    let point = Vec3::new(0.3, 0.5, 0.0);
    let hits = [Hit {
        target: TARGET,
        projectile: BALL,
        impact: Impact::from_contact(point, -Vec3::Y, &BodyState::FIXED, &state).unwrap(),
        target_state: BodyState::FIXED,
        projectile_state: state,
        projectile_surface: Surface { mesh: &ball, to_world: Affine3A::from_translation(state.center_of_mass) },
    }];
    let plan = Damage::new().plan(&set, &hits, 1, &mut CpuBackend).unwrap();
    recorder.record(&set, &hits, &plan).unwrap();
    set.apply(plan.targets);
    let body = recorder.body(TARGET).unwrap();
    // The message a server sends: the body's records as binary.
    let message = dentbend::record::encode_records(&body.records).unwrap();
    eprintln!("one impact dent: {} bytes of binary", message.len());
    // Record count, tag, dent count, impact count (4); contact 36, two poses 96, hash 8, name 7,
    // reach 4, flag 1 (152); every parameter (42, with refinement 5, volume mode 1 and guard flag 1); no-edit
    // flag and result hash (9).
    assert!(message.len() <= 207, "{} bytes", message.len());
    let mut received = body.clone();
    received.records = dentbend::record::decode_records(&message).unwrap();
    // The client has the block and the built-in sphere; it is given no projectile mesh.
    let replayed = replay_body(&received, &block, DentForm::Impacts, &Projectiles::new()).unwrap().mesh;
    assert_bit_identical(&replayed, set.mesh(TARGET).unwrap(), "binary impact message");
    assert!(matches!(
        dentbend::record::decode_records(&message[..message.len() - 1]),
        Err(RecordError::Truncated { .. })
    ));
}

#[test]
fn a_custom_falloff_cannot_be_recorded_as_an_impact_and_nothing_is_recorded() {
    let mut settings = DentSettings::new(1.0, 0.02, 0.1);
    settings.params.attenuation = dentbend::Attenuation::Custom(std::sync::Arc::new(|z: f32, d: f32| (-z / d).exp()));
    let mut set = TargetSet::new();
    let block = mesh::builtin("block").unwrap();
    set.insert(TARGET, block.clone(), Affine3A::IDENTITY, settings).unwrap();
    set.insert_rigid(BALL);
    let ball = mesh::icosphere(0.25, 2).unwrap();
    let state =
        BodyState::moving(Vec3::new(0.0, 0.75, 0.0), Vec3::new(0.0, -5.0, 0.0), Vec3::ZERO, 1.0, Mat3::IDENTITY);
    let hits = [Hit {
        target: TARGET,
        projectile: BALL,
        impact: Impact::from_contact(Vec3::new(0.0, 0.5, 0.0), -Vec3::Y, &BodyState::FIXED, &state).unwrap(),
        target_state: BodyState::FIXED,
        projectile_state: state,
        projectile_surface: Surface { mesh: &ball, to_world: Affine3A::from_translation(state.center_of_mass) },
    }];
    let plan = Damage::new().plan(&set, &hits, 1, &mut CpuBackend).unwrap();
    assert_eq!(plan.dents.len(), 1);
    let mut recorder = DamageRecorder::new(RecordForms::BOTH);
    recorder.track(TARGET, "block", &block);
    assert!(matches!(recorder.record(&set, &hits, &plan), Err(RecordError::NotRecordable(_))));
    assert!(recorder.body(TARGET).unwrap().records.is_empty(), "a refused plan records nothing");
    // As an edit it records, and replays exactly.
    let mut edits = DamageRecorder::new(RecordForms::EDITS);
    edits.track(TARGET, "block", &block);
    edits.record(&set, &hits, &plan).unwrap();
    set.apply(plan.targets);
    let replayed = replay_body(edits.body(TARGET).unwrap(), &block, DentForm::Edits, &Projectiles::new()).unwrap().mesh;
    assert_bit_identical(&replayed, set.mesh(TARGET).unwrap(), "custom falloff as an edit");
    // The set's mesh changed outside the recorder: the next plan is refused.
    set.apply(vec![dentbend::damage::DentedTarget {
        key: TARGET,
        mesh: block.clone(),
        moved: Vec::new(),
        refinement: Default::default(),
        topology_changed: false,
    }]);
    let plan = Damage::new().plan(&set, &hits, 2, &mut CpuBackend).unwrap();
    assert!(matches!(edits.record(&set, &hits, &plan), Err(RecordError::Tampered { .. })));
}

/// The built-in scene `wall` (paper Figure 3) run for `frames` steps and recorded: the
/// simulation (its meshes are what the replay must give), the damage file read back from its
/// JSON, and the scene's base meshes by name.
fn recorded_wall(frames: u32) -> (Simulation, DamageFile, Vec<(String, TriMesh)>) {
    recorded(builtin_scene("wall", SceneSize::Demo).unwrap().world, frames)
}

/// `world` run for `frames` steps and recorded, as [`recorded_wall`].
fn recorded(world: World, frames: u32) -> (Simulation, DamageFile, Vec<(String, TriMesh)>) {
    let bases = world.bodies().iter().map(|b| (b.name.clone(), b.mesh().clone())).collect();
    let mut sim = Simulation::new(world, None).unwrap();
    let mut log = DamageLog::new(&sim);
    for _ in 0..frames {
        sim.step().unwrap();
        log.after_step(&sim).unwrap();
    }
    let scene = SceneRef { spec: "wall".into(), size: "demo".into(), file_hash: None, frame: u64::from(frames) };
    let file = log.finish(&mut sim, scene).unwrap();
    (sim, DamageFile::from_json(&file.to_json().unwrap()).unwrap(), bases)
}

/// Replays every body of `file` (pieces from the fracture that made them) and checks each
/// against `sim`'s mesh and pose, bit for bit.
fn assert_replays(sim: &Simulation, file: &DamageFile, bases: &[(String, TriMesh)]) {
    let world = sim.world();
    let projectiles = Projectiles::new();
    let mut from_fractures: Vec<(String, TriMesh)> = Vec::new();
    for body in &file.bodies {
        let base = match bases.iter().find(|(n, _)| *n == body.name) {
            Some((_, mesh)) => mesh.clone(),
            None => {
                let k = from_fractures.iter().position(|(n, _)| *n == body.name).expect("a piece replayed first");
                from_fractures.swap_remove(k).1
            }
        };
        let replayed = replay_body(body, &base, DentForm::Edits, &projectiles).unwrap();
        from_fractures.extend(replayed.pieces);
        let now = &world.bodies()[world.find(&body.name).unwrap()];
        assert_bit_identical(&replayed.mesh, now.mesh(), &body.name);
        assert_eq!(body.pose, Some(now.transform()), "{}", body.name);
    }
    assert!(from_fractures.is_empty(), "every piece is listed as a body");
}

/// The wall's record index of its fracture.
fn fracture_of(body: &BodyDamage) -> usize {
    body.records.iter().position(|r| matches!(r, DamageRecord::Fracture(_))).expect("a fracture record")
}

/// The wall breaks into pieces at about frame 80 of 120 (solver/tests/paper_fig03_wall.rs); its damage
/// file lists the wall (dents, then the fracture), the balls and every piece as a body, and
/// replaying it through the API gives every body's mesh bit for bit: the wall's rest from its
/// scene mesh, each piece from the wall's fracture.
#[test]
fn a_fracture_replays_bit_identically_with_its_pieces() {
    let (sim, file, bases) = recorded_wall(120);
    let fractures = sim.fractures();
    assert_eq!(fractures.len(), 1, "the wall breaks once");
    let wall = file.body("wall").unwrap();
    let DamageRecord::Fracture(f) = &wall.records[fracture_of(wall)] else { unreachable!() };
    assert!(wall.dents() >= 3, "the wall's dents are recorded before its fracture");
    assert_eq!(f.pieces.iter().map(|p| p.name.as_str()).collect::<Vec<_>>(), fractures[0].pieces);
    // Listed as `run` lists them: the world's bodies in order, pieces included.
    let world = sim.world();
    let names: Vec<&str> = world.bodies().iter().map(|b| b.name.as_str()).collect();
    assert_eq!(file.bodies.iter().map(|b| b.name.as_str()).collect::<Vec<_>>(), names);
    assert_replays(&sim, &file, &bases);
    assert!(f.pieces.len() >= 10, "{} pieces", f.pieces.len());
}

/// The wall made dynamic, its mesh off its centre of mass (so the body, its rest and its pieces
/// each sit in coordinates of their own): the fracture's shifts are not zero and the replay
/// still gives every mesh bit for bit.
#[test]
fn a_moving_body_breaks_and_replays_bit_identically() {
    let world = common::walls::moving_wall();
    let (sim, file, bases) = recorded(world, 120);
    assert_eq!(sim.fractures().len(), 1, "the moving wall breaks once");
    let wall = file.body("wall").unwrap();
    let DamageRecord::Fracture(f) = &wall.records[fracture_of(wall)] else { unreachable!() };
    assert!(f.to_model != Vec3::ZERO && f.rest_shift != Vec3::ZERO, "{f:?}");
    assert!(f.pieces.len() >= 10 && f.pieces.iter().all(|p| p.shift != Vec3::ZERO));
    assert_replays(&sim, &file, &bases);
}

/// A fracture record altered in the file (another seed, a NaN density, a piece the fracture did
/// not make, another mesh it is applied to) is refused with a typed error, its base untouched.
#[test]
fn a_tampered_fracture_record_is_refused_and_changes_nothing() {
    let (_, file, bases) = recorded_wall(120);
    let base = &bases.iter().find(|(n, _)| n == "wall").unwrap().1;
    let k = fracture_of(file.body("wall").unwrap());
    let projectiles = Projectiles::new();
    let altered = |change: &dyn Fn(&mut dentbend::record::FractureRecord)| {
        let mut file = file.clone();
        let wall = file.bodies.iter_mut().find(|b| b.name == "wall").unwrap();
        let DamageRecord::Fracture(f) = &mut wall.records[k] else { unreachable!() };
        change(f);
        // Through the file's bytes, as a received file would come.
        let file = DamageFile::from_json(&file.to_json().unwrap()).unwrap();
        let wall = file.bodies.iter().position(|b| b.name == "wall").unwrap();
        DamageFile { bodies: vec![file.bodies[wall].clone()], ..file }
    };
    let error = refused(&altered(&|f| f.fracture.pattern.seed += 1), base, &projectiles);
    assert!(matches!(error, RecordError::Tampered { record, .. } if record == k), "{error}");
    let error = refused(&altered(&|f| f.fracture.density = f32::NAN), base, &projectiles);
    assert!(matches!(error, RecordError::Fracture { record, .. } if record == k), "{error}");
    let error = refused(&altered(&|f| f.fracture.pattern.cells = 0), base, &projectiles);
    assert!(matches!(error, RecordError::Fracture { .. }), "{error}");
    let error = refused(&altered(&|f| f.pieces[0].index = 10_000), base, &projectiles);
    assert!(matches!(error, RecordError::Tampered { record, .. } if record == k), "{error}");
    let error = refused(&altered(&|f| f.to_model.x += 0.25), base, &projectiles);
    assert!(matches!(error, RecordError::Tampered { .. }), "{error}");
    // A truncated fracture record is refused as data.
    let wall = file.body("wall").unwrap();
    let bytes = encode_records(&wall.records[..=k]).unwrap();
    let cut = decode_records(&bytes[..bytes.len() - 5]).unwrap_err();
    assert!(matches!(cut, RecordError::Truncated { .. }), "{cut}");
}

/// A damage file of version 1 (whose fractures welded their output, seams or not): a
/// faceted 1.2 × 0.8 × 0.1 m wall (every face with vertices of its own) dented twice and broken
/// by the second hit. Its fracture replays as it was made, welded, and every hash checks, also
/// once the file is written again as version 2; read as version 2 (seams kept), the same
/// records give another rest and are refused.
#[test]
fn a_version_1_file_replays_its_fractures_welded() {
    let bytes = include_bytes!("fixtures/damage_v1_faceted_wall.json");
    let wall = mesh::subdivided_box(Vec3::new(1.2, 0.8, 0.1), [24, 16, 2]).unwrap();
    let positions = wall.faces().iter().flat_map(|f| f.map(|v| wall.positions()[v as usize])).collect();
    let faces = (0..wall.face_count() as u32).map(|f| [3 * f, 3 * f + 1, 3 * f + 2]).collect();
    let faceted = TriMesh::new(positions, faces).unwrap();

    let file = DamageFile::from_json(bytes).unwrap();
    let body = &file.bodies[0];
    assert!(body.records.iter().any(|r| matches!(r, DamageRecord::Fracture(_))), "the fixture has no fracture");
    let rest = replay_body(body, &faceted, DentForm::Edits, &Projectiles::new()).unwrap().mesh;
    assert_eq!(content_hash(&rest), body.final_mesh.hash);
    assert_eq!(rest.vertex_count(), 1216, "the rest as version 1 made it");
    // Written again (version 2), the fracture still replays welded.
    let again = DamageFile::from_json(&file.to_json().unwrap()).unwrap();
    assert_eq!(replay_body(&again.bodies[0], &faceted, DentForm::Edits, &Projectiles::new()).unwrap().mesh, rest);

    let text = String::from_utf8(bytes.to_vec()).unwrap().replacen("\"version\":1", "\"version\":2", 1);
    let as_new = DamageFile::from_json(text.as_bytes()).unwrap();
    let refused = replay_body(&as_new.bodies[0], &faceted, DentForm::Edits, &Projectiles::new());
    assert!(matches!(refused, Err(RecordError::Tampered { .. })), "{refused:?}");
}
