//! The bendable bodies' joint rules applied to bevy_rapier3d's bodies just before each step
//! (once Bevy's changes are synced, so the impulses go straight into it), as dentbend-rapier's
//! `Bendable::after_step` applies them.

use bevy::prelude::*;
use bevy_rapier3d::plugin::context::{RapierContextSimulation, RapierRigidBodySet};
use dentbend_rapier::apply_joint;

use crate::bend::Bends;

/// Applies every bendable body's joint rules.
pub(crate) fn apply_joint_rules(
    mut bends: ResMut<Bends>,
    mut contexts: Query<(&RapierContextSimulation, &mut RapierRigidBodySet)>,
) {
    let Some((simulation, mut set)) = contexts.iter_mut().next() else { return };
    let dt = simulation.integration_parameters.dt;
    for rig in bends.rigs.values_mut() {
        for joint in &mut rig.joints {
            let handles =
                [rig.pieces[joint.parent], rig.pieces[joint.child]].map(|e| set.entity2body().get(&e).copied());
            let [Some(h1), Some(h2)] = handles else { continue };
            let (Some(b1), Some(b2)) = set.bodies.get_pair_mut(h1, h2) else { continue };
            apply_joint(&mut joint.rule, b1, b2, dt);
        }
    }
}
