//! Small edits of a [`World`]'s joints that bending needs (paper §4): when a bone is split, the
//! joints of the old bone's far end move to the new second half (§4.2); the sub-bodies of one
//! bending body do not collide with each other.
//!
//! A child module of `world` (declared there with `#[path]`) so that it can keep the world's
//! set of joined pairs in step with its joints.

use super::{World, invalid, joints};
use crate::sim::cluster::Role;
use crate::sim::{Joint, RigidBody, SimError};

/// What an edit of a few bodies may change, recorded before it so that a failed edit is put
/// back without copying the world (see [`World::record_edit`]).
pub(crate) struct EditUndo {
    body_count: usize,
    joint_count: usize,
    bodies: Vec<(usize, RigidBody)>,
    joints: Vec<(usize, Joint)>,
    /// Pairs of the recorded bodies that collided with each other before the edit.
    colliding: Vec<(usize, usize)>,
}

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
        if !still_joined && self.joined.remove(&joints::pair(other, from)) {
            self.filters_lifted += 1;
        }
    }

    /// Records bodies `touched` (those an edit may rebuild, move joint ends from or stop from
    /// colliding with each other), every joint on them, and which of their pairs collide, for
    /// [`undo_edit`](Self::undo_edit). Whatever else the edit does must be additions of bodies
    /// and joints and of ignored pairs with the added bodies.
    pub(crate) fn record_edit(&self, touched: &[usize]) -> EditUndo {
        let on_touched = |j: &Joint| touched.contains(&j.a) || touched.contains(&j.b);
        let joints = self.joints.iter().enumerate().filter(|(_, j)| on_touched(j)).map(|(k, j)| (k, j.clone()));
        let pairs =
            touched.iter().enumerate().flat_map(|(k, &a)| touched[k + 1..].iter().map(move |&b| joints::pair(a, b)));
        EditUndo {
            body_count: self.bodies.len(),
            joint_count: self.joints.len(),
            bodies: touched.iter().map(|&i| (i, self.bodies[i].clone())).collect(),
            joints: joints.collect(),
            colliding: pairs.filter(|pair| !self.ignored.contains(pair)).collect(),
        }
    }

    /// Puts back what `undo` recorded and drops the bodies and joints added since.
    pub(crate) fn undo_edit(&mut self, undo: EditUndo) {
        for (i, body) in undo.bodies {
            self.bodies[i] = body;
        }
        for (k, joint) in undo.joints {
            self.joints[k] = joint;
        }
        self.truncate(undo.body_count, undo.joint_count);
        for pair in undo.colliding {
            self.ignored.remove(&pair);
        }
        self.filters_lifted += 1;
    }

    /// Drops the bodies and joints added after the world had `bodies` bodies and `joints`
    /// joints (undoes a failed multi-part addition without copying the world first). Only for
    /// additions: nothing added may have been condensed.
    pub(crate) fn truncate(&mut self, bodies: usize, joints: usize) {
        self.bodies.truncate(bodies);
        self.joints.truncate(joints);
        self.joined = self.joints.iter().map(|j| joints::pair(j.a, j.b)).collect();
        self.ignored.retain(|&(_, b)| b < bodies);
        self.filters_lifted += 1;
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
    use crate::sim::{BodyDesc, ColliderKind, JointKind};
    use dentbend::mesh;

    /// Everything an edit may change, as comparable values: body names and poses, joint ends and
    /// anchors, joined and ignored pairs.
    fn picture(world: &World) -> impl PartialEq + std::fmt::Debug + use<> {
        let bodies: Vec<_> = world.bodies.iter().map(|b| (b.name.clone(), b.position, b.orientation)).collect();
        let joints: Vec<_> = world.joints.iter().map(|j| (j.a, j.b, j.anchors(&world.bodies))).collect();
        let mut joined: Vec<_> = world.joined.iter().copied().collect();
        let mut ignored: Vec<_> = world.ignored.iter().copied().collect();
        joined.sort_unstable();
        ignored.sort_unstable();
        (bodies, joints, joined, ignored)
    }

    /// A split's edits (a body rebuilt elsewhere, a body added, a joint end moved to it, a
    /// joint added, collision filters set) are all put back by undoing the record taken before.
    #[test]
    fn an_undone_edit_leaves_the_world_as_it_was() {
        let mut world = World::new(WorldSettings::default()).unwrap();
        let cube = mesh::subdivided_box(Vec3::splat(0.2), [1, 1, 1]).unwrap();
        let desc = |k: usize, x: f32| BodyDesc::new(format!("box{k}"), cube.clone()).at(Vec3::new(x, 0.0, 0.0));
        for k in 0..3 {
            world.add(desc(k, k as f32).collider(ColliderKind::Cuboid)).unwrap();
        }
        world.add_joint(0, 1, Vec3::new(0.5, 0.0, 0.0), JointKind::Ball).unwrap();
        world.add_joint(1, 2, Vec3::new(1.5, 0.0, 0.0), JointKind::Rigid).unwrap();
        world.ignore_collisions(0, 2).unwrap();
        let before = picture(&world);
        let undo = world.record_edit(&[0, 1]);
        world.rebuild_body(1, desc(1, 1.2)).unwrap();
        let added = world.add(desc(3, 3.0)).unwrap();
        world.inherit_ignored_collisions(0, added);
        world.retarget_joint(1, 1, added).unwrap();
        world.add_joint(1, added, Vec3::new(2.0, 0.0, 0.0), JointKind::Ball).unwrap();
        world.ignore_collisions(0, 1).unwrap();
        assert_ne!(picture(&world), before, "the edits changed nothing");
        world.undo_edit(undo);
        assert_eq!(picture(&world), before);
    }

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
        assert_eq!(world.ignored.iter().copied().collect::<HashSet<_>>(), expected);
        // Body 1 now ignores 0 and 3 (the latter inherited): both pass on to 4, nothing else.
        world.inherit_ignored_collisions(1, 4);
        let expected: HashSet<(usize, usize)> = [(0, 1), (0, 2), (0, 3), (2, 4), (1, 3), (2, 3), (0, 4), (3, 4)].into();
        assert_eq!(world.ignored.iter().copied().collect::<HashSet<_>>(), expected);
    }
}
