//! bevy_rapier3d as the contact source and collider owner: impacts from Rapier's solver become
//! [`DentContact`](crate::DentContact)s, and dented meshes refit the entities' `Collider`s.
//!
//! Dentable colliders get `ActiveEvents::CONTACT_FORCE_EVENTS` with a 0 N threshold, so Rapier
//! reports each impact on the step a pair first pushes (dentbend-rapier's
//! [`ImpactCollector`](dentbend_rapier::ImpactCollector) turns the solver's contacts into one
//! point and normal); body states are recorded just before Rapier's step.

mod contacts;
mod refit;

use bevy::prelude::*;
use bevy_rapier3d::plugin::PhysicsSet;

use crate::DentSystems;

/// Adds the bevy_rapier3d contact source and collider refits (added by
/// [`DentbendPlugin`](crate::DentbendPlugin) when the `rapier` feature is on).
pub(crate) fn build(app: &mut App) {
    app.init_resource::<contacts::RapierImpacts>()
        .configure_sets(PostUpdate, DentSystems::Decide.after(PhysicsSet::Writeback))
        .add_systems(
            PostUpdate,
            (contacts::install_collector, contacts::enable_force_events, contacts::record_states)
                .chain()
                .after(PhysicsSet::SyncBackend)
                .before(PhysicsSet::StepSimulation),
        )
        .add_systems(PostUpdate, contacts::send_contacts.after(PhysicsSet::StepSimulation).before(DentSystems::Decide))
        .add_systems(PostUpdate, refit::refit_colliders.in_set(DentSystems::Apply));
}
