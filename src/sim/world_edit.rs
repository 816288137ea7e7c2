//! Small edits of a [`World`]'s joints that bending needs (paper §4): when a bone is split, the
//! joints of the old bone's far end move to the new second half (§4.2); the sub-bodies of one
//! bending body do not collide with each other.
//!
//! A child module of `world` (declared there with `#[path]`) so that it can keep the world's
//! set of joined pairs in step with its joints.

use super::{World, invalid, joints};
use crate::sim::SimError;
use crate::sim::cluster::Role;

impl World {
    /// Moves the end of joint `joint` that is on body `from` to body `to`, keeping the joint's
    /// anchor, sliding axis and target and rest relative orientations where they are in the world
    /// (so it holds what it held, now through `to`). Bodies `to` and the joint's other body stop
    /// colliding with each other; `from` and the other body collide again unless another joint
    /// still joins them.
    ///
    /// # Errors
    /// [`SimError::Invalid`] for a joint or body index out of range, `from == to`, a joint that
    /// does not end on `from`, a joint whose other end is `to`, or a body condensed into a
    /// cluster or standing in for one. The world is unchanged then.
    pub fn retarget_joint(&mut self, joint: usize, from: usize, to: usize) -> Result<(), SimError> {
        let Some(current) = self.joints.get(joint) else {
            return Err(invalid("joint index", joint, "is not a joint of the world"));
        };
        for (what, index) in [("retarget from body", from), ("retarget to body", to)] {
            if index >= self.bodies.len() {
                return Err(invalid(what, index, "is not a body of the world"));
            }
        }
        if from == to {
            return Err(invalid("retarget bodies", (from, to), "must be two different bodies"));
        }
        let other = match (current.a, current.b) {
            (a, b) if a == from => b,
            (a, b) if b == from => a,
            ends => return Err(invalid("retarget joint ends", ends, "do not include the body to move from")),
        };
        if other == to {
            return Err(invalid("retarget to body", to, "is already the joint's other body"));
        }
        for (what, index) in [("retarget from body", from), ("retarget to body", to)] {
            if !matches!(self.bodies[index].role, Role::Free) {
                return Err(invalid(what, index, "is condensed into a cluster or is a cluster's proxy"));
            }
        }
        self.move_joint_end(joint, from, to);
        Ok(())
    }

    /// [`retarget_joint`](Self::retarget_joint) without the checks (`joint` ends on `from`,
    /// its other end is not `to`).
    pub(crate) fn move_joint_end(&mut self, joint: usize, from: usize, to: usize) {
        let current = &self.joints[joint];
        let other = if current.a == from { current.b } else { current.a };
        let pose = |i: usize| (self.bodies[i].position, self.bodies[i].orientation);
        let (old, new) = (pose(from), pose(to));
        let moved = &mut self.joints[joint];
        moved.rebase(from, old, new);
        if moved.a == from {
            moved.a = to;
        } else {
            moved.b = to;
        }
        self.joined.insert(joints::pair(other, to));
        let still_joined = self.joints.iter().any(|j| joints::pair(j.a, j.b) == joints::pair(other, from));
        if !still_joined {
            self.joined.remove(&joints::pair(other, from));
        }
    }

    /// Drops the bodies and joints added after the world had `bodies` bodies and `joints`
    /// joints (undoes a failed multi-part addition without copying the world first). Only for
    /// additions: nothing added may have been condensed.
    pub(crate) fn truncate(&mut self, bodies: usize, joints: usize) {
        self.bodies.truncate(bodies);
        self.joints.truncate(joints);
        self.joined = self.joints.iter().map(|j| joints::pair(j.a, j.b)).collect();
        self.ignored.retain(|&(_, b)| b < bodies);
    }

    /// Stops bodies `a` and `b` from colliding with each other for good, joined or not: for parts
    /// of one body, such as a bending body's sub-bodies, whose colliders overlap where they meet.
    ///
    /// # Errors
    /// [`SimError::Invalid`] for an index that is not a body or the same body twice; the world
    /// is unchanged then.
    pub fn ignore_collisions(&mut self, a: usize, b: usize) -> Result<(), SimError> {
        for (what, index) in [("ignore collisions of body", a), ("ignore collisions with body", b)] {
            if index >= self.bodies.len() {
                return Err(invalid(what, index, "is not a body of the world"));
            }
        }
        if a == b {
            return Err(invalid("ignore collisions of bodies", (a, b), "must be two different bodies"));
        }
        self.ignored.insert(joints::pair(a, b));
        Ok(())
    }

    /// Makes body `to` ignore every body that `from` ignores (see
    /// [`ignore_collisions`](Self::ignore_collisions)): the new half of a split body keeps the
    /// filters set on the whole body.
    pub(crate) fn inherit_ignored_collisions(&mut self, from: usize, to: usize) {
        let others: Vec<usize> = self
            .ignored
            .iter()
            .filter_map(|&(a, b)| {
                if a == from {
                    Some(b)
                } else if b == from {
                    Some(a)
                } else {
                    None
                }
            })
            .filter(|&other| other != to)
            .collect();
        for other in others {
            self.ignored.insert(joints::pair(other, to));
        }
    }
}

#[cfg(test)]
mod tests {
    use std::collections::HashSet;

    use glam::Vec3;

    use super::super::{World, WorldSettings};
    use crate::mesh;
    use crate::sim::{BodyDesc, ColliderKind};

    /// Body 3 inherits what body 0 ignores (1, 2 and 3 itself): it gains 1 and 2, never
    /// itself; every pair set before stays and body 4 gains nothing.
    #[test]
    fn a_new_body_ignores_what_its_source_ignores() {
        let mut world = World::new(WorldSettings::default()).unwrap();
        let cube = mesh::subdivided_box(Vec3::splat(0.2), [1, 1, 1]).unwrap();
        for k in 0..5 {
            let desc = BodyDesc::new(format!("box{k}"), cube.clone()).at(Vec3::new(k as f32, 0.0, 0.0));
            world.add(desc.collider(ColliderKind::Cuboid)).unwrap();
        }
        for (a, b) in [(1, 0), (0, 2), (3, 0), (2, 4)] {
            world.ignore_collisions(a, b).unwrap();
        }
        world.inherit_ignored_collisions(0, 3);
        let expected: HashSet<(usize, usize)> = [(0, 1), (0, 2), (0, 3), (2, 4), (1, 3), (2, 3)].into();
        assert_eq!(world.ignored, expected);
        // Body 1 now ignores 0 and 3 (the latter inherited): both pass on to 4, nothing else.
        world.inherit_ignored_collisions(1, 4);
        let expected: HashSet<(usize, usize)> = [(0, 1), (0, 2), (0, 3), (2, 4), (1, 3), (2, 3), (0, 4), (3, 4)].into();
        assert_eq!(world.ignored, expected);
    }
}
