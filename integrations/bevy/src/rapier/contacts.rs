//! Rapier's impacts as [`DentContact`]s.

use std::sync::Arc;

use bevy::prelude::*;
use bevy_rapier3d::plugin::context::{RapierContextColliders, RapierContextSimulation, RapierRigidBodySet};
use bevy_rapier3d::prelude::{ActiveEvents, Collider, ContactForceEventThreshold};
use bevy_rapier3d::rapier::prelude::{
    ColliderHandle, ColliderSet, CollisionEvent, ContactPair, EventHandler, Real, RigidBodySet, SoftBodySet,
    SoftBodyTearEvent,
};
use dentbend_rapier::{BodyStates, ImpactCollector};

use crate::{DentBody, DentContact, DentWorld, Dentable};

/// The collector shared with Rapier's event handler, and the states recorded before the step.
#[derive(Resource, Default)]
pub(crate) struct RapierImpacts {
    collector: Arc<ImpactCollector>,
    states: BodyStates,
    /// Contexts whose event handler forwards to the collector.
    installed: Vec<Entity>,
}

/// Rapier's event handler: the collector, then the handler the application had installed.
struct Forward {
    collector: Arc<ImpactCollector>,
    theirs: Option<Box<dyn EventHandler + Send + Sync>>,
}

impl EventHandler for Forward {
    fn handle_collision_event(&self, b: &RigidBodySet, c: &ColliderSet, e: CollisionEvent, p: Option<&ContactPair>) {
        if let Some(theirs) = &self.theirs {
            theirs.handle_collision_event(b, c, e, p);
        }
    }

    fn handle_contact_force_event(&self, dt: Real, b: &RigidBodySet, c: &ColliderSet, p: &ContactPair, f: Real) {
        self.collector.handle_contact_force_event(dt, b, c, p, f);
        if let Some(theirs) = &self.theirs {
            theirs.handle_contact_force_event(dt, b, c, p, f);
        }
    }

    fn handle_soft_body_tear_event(&self, s: &SoftBodySet, e: &SoftBodyTearEvent) {
        if let Some(theirs) = &self.theirs {
            theirs.handle_soft_body_tear_event(s, e);
        }
    }
}

/// Makes every Rapier context report its contact force events to the collector (keeping the
/// application's own handler).
pub(crate) fn install_collector(
    mut impacts: ResMut<RapierImpacts>,
    mut contexts: Query<(Entity, &mut RapierContextSimulation)>,
) {
    for (entity, mut simulation) in &mut contexts {
        if impacts.installed.contains(&entity) {
            continue;
        }
        let theirs = simulation.remove_event_handler();
        simulation.set_event_handler(Forward { collector: impacts.collector.clone(), theirs });
        impacts.installed.push(entity);
    }
}

/// Dentable colliders whose force events are not on yet.
type NewDentableCollider = (With<Dentable>, With<Collider>, Without<ForceEventsOn>);

/// Colliders whose force events are not on yet.
type NewCollider = (With<Collider>, Without<ForceEventsOn>);

/// Dentable colliders report every push (0 N threshold), so the first step of each impact is
/// seen.
pub(crate) fn enable_force_events(
    mut commands: Commands,
    world: Res<DentWorld>,
    new: Query<(Entity, Option<&ActiveEvents>), NewDentableCollider>,
    others: Query<(Entity, Option<&ActiveEvents>), NewCollider>,
) {
    let aliased = world.aliases.keys().filter_map(|&e| others.get(e).ok());
    for (entity, events) in new.iter().chain(aliased) {
        let events = events.copied().unwrap_or_default() | ActiveEvents::CONTACT_FORCE_EVENTS;
        commands.entity(entity).insert((events, ContactForceEventThreshold(0.0), ForceEventsOn));
    }
}

/// Marks a dentable collider whose force events the plug-in turned on.
#[derive(Component)]
pub(crate) struct ForceEventsOn;

/// Records every body's state and collider's pose just before Rapier's step.
pub(crate) fn record_states(
    mut impacts: ResMut<RapierImpacts>,
    contexts: Query<(&RapierContextColliders, &RapierRigidBodySet)>,
) {
    if let Some((colliders, bodies)) = contexts.iter().next() {
        impacts.states = BodyStates::record(&bodies.bodies, &colliders.colliders);
    }
}

/// The step's impacts between bodies the plug-in knows, as [`DentContact`]s.
pub(crate) fn send_contacts(
    impacts: Res<RapierImpacts>,
    world: Res<DentWorld>,
    contexts: Query<(&RapierContextColliders, &RapierRigidBodySet)>,
    bones: Query<(), With<crate::BendPiece>>,
    mut out: MessageWriter<DentContact>,
) {
    let contacts = impacts.collector.take_contacts(&impacts.states);
    let Some((colliders, bodies)) = contexts.iter().next() else { return };
    for c in contacts {
        let side = |handle| body(handle, &impacts.states, colliders, bodies).map(|b| world.as_mesh(b));
        let (Some(a), Some(b)) = (side(c.collider1), side(c.collider2)) else { continue };
        // Only impacts that may dent (a side with a surface) or split a bendable body's bone.
        let may_dent = world.surface(a.entity).is_some() || world.surface(b.entity).is_some();
        if !may_dent && !bones.contains(a.entity) && !bones.contains(b.entity) {
            continue;
        }
        out.write(DentContact { a, b, point: c.point, normal: c.normal, started: c.started });
    }
}

/// Collider `handle` as a [`DentBody`]: its entity, pose and body state before the step
/// (restitution: the collider's); `None` when it was removed.
fn body(
    handle: ColliderHandle,
    states: &BodyStates,
    colliders: &RapierContextColliders,
    bodies: &RapierRigidBodySet,
) -> Option<DentBody> {
    let entity = colliders.collider_entity(handle)?;
    let (pose, state) = states.collider_state(handle, &bodies.bodies, &colliders.colliders).ok()?;
    Some(DentBody { entity, pose, state })
}
