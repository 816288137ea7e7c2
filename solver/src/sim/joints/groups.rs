//! Jointed groups: dynamic bodies connected through joints (static and kinematic bodies do not
//! connect groups). A group wakes as one, so a joint never holds an awake body to an asleep
//! (immovable) partner; it falls asleep as one because joints link the sleep islands
//! (`sleep::settle`).

use super::Joint;
use crate::sim::union_find::UnionFind;
use crate::sim::{BodyKind, RigidBody};

/// The key of an unordered body pair (smaller index first).
pub(crate) fn pair(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

/// Group representative of every body (itself when it has no dynamic joint partner).
fn groups(joints: &[Joint], bodies: &[RigidBody]) -> Vec<usize> {
    let mut sets = UnionFind::new(bodies.len());
    let dynamic = |i: usize| bodies.get(i).is_some_and(|b| b.kind == BodyKind::Dynamic && b.is_simulated());
    for joint in joints {
        if dynamic(joint.a) && dynamic(joint.b) {
            sets.join(joint.a, joint.b);
        }
    }
    (0..bodies.len()).map(|i| sets.root(i)).collect()
}

/// Wakes every member of a jointed group that has an awake member (a group falls asleep as one
/// island, see `sleep::settle`, but a body can be woken alone by a touch).
pub(crate) fn sync_sleep(joints: &[Joint], bodies: &mut [RigidBody]) {
    if joints.is_empty() {
        return;
    }
    let group = groups(joints, bodies);
    let mut awake = vec![false; bodies.len()];
    for (i, body) in bodies.iter().enumerate() {
        if body.kind == BodyKind::Dynamic && !body.activity.asleep {
            awake[group[i]] = true;
        }
    }
    for (i, body) in bodies.iter_mut().enumerate() {
        if body.kind == BodyKind::Dynamic && body.is_simulated() && body.activity.asleep && awake[group[i]] {
            body.activity.wake();
        }
    }
}
