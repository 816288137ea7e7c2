//! bevy_rapier3d as the contact source and collider owner: impacts from Rapier's solver become
//! [`DentContact`](crate::DentContact)s, and dented meshes refit the entities' `Collider`s.
//!
//! Dentable colliders get `ActiveEvents::CONTACT_FORCE_EVENTS` with a 0 N threshold, so Rapier
//! reports each impact on the step a pair first pushes (dentbend-rapier's
//! [`ImpactCollector`](dentbend_rapier::ImpactCollector) turns the solver's contacts into one
//! point and normal); body states are recorded just before Rapier's step.

mod alias;
mod contacts;
mod pieces;
mod refit;

use bevy::ecs::schedule::graph::Direction;
use bevy::ecs::schedule::{InternedScheduleLabel, NodeId, ScheduleLabel};
use bevy::prelude::*;
use bevy_rapier3d::plugin::PhysicsSet;

use crate::DentSystems;

/// Adds the bevy_rapier3d contact source and collider refits (added by
/// [`DentbendPlugin`](crate::DentbendPlugin) when the `rapier` feature is on): states recorded
/// before each step and impacts read after it in `physics` (the schedule bevy_rapier3d steps
/// in), dents decided in `PostUpdate` after them.
pub(crate) fn build(app: &mut App, physics: InternedScheduleLabel) {
    app.init_resource::<contacts::RapierImpacts>()
        .add_systems(
            physics,
            (contacts::install_collector, contacts::enable_force_events, contacts::record_states)
                .chain()
                .after(PhysicsSet::SyncBackend)
                .before(PhysicsSet::StepSimulation),
        )
        .add_systems(physics, contacts::send_contacts.after(PhysicsSet::StepSimulation).before(PhysicsSet::Writeback))
        .add_systems(
            PostUpdate,
            alias::find_colliders.after(crate::register::register_dentables).in_set(DentSystems::Register),
        )
        .add_systems(
            PostUpdate,
            (refit::refit_colliders, pieces::give_bodies, pieces::give_way).in_set(DentSystems::Apply),
        );
    if physics == PostUpdate.intern() {
        app.configure_sets(PostUpdate, DentSystems::Decide.after(PhysicsSet::Writeback));
    }
}

/// The schedule whose `PhysicsSet::StepSimulation` holds a system (bevy_rapier3d's step), if
/// one does.
pub(crate) fn physics_schedule(app: &App) -> Option<InternedScheduleLabel> {
    let schedules = app.world().get_resource::<Schedules>()?;
    let step = PhysicsSet::StepSimulation.intern();
    schedules
        .iter()
        .find(|(_, schedule)| {
            let graph = schedule.graph();
            graph.system_sets.get_key(step).is_some_and(|set| {
                graph
                    .hierarchy()
                    .graph()
                    .neighbors_directed(NodeId::Set(set), Direction::Outgoing)
                    .any(|child| matches!(child, NodeId::System(_)))
            })
        })
        .map(|(_, schedule)| schedule.label())
}
