//! Bad contacts and unknown bodies: a typed error naming what was wrong, and no mesh,
//! collider, body or joint changed. Contacts of bodies removed after the step are skipped and
//! reported, and the step's other dents made.

use dentbend::damage::CpuBackend;
use dentbend::mesh::{self, TriMesh};
use dentbend_rapier::demo::rain::{ball_dent, target_dent};
use dentbend_rapier::rapier3d::prelude::{ActiveEvents, ColliderHandle, RigidBodyBuilder, RigidBodyHandle};
use dentbend_rapier::{AdapterError, BodyStates, Contact, Dentables, PhysicsWorld, convex_collider, trimesh_collider};
use glam::Vec3;

struct Scene {
    world: PhysicsWorld,
    dentables: Dentables,
    block: ColliderHandle,
    ball_body: RigidBodyHandle,
    ball: ColliderHandle,
}

/// A 2 × 0.5 × 2 block (top at y = 0.25) and a ball of radius 0.1 just above it falling at
/// 6 m/s, both dentable.
fn scene() -> Scene {
    let mut world = PhysicsWorld::new(Vec3::new(0.0, -9.81, 0.0), 1.0 / 60.0);
    let block_mesh = mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [16, 4, 16]).unwrap();
    let fixed = world.bodies.insert(RigidBodyBuilder::fixed());
    let block = world.colliders.insert_with_parent(trimesh_collider(&block_mesh).unwrap(), fixed, &mut world.bodies);
    let ball_mesh = mesh::icosphere(0.1, 2).unwrap();
    let ball_body = world
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vec3::new(0.0, 0.36, 0.0)).linvel(Vec3::new(0.0, -6.0, 0.0)));
    let collider = convex_collider(&ball_mesh).unwrap().active_events(ActiveEvents::CONTACT_FORCE_EVENTS);
    let ball = world.colliders.insert_with_parent(collider, ball_body, &mut world.bodies);
    let mut dentables = Dentables::new();
    dentables.insert(&world.colliders, &world.bodies, block, block_mesh, target_dent()).unwrap();
    dentables.insert(&world.colliders, &world.bodies, ball, ball_mesh, ball_dent()).unwrap();
    Scene { world, dentables, block, ball_body, ball }
}

/// A head-on hit of the ball on the block's top.
fn good_contact(s: &Scene) -> Contact {
    Contact {
        collider1: s.block,
        collider2: s.ball,
        point: Vec3::new(0.0, 0.25, 0.0),
        normal: Vec3::Y,
        impulse: 1.0,
        started: true,
    }
}

/// Everything the adapter could change, to compare before and after.
fn snapshot(s: &Scene) -> (TriMesh, TriMesh, Vec<Vec3>, Vec<Vec3>, Vec3) {
    let block_shape = s.world.colliders.get(s.block).unwrap().shape().as_trimesh().unwrap().vertices().to_vec();
    let ball_shape = s.world.colliders.get(s.ball).unwrap().shape().as_convex_polyhedron().unwrap().points().to_vec();
    let ball_at = s.world.bodies.get(s.ball_body).unwrap().translation();
    (
        s.dentables.mesh(s.block).unwrap().clone(),
        s.dentables.mesh(s.ball).unwrap().clone(),
        block_shape,
        ball_shape,
        ball_at,
    )
}

fn assert_unchanged(s: &Scene, before: &(TriMesh, TriMesh, Vec<Vec3>, Vec<Vec3>, Vec3)) {
    let now = snapshot(s);
    assert_eq!(now.0.positions(), before.0.positions(), "block mesh changed");
    assert_eq!(now.1.positions(), before.1.positions(), "ball mesh changed");
    assert_eq!(now.2, before.2, "block collider changed");
    assert_eq!(now.3, before.3, "ball collider changed");
    assert_eq!(now.4, before.4, "ball moved");
}

fn process(s: &mut Scene, states: &BodyStates, contacts: &[Contact]) -> Result<usize, AdapterError> {
    let Scene { world, dentables, .. } = s;
    dentables.process(contacts, states, &mut world.bodies, &mut world.colliders, &mut CpuBackend).map(|r| r.dents.len())
}

