//! Dynamic articulation of one bending body (paper §4.2, Algorithm 2 steps 8–11): split the bone
//! a hit lands on where the hit projects onto it, recompute the weights of that bone only and
//! the sub-bodies, and rebuild the world's bodies and joints to match.

use glam::Vec3;

use super::ArticulatedBody;
use super::articulated::{RigidMotion, ignore_own_collisions};
use super::bendable::bend_error;
use crate::sim::{SimError, World};

/// What a split did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SplitOutcome {
    /// The bone split (it keeps its index as the first half).
    pub bone: usize,
    /// The new bone (the second half).
    pub new_bone: usize,
    /// World index of the new bone's body.
    pub new_body: usize,
    /// Index of the joint added, in [`World::joints`].
    pub joint: usize,
    /// The split point in the rest (model) frame, m.
    pub rest_point: Vec3,
    /// The split point in the world when the joint was made, m.
    pub world_point: Vec3,
}

impl ArticulatedBody {
    /// Splits the bone nearest to the world point `point` (a hit on world body `index`, one of
    /// this body's) at the point's projection onto it, in the rest pose: the point is mapped to
    /// the rest frame by the inverse of the hit sub-body's bone transform.
    ///
    /// Returns `Ok(None)` and changes nothing when the body has no dynamic articulation, has made
    /// its most joints, `index` is not one of its bodies, either half would be shorter than the
    /// minimum bone length (or within 5 % of an
    /// end), or a half would own no triangle or no inside cell at this resolution.
    ///
    /// Otherwise: the first half keeps the old bone's index and body (rebuilt in place, as is
    /// every other bone whose sub-body changed), the second half gets a new world body moving
    /// with the old body's rigid motion (v + ω × r at its centre of mass), every joint of the old
    /// body anchored nearer the second half (the joints to the bone's children, joints to other
    /// bodies at its far end) moves to it, and a joint of the dynamic kind joins the halves at
    /// the split point.
    ///
    /// # Errors
    /// A world edit or weight computation failed (a bug); the body and the world are unchanged.
    pub fn split_at(&mut self, world: &mut World, index: usize, point: Vec3) -> Result<Option<SplitOutcome>, SimError> {
        let Some(dynamic) = self.dynamic else { return Ok(None) };
        let Some(hit_bone) = self.bone_of(index) else { return Ok(None) };
        if self.added_joints >= dynamic.max_joints || !point.is_finite() {
            return Ok(None);
        }
        let transforms = self.bone_transforms(world)?;
        let rest_point = transforms[hit_bone].inverse().transform_point3(point);
        let Some((bone, _, _)) = self.rig.skeleton().nearest_bone(rest_point) else { return Ok(None) };
        let fail = |e| bend_error(&self.name, e);
        let Some(split) = self.rig.split(bone, rest_point, dynamic.min_bone_length).map_err(fail)? else {
            return Ok(None);
        };
        let (second, split_point, changed) = (split.new_bone, split.joint_point, split.changed.clone());
        let mut rig = self.rig.clone();
        rig.apply_split(split).map_err(fail)?;
        // Stage: the new rig in self and the edits on the world, both put back on error (the
        // edits rebuild this body's sub-bodies and add one: recording those is enough).
        let old_rig = std::mem::replace(&mut self.rig, rig);
        let undo = world.record_edit(&self.bodies);
        match self.apply_split(world, &changed, bone, second, transforms[bone].transform_point3(split_point)) {
            Ok((new_body, joint)) => {
                self.bodies.push(new_body);
                self.rest_revision = super::articulated::next_rest_revision();
                self.added_joints += 1;
                let world_point = transforms[bone].transform_point3(split_point);
                Ok(Some(SplitOutcome { bone, new_bone: second, new_body, joint, rest_point: split_point, world_point }))
            }
            Err(e) => {
                world.undo_edit(undo);
                self.rig = old_rig;
                Err(e)
            }
        }
    }

    /// The world edits of a split (self already holds the new skeleton, weights and sub-bodies):
    /// returns the new body's index and the new joint's.
    fn apply_split(
        &self,
        world: &mut World,
        changed: &[usize],
        bone: usize,
        second: usize,
        anchor: Vec3,
    ) -> Result<(usize, usize), SimError> {
        let dynamic = self.dynamic.ok_or_else(|| SimError::BadShape {
            body: self.name.clone(),
            reason: "bending: split without dynamic articulation".into(),
        })?;
        let state = |world: &World, k: usize| {
            let b = &world.bodies()[self.bodies[k]];
            let origin = Vec3::from(b.model_transform().translation);
            let motion = RigidMotion { velocity: b.linear_velocity, angular: b.angular_velocity, centre: b.position };
            ((origin, b.orientation), motion)
        };
        let (old_pose, old_motion) = state(world, bone);
        for &k in changed {
            let (pose, motion) = state(world, k);
            let desc = self.sub_body_desc(k, pose, motion)?;
            world.rebuild_body(self.bodies[k], desc)?;
        }
        let new_body = world.add(self.sub_body_desc(second, old_pose, old_motion)?)?;
        let old_body = self.bodies[bone];
        world.inherit_ignored_collisions(old_body, new_body);
        // Every joint on the old bone's far half moves to the new body: the skeleton's joints
        // to the split bone's children, and joints to other bodies (a strut's end caps).
        let to_rest = world.bodies()[old_body].model_transform().inverse();
        let (first_bone, second_bone) = (&self.rig.skeleton().bones()[bone], &self.rig.skeleton().bones()[second]);
        for joint in 0..world.joints().len() {
            let j = &world.joints()[joint];
            let Some((on_a, on_b)) = j.anchors(world.bodies()) else { continue };
            let anchor_here = match (j.a(), j.b()) {
                (a, _) if a == old_body => on_a,
                (_, b) if b == old_body => on_b,
                _ => continue,
            };
            let rest = to_rest.transform_point3(anchor_here);
            if second_bone.distance(rest) < first_bone.distance(rest) {
                world.retarget_joint(joint, old_body, new_body)?;
            }
        }
        let joint = world.add_joint(old_body, new_body, anchor, dynamic.joint)?;
        let own: Vec<usize> = self.bodies.iter().copied().chain([new_body]).collect();
        ignore_own_collisions(world, &own)?;
        Ok((new_body, joint))
    }
}
