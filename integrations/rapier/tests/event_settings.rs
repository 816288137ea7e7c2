//! Dents do not depend on the game's event settings: the same balls on the same block make the
//! same dents whether the colliders ask for contact force events at 0 N, at 1,000 N or not at
//! all, because the adapter reads impacts from the narrow phase. `Adapter::step_with` runs the
//! game's own hooks and event handler: a hook that filters the pair out means no contact and no
//! dent, and the handler still gets its collision events.

use std::sync::atomic::{AtomicUsize, Ordering};

use dentbend::mesh::{self, content_hash};
use dentbend_rapier::demo::rain::target_dent;
use dentbend_rapier::rapier3d::prelude::{
    ActiveEvents, ActiveHooks, ColliderBuilder, ColliderSet, CollisionEvent, ContactPair, EventHandler,
    PairFilterContext, PhysicsHooks, Real, RigidBodyBuilder, RigidBodySet, SolverFlags,
};
use dentbend_rapier::{Adapter, PhysicsWorld, convex_collider, trimesh_collider};
use glam::Vec3;

/// Balls dropped on a block, the colliders built by `events`; returns the dents made and the
/// block's mesh hash at the end.
fn drop_balls(
    events: impl Fn(ColliderBuilder) -> ColliderBuilder,
    run: impl Fn(&mut Adapter, &mut PhysicsWorld) -> usize,
) -> (usize, u64) {
    let mut world = PhysicsWorld::new(Vec3::new(0.0, -9.81, 0.0), 1.0 / 60.0);
    let mut adapter = Adapter::new();
    let block_mesh = mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [16, 4, 16]).unwrap();
    let fixed = world.bodies.insert(RigidBodyBuilder::fixed());
    let block =
        world.colliders.insert_with_parent(events(trimesh_collider(&block_mesh).unwrap()), fixed, &mut world.bodies);
    adapter.dentables.insert(&world.colliders, &world.bodies, block, block_mesh, target_dent()).unwrap();
    let ball_mesh = mesh::icosphere(0.1, 2).unwrap();
    for (k, x) in [-0.6f32, -0.1, 0.4, 0.7].into_iter().enumerate() {
        let at = Vec3::new(x, 0.6 + 0.3 * k as f32, 0.2 * x);
        let body = world.bodies.insert(RigidBodyBuilder::dynamic().translation(at).linvel(Vec3::new(0.0, -6.0, 0.0)));
        let collider = events(convex_collider(&ball_mesh).unwrap().density(2000.0).restitution(0.4));
        let collider = world.colliders.insert_with_parent(collider, body, &mut world.bodies);
        adapter.dentables.insert_projectile(&world.colliders, collider, ball_mesh.clone()).unwrap();
    }
    let dents = run(&mut adapter, &mut world);
    (dents, content_hash(adapter.dentables.mesh(block).unwrap()))
}

fn plain_steps(adapter: &mut Adapter, world: &mut PhysicsWorld) -> usize {
    (0..60).map(|_| adapter.step(world).unwrap().dents.len()).sum()
}

#[test]
fn dents_are_the_same_whatever_the_force_event_threshold() {
    let at_zero = drop_balls(
        |b| b.active_events(ActiveEvents::CONTACT_FORCE_EVENTS).contact_force_event_threshold(0.0),
        plain_steps,
    );
    let at_1000 = drop_balls(
        |b| b.active_events(ActiveEvents::CONTACT_FORCE_EVENTS).contact_force_event_threshold(1000.0),
        plain_steps,
    );
    let none = drop_balls(|b| b, plain_steps);
    assert!(at_zero.0 >= 4, "{} dents", at_zero.0);
    assert_eq!(at_1000, at_zero, "a 1,000 N threshold");
    assert_eq!(none, at_zero, "no contact force events");
}

/// A game's event handler: counts collision events.
#[derive(Default)]
struct Counter(AtomicUsize);

impl EventHandler for Counter {
    fn handle_collision_event(&self, _: &RigidBodySet, _: &ColliderSet, _: CollisionEvent, _: Option<&ContactPair>) {
        self.0.fetch_add(1, Ordering::Relaxed);
    }
    fn handle_contact_force_event(&self, _: Real, _: &RigidBodySet, _: &ColliderSet, _: &ContactPair, _: Real) {}
    fn handle_soft_body_tear_event(
        &self,
        _: &dentbend_rapier::rapier3d::prelude::SoftBodySet,
        _: &dentbend_rapier::rapier3d::prelude::SoftBodyTearEvent,
    ) {
    }
}

/// A game's hook: no contact at all between the pairs it sees.
struct NoContacts;

impl PhysicsHooks for NoContacts {
    fn filter_contact_pair(&self, _: &PairFilterContext) -> Option<SolverFlags> {
        None
    }
}

#[test]
fn step_with_runs_the_games_hooks_and_handler() {
    let counter = Counter::default();
    let events = |b: ColliderBuilder| b.active_events(ActiveEvents::COLLISION_EVENTS);
    let (dents, _) = drop_balls(events, |adapter, world| {
        (0..60).map(|_| adapter.step_with(world, &(), &counter).unwrap().dents.len()).sum()
    });
    assert!(dents >= 4);
    assert!(counter.0.load(Ordering::Relaxed) >= 4, "the game's handler got the collision events");

    let filtered = |b: ColliderBuilder| b.active_hooks(ActiveHooks::FILTER_CONTACT_PAIRS);
    let (dents, _) = drop_balls(filtered, |adapter, world| {
        (0..60).map(|_| adapter.step_with(world, &NoContacts, &()).unwrap().dents.len()).sum()
    });
    assert_eq!(dents, 0, "the hook filtered every contact out");
}