#[test]
fn the_good_contact_dents_both_bodies() {
    // The control: the contact the other tests spoil does dent (6 m/s head-on).
    let mut s = scene();
    let states = BodyStates::record(&s.world.bodies, &s.world.colliders);
    let before = snapshot(&s);
    let good = good_contact(&s);
    assert_eq!(process(&mut s, &states, &[good]).unwrap(), 2);
    assert_ne!(snapshot(&s).0.positions(), before.0.positions());
}

#[test]
fn nan_and_infinite_contacts_are_named_and_change_nothing() {
    let mut s = scene();
    let states = BodyStates::record(&s.world.bodies, &s.world.colliders);
    let before = snapshot(&s);
    let good = good_contact(&s);
    for bad in [
        Contact { point: Vec3::new(f32::NAN, 0.25, 0.0), ..good },
        Contact { normal: Vec3::new(0.0, f32::INFINITY, 0.0), ..good },
        Contact { impulse: f32::NAN, ..good },
    ] {
        // The good contact first: a bad one later in the list still changes nothing.
        let err = process(&mut s, &states, &[good, bad]).unwrap_err();
        assert!(matches!(err, AdapterError::NonFiniteContact { .. }), "{err}");
        assert_unchanged(&s, &before);
    }
}

#[test]
fn a_zero_normal_is_named_and_changes_nothing() {
    let mut s = scene();
    let states = BodyStates::record(&s.world.bodies, &s.world.colliders);
    let before = snapshot(&s);
    let bad = Contact { normal: Vec3::ZERO, ..good_contact(&s) };
    let good = good_contact(&s);
    let err = process(&mut s, &states, &[good, bad]).unwrap_err();
    assert!(matches!(err, AdapterError::ZeroNormal { .. }), "{err}");
    assert_unchanged(&s, &before);
}

#[test]
fn an_unknown_collider_is_named_and_changes_nothing() {
    let mut s = scene();
    let states = BodyStates::record(&s.world.bodies, &s.world.colliders);
    let before = snapshot(&s);
    let stranger = ColliderHandle::from_raw_parts(999, 0);
    let bad = Contact { collider2: stranger, ..good_contact(&s) };
    let good = good_contact(&s);
    let err = process(&mut s, &states, &[good, bad]).unwrap_err();
    assert!(matches!(err, AdapterError::UnknownCollider(h) if h == stranger), "{err}");
    assert_unchanged(&s, &before);
}

#[test]
fn a_body_removed_after_the_step_is_skipped_and_reported_and_the_other_dents_are_made() {
    let mut s = scene();
    // A second ball, recorded with the others, then removed before the contacts are processed
    // (a game that despawns a ball as it lands).
    let body = s.world.bodies.insert(RigidBodyBuilder::dynamic().translation(Vec3::new(0.5, 0.4, 0.0)));
    let gone_mesh = mesh::icosphere(0.1, 1).unwrap();
    let gone = s.world.colliders.insert_with_parent(convex_collider(&gone_mesh).unwrap(), body, &mut s.world.bodies);
    s.dentables.insert_projectile(&s.world.colliders, gone, gone_mesh).unwrap();
    let states = BodyStates::record(&s.world.bodies, &s.world.colliders);
    let before = snapshot(&s);
    assert!(s.world.remove_body(body));
    let bad = Contact { collider2: gone, point: Vec3::new(0.5, 0.25, 0.0), ..good_contact(&s) };
    let good = good_contact(&s);
    let Scene { world, dentables, .. } = &mut s;
    let report =
        dentables.process(&[good, bad], &states, &mut world.bodies, &mut world.colliders, &mut CpuBackend).unwrap();
    assert_eq!(report.dents.len(), 2, "the good contact still dents the block and the ball");
    assert_eq!(report.skipped, vec![bad]);
    // The removed collider is forgotten: no leak.
    assert_eq!(report.forgotten, vec![gone]);
    assert!(s.dentables.surface(gone).is_none());
    assert_ne!(snapshot(&s).0.positions(), before.0.positions());

    let mut s = scene();
    let states = BodyStates::record(&s.world.bodies, &s.world.colliders);
    let before = snapshot(&s);
    // A body added after the record has no state before the step: named too.
    let late = s.world.bodies.insert(RigidBodyBuilder::dynamic());
    let late_collider = s.world.colliders.insert_with_parent(
        convex_collider(&mesh::icosphere(0.1, 1).unwrap()).unwrap(),
        late,
        &mut s.world.bodies,
    );
    let bad = Contact { collider2: late_collider, ..good_contact(&s) };
    let err = process(&mut s, &states, &[bad]).unwrap_err();
    assert!(matches!(err, AdapterError::NotRecorded(h) if h == late), "{err}");
    assert_unchanged(&s, &before);
}

