//! Dynamic articulation (paper §4.2): a hit whose approach speed reaches the body's split
//! speed splits the bone it lands on at the contact's projection, replacing the hit piece by
//! two Rapier bodies joined by a new joint.

use glam::Vec3;
use rapier3d::prelude::{RigidBodyHandle, SharedShape};

use crate::bendable::{BendJoint, BendReport, hulls, part_hull, rig_error};
use crate::{AdapterError, Bendable, BodyStates, Contact, PhysicsWorld};

impl Bendable {
    /// Splits bones where the fast hits of `contacts` (normal approach speed ≥ `speed` m/s)
    /// landed: every split decided (and every contact checked) before any is made, one split
    /// per piece per step.
    ///
    /// # Errors
    /// A contact with NaN/∞ or a zero normal, a removed body; nothing changed then.
    pub(crate) fn split_where_hit(
        &mut self,
        world: &mut PhysicsWorld,
        states: &BodyStates,
        contacts: &[Contact],
        speed: f32,
        report: &mut BendReport,
    ) -> Result<(), AdapterError> {
        for c in contacts {
            c.validate()?;
        }
        let mut splits: Vec<Split> = Vec::new();
        for c in contacts.iter().filter(|c| c.started) {
            if let Some(split) = self.split_of(c, speed, states, world)?
                && !splits.iter().any(|s| s.piece == split.piece)
            {
                splits.push(split);
            }
        }
        for split in splits {
            self.split(world, states, split, report)?;
        }
        Ok(())
    }

    /// The split a contact asks for: (piece index, rest point, projectile body).
    fn split_of(
        &self,
        c: &Contact,
        speed: f32,
        states: &BodyStates,
        world: &PhysicsWorld,
    ) -> Result<Option<Split>, AdapterError> {
        let (piece, other, normal) = match self.pieces.iter().position(|p| p.collider == c.collider1) {
            Some(i) => (i, c.collider2, -c.normal),
            None => match self.pieces.iter().position(|p| p.collider == c.collider2) {
                Some(i) => (i, c.collider1, c.normal),
                None => return Ok(None),
            },
        };
        let own = states.body(self.pieces[piece].body, &world.bodies)?;
        let projectile = states.collider(other, &world.bodies, &world.colliders)?.parent();
        let hitter = match projectile {
            Some(b) => Some((b, states.body(b, &world.bodies)?)),
            None => None,
        };
        let their = hitter.map(|(_, s)| s.velocity_at(c.point)).unwrap_or(Vec3::ZERO);
        let approach = (their - own.velocity_at(c.point)).dot(normal.normalize());
        if approach < speed {
            return Ok(None);
        }
        let Some(pose) = states.body_pose(self.pieces[piece].body) else { return Ok(None) };
        let rest_point = pose.inverse_transform_point(c.point);
        let joints = self.joints.iter().map(|j| j.rest_point);
        if self.rig.split_point(self.pieces[piece].bone, rest_point, self.settings.min_joint_spacing, joints).is_none()
        {
            return Ok(None);
        }
        Ok(Some(Split { piece, rest_point, projectile: hitter.map(|(b, _)| b) }))
    }

    /// Splits the bone of `split.piece` at `split.rest_point`; a point too near the bone's ends
    /// is no split.
    fn split(
        &mut self,
        world: &mut PhysicsWorld,
        states: &BodyStates,
        split: Split,
        report: &mut BendReport,
    ) -> Result<(), AdapterError> {
        let old = self.pieces[split.piece];
        let Some(rig_split) = self.rig.split(old.bone, split.rest_point, 0.0).map_err(rig_error)? else {
            return Ok(());
        };
        let (first, second, at) = (rig_split.bone, rig_split.new_bone, rig_split.joint_point);
        let mut after = self.rig.clone();
        let recut: Vec<usize> = rig_split.changed.iter().copied().filter(|&k| k != first).collect();
        after.apply_split(rig_split).map_err(rig_error)?;
        let hulls = hulls(&after, &[first, second])?;
        // Other bones whose sub-body the split recut get hulls of their new parts.
        let recut_hulls: Vec<(usize, SharedShape)> =
            recut.iter().map(|&bone| Ok((bone, part_hull(&after, bone)?))).collect::<Result<_, AdapterError>>()?;
        let (Some(pose), state) = (states.body_pose(old.body), states.body(old.body, &world.bodies)?) else {
            return Ok(());
        };
        // Checked: commit.
        let attached: Vec<usize> = (0..self.joints.len())
            .filter(|&j| [self.joints[j].parent, self.joints[j].child].contains(&old.bone))
            .collect();
        world.remove_body(old.body);
        report.removed_colliders.push(old.collider);
        self.rig = after;
        for (bone, shape) in recut_hulls {
            if let Some(piece) = self.pieces.iter().find(|p| p.bone == bone)
                && let Some(collider) = world.colliders.get_mut(piece.collider)
            {
                collider.set_shape(shape);
            }
        }
        let mut made = Vec::new();
        for (bone, hull) in hulls {
            let velocity = (state.linear_velocity, state.angular_velocity);
            made.push(self.add_piece(world, bone, hull, pose, velocity, Some(state.center_of_mass)));
        }
        self.pieces[split.piece] = made[0];
        self.pieces.push(made[1]);
        for j in attached {
            let mut joint = self.joints[j];
            if joint.parent == old.bone && self.rig.skeleton().bones()[joint.child].parent == Some(second) {
                joint.parent = second;
            }
            let rebuilt = self.add_joint(world, joint.parent, joint.child, joint.rest_point, joint.dynamic)?;
            self.joints[j] = BendJoint { handle: rebuilt.handle, ..joint };
        }
        let joint = self.add_joint(world, first, second, at, true)?;
        self.joints.push(joint);
        report.joints_created += 1;
        if let Some(body) = split.projectile
            && let (Some(p), Ok(s)) = (states.body_pose(body), states.body(body, &world.bodies))
            && let Some(rb) = world.bodies.get_mut(body)
            && rb.is_dynamic()
        {
            rb.set_position(p, true);
            rb.set_linvel(s.linear_velocity, true);
            rb.set_angvel(s.angular_velocity, true);
        }
        Ok(())
    }
}

/// A split to make.
#[derive(Debug, Clone, Copy)]
struct Split {
    piece: usize,
    rest_point: Vec3,
    projectile: Option<RigidBodyHandle>,
}
