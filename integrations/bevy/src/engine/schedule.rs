//! Finding the schedule a physics engine steps in, from the system set its step runs in.

use bevy::ecs::intern::Interned;
use bevy::ecs::schedule::graph::Direction;
use bevy::ecs::schedule::{InternedScheduleLabel, NodeId, SystemSet};
use bevy::prelude::*;

/// The schedule whose system set `step` holds a system (the engine's step), if one does.
pub(crate) fn schedule_stepping(app: &App, step: Interned<dyn SystemSet>) -> Option<InternedScheduleLabel> {
    let schedules = app.world().get_resource::<Schedules>()?;
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