#[test]
fn the_adapter_checks_every_contact_before_it_splits_bends_or_dents() {
    use dentbend_rapier::demo::plank::Plank;
    // The plank scene just before the ball lands: a good contact on a piece and a contact
    // naming a collider that never existed; the adapter names it and changes nothing.
    let mut p = Plank::new(64).unwrap();
    p.run(2).unwrap();
    let states = BodyStates::record(&p.world.bodies, &p.world.colliders);
    let piece = p.plank().pieces()[0];
    let ball = p.world.bodies.get(p.ball).unwrap().colliders()[0];
    let hit = Contact {
        collider1: piece.collider,
        collider2: ball,
        point: Vec3::new(0.3, 0.102, 0.0),
        normal: Vec3::Y,
        impulse: 100.0,
        started: true,
    };
    // Not on the plank: only the up-front check stops the split the first contact asks for.
    let stranger = ColliderHandle::from_raw_parts(999, 0);
    let bad = Contact { collider1: ball, collider2: stranger, ..hit };
    let pieces_before = p.plank().pieces().to_vec();
    let err = p.adapter.after_step(&mut p.world, &states, vec![hit, bad], 0.0).unwrap_err();
    assert!(matches!(err, AdapterError::UnknownCollider(h) if h == stranger), "{err}");
    assert_eq!(p.plank().pieces(), &pieces_before[..]);
    assert!(p.plank().joints().is_empty());
    assert_eq!(p.plank().rest_mesh().positions(), mesh::plank(4.0, 0.3, 0.1, 64).unwrap().positions());
}

#[test]
fn unknown_ids_are_named() {
    let mut s = scene();
    let states = BodyStates::record(&s.world.bodies, &s.world.colliders);
    let stranger = RigidBodyHandle::from_raw_parts(999, 0);
    let err = states.body(stranger, &s.world.bodies).unwrap_err();
    assert!(matches!(err, AdapterError::UnknownBody(h) if h == stranger), "{err}");
    // Registering an unknown collider changes nothing.
    let collider = ColliderHandle::from_raw_parts(999, 0);
    let err = s.dentables.insert(
        &s.world.colliders,
        &s.world.bodies,
        collider,
        mesh::icosphere(0.1, 1).unwrap(),
        target_dent(),
    );
    assert!(matches!(err, Err(AdapterError::UnknownCollider(h)) if h == collider));
    assert!(!s.dentables.is_dentable(collider));
    // A mesh that does not match its tri-mesh collider is refused.
    let err = s.dentables.insert(
        &s.world.colliders,
        &s.world.bodies,
        s.block,
        mesh::icosphere(0.1, 1).unwrap(),
        target_dent(),
    );
    assert!(matches!(err, Err(AdapterError::Refit { .. })), "{err:?}");
    let block = mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [16, 4, 16]).unwrap();
    assert_eq!(s.dentables.mesh(s.block).unwrap().positions(), block.positions());
}

#[test]
fn a_fixed_dentable_removed_after_the_step_is_skipped_and_forgotten() {
    // The block is on a fixed body, so the states do not record it; the adapter knows it.
    let mut s = scene();
    let states = BodyStates::record(&s.world.bodies, &s.world.colliders);
    let good = good_contact(&s);
    let PhysicsWorld { colliders, islands, bodies, soft_bodies, .. } = &mut s.world;
    assert!(colliders.remove(s.block, islands, bodies, soft_bodies, false).is_some());
    let Scene { world, dentables, block, .. } = &mut s;
    let report = dentables.process(&[good], &states, &mut world.bodies, &mut world.colliders, &mut CpuBackend).unwrap();
    assert!(report.dents.is_empty());
    assert_eq!(report.skipped, vec![good]);
    assert_eq!(report.forgotten, vec![*block]);
    assert!(!dentables.is_dentable(*block));
}
