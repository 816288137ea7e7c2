//! Bendable bodies (paper §4): a mesh with a skeleton, one Rapier rigid body per bone (its
//! sub-body's convex hull as the collider), neighbouring bones joined by spherical impulse
//! joints whose angular part is a [`JointState`] (plastic or elastic) the adapter applies
//! after each step. Dynamic articulation splits a bone where a fast hit lands (see
//! [`Bendable::after_step`]). The parent mesh is skinned from the Rapier poses.
//!
//! Frames: every piece's body frame is the bendable's rest frame (the mesh's coordinates), so a
//! piece's Rapier pose *is* its bone's skinning transform (rest → world).

use dentbend::bend::{BendSettings, JointState, Rig, Skeleton};
use dentbend::mesh::TriMesh;
use glam::{Quat, Vec3};
use rapier3d::math::Pose;
use rapier3d::prelude::{
    ActiveEvents, ColliderBuilder, ColliderHandle, GenericJoint, ImpulseJointHandle, RigidBodyBuilder, RigidBodyHandle,
    SharedShape, SphericalJointBuilder,
};

use crate::contacts::Contact;
use crate::joints::apply_joint;
use crate::world::PhysicsWorld;
use crate::{AdapterError, BodyStates};

/// One bone's Rapier body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Piece {
    /// The bone.
    pub bone: usize,
    /// Its body (body frame = rest frame).
    pub body: RigidBodyHandle,
    /// Its collider (convex hull of the sub-body).
    pub collider: ColliderHandle,
}

/// A joint between two bones' bodies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BendJoint {
    /// Parent bone (Rapier body 1).
    pub parent: usize,
    /// Child bone (Rapier body 2).
    pub child: usize,
    /// Joint point, rest frame, m.
    pub rest_point: Vec3,
    /// The Rapier joint (spherical: anchors only).
    pub handle: ImpulseJointHandle,
    /// Its angular rule and state.
    pub rule: JointState,
    /// Whether dynamic articulation made it.
    pub dynamic: bool,
}

impl BendJoint {
    /// Net plastic bend since the joint was made, rad (0 for elastic joints).
    pub fn bend_angle(&self) -> f32 {
        self.rule.bend_angle()
    }
}

/// What [`Bendable::after_step`] did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BendReport {
    /// Joints dynamic articulation made this step.
    pub joints_created: usize,
    /// Plastic joints that yielded this step.
    pub plastic_bends: usize,
    /// Colliders removed by splits (their contacts this step are void: the hit is solved
    /// again next step against the new pieces).
    pub removed_colliders: Vec<ColliderHandle>,
}

/// A bendable body in a Rapier world.
#[derive(Debug)]
pub struct Bendable {
    pub(crate) rig: Rig,
    pub(crate) pieces: Vec<Piece>,
    pub(crate) joints: Vec<BendJoint>,
    pub(crate) settings: BendSettings,
    pub(crate) dent: Option<crate::bend_dent::BendDent>,
}

impl Bendable {
    /// Adds `mesh` (rest frame, m) posed at `pose` (rest frame → world) to `world` as one body
    /// per bone of `skeleton` (rest frame), joined at the skeleton's joints.
    ///
    /// # Errors
    /// Invalid settings, or a rig that cannot be built (weights, sub-bodies, hulls); `world`
    /// is unchanged then.
    pub fn new(
        world: &mut PhysicsWorld,
        mesh: TriMesh,
        pose: Pose,
        skeleton: Skeleton,
        settings: BendSettings,
    ) -> Result<Self, AdapterError> {
        check_settings(&settings)?;
        if !pose.is_finite() {
            return Err(AdapterError::InvalidParameter {
                name: "pose",
                value: format!("{pose:?}"),
                reason: "must be finite",
            });
        }
        let rig = Rig::new(mesh, skeleton, settings.weights, settings.density).map_err(rig_error)?;
        let hulls = hulls(&rig, &(0..rig.skeleton().len()).collect::<Vec<_>>())?;
        let mut this = Self { rig, pieces: Vec::new(), joints: Vec::new(), settings, dent: None };
        for (bone, hull) in hulls {
            let piece = this.add_piece(world, bone, hull, pose, (Vec3::ZERO, Vec3::ZERO), None);
            this.pieces.push(piece);
        }
        for j in this.rig.skeleton().joints() {
            let joint = this.add_joint(world, j.parent, j.child, j.point, false)?;
            this.joints.push(joint);
        }
        Ok(this)
    }

    /// The rest mesh (rest frame, m).
    pub fn rest_mesh(&self) -> &TriMesh {
        self.rig.rest()
    }

    /// The skeleton (rest frame).
    pub fn skeleton(&self) -> &Skeleton {
        self.rig.skeleton()
    }

    /// The rig: rest mesh, skeleton, weights and sub-bodies.
    pub fn rig(&self) -> &Rig {
        &self.rig
    }

    /// The pieces, one per bone, in bone order (`pieces()[b].bone == b`).
    pub fn pieces(&self) -> &[Piece] {
        &self.pieces
    }

    /// The joints.
    pub fn joints(&self) -> &[BendJoint] {
        &self.joints
    }

    /// Whether collider `handle` is one of this body's pieces.
    pub fn owns(&self, handle: ColliderHandle) -> bool {
        self.pieces.iter().any(|p| p.collider == handle)
    }

    /// After Rapier's step: splits bones where fast hits in `contacts` landed (dynamic
    /// articulation), then applies every joint's plastic or elastic rule.
    ///
    /// A split replaces the hit piece by two bodies at the piece's pose and velocity from
    /// before the step (`states`), joined at the hit's projection on the bone, and puts the body
    /// that hit back where and how it was before the step: the impact is solved again in the
    /// next step, against the articulated body (the step's time is lost for those bodies only).
    ///
    /// # Errors
    /// A contact with NaN/∞ or a zero normal, a removed body or joint: nothing changed then.
    pub fn after_step(
        &mut self,
        world: &mut PhysicsWorld,
        states: &BodyStates,
        contacts: &[Contact],
    ) -> Result<BendReport, AdapterError> {
        for p in &self.pieces {
            world.bodies.get(p.body).ok_or(AdapterError::UnknownBody(p.body))?;
        }
        for j in &self.joints {
            world.impulse_joints.get(j.handle).ok_or(AdapterError::UnknownJoint(j.handle))?;
        }
        let mut report = BendReport::default();
        if let Some(speed) = self.settings.split_speed {
            self.split_where_hit(world, states, contacts, speed, &mut report)?;
        }
        let dt = world.params.dt;
        for j in &mut self.joints {
            let (b1, b2) = (self.pieces[j.parent].body, self.pieces[j.child].body);
            let (Some(rb1), Some(rb2)) = world.bodies.get_pair_mut(b1, b2) else { continue };
            report.plastic_bends += usize::from(apply_joint(&mut j.rule, rb1, rb2, dt).yielded);
        }
        Ok(report)
    }

    /// Adds bone `bone`'s body with collider `hull` at `pose`, moving with `velocity` (linear
    /// m/s of the point `com`, angular rad/s; `com` None: the body's own centre of mass).
    pub(crate) fn add_piece(
        &self,
        world: &mut PhysicsWorld,
        bone: usize,
        hull: ColliderBuilder,
        pose: Pose,
        velocity: (Vec3, Vec3),
        com: Option<Vec3>,
    ) -> Piece {
        let body = world.bodies.insert(RigidBodyBuilder::dynamic().pose(pose).build());
        let collider = hull
            .density(self.settings.density)
            .friction(self.settings.friction)
            .active_events(ActiveEvents::CONTACT_FORCE_EVENTS)
            .contact_force_event_threshold(0.0);
        let collider = world.colliders.insert_with_parent(collider, body, &mut world.bodies);
        if let Some(rb) = world.bodies.get_mut(body) {
            let (v, w) = velocity;
            let at = rb.center_of_mass();
            let v = com.map_or(v, |c| v + w.cross(at - c));
            rb.set_linvel(v, false);
            rb.set_angvel(w, false);
        }
        Piece { bone, body, collider }
    }

    /// Joins bones `parent` and `child` at `rest_point` (rest frame) with the settings' rule, at
    /// rest in their current relative orientation.
    pub(crate) fn add_joint(
        &self,
        world: &mut PhysicsWorld,
        parent: usize,
        child: usize,
        rest_point: Vec3,
        dynamic: bool,
    ) -> Result<BendJoint, AdapterError> {
        let (b1, b2) = (self.pieces[parent].body, self.pieces[child].body);
        let r1 = *world.bodies.get(b1).ok_or(AdapterError::UnknownBody(b1))?.rotation();
        let r2 = *world.bodies.get(b2).ok_or(AdapterError::UnknownBody(b2))?.rotation();
        let rest: Quat = r1.inverse() * r2;
        let rule = JointState::new(self.settings.joint, rest)?;
        let joint: GenericJoint = SphericalJointBuilder::new()
            .local_anchor1(rest_point)
            .local_anchor2(rest_point)
            .contacts_enabled(false)
            .build()
            .into();
        let handle = world.impulse_joints.insert(b1, b2, joint, true);
        Ok(BendJoint { parent, child, rest_point, handle, rule, dynamic })
    }
}

/// The convex-hull collider of each of `bones`' parts of `rig`.
pub(crate) fn hulls(rig: &Rig, bones: &[usize]) -> Result<Vec<(usize, ColliderBuilder)>, AdapterError> {
    bones.iter().map(|&bone| Ok((bone, ColliderBuilder::new(part_hull(rig, bone)?)))).collect()
}

/// The convex hull of `bone`'s part of `rig`.
pub(crate) fn part_hull(rig: &Rig, bone: usize) -> Result<SharedShape, AdapterError> {
    let part = rig.part(bone).map_err(rig_error)?;
    crate::convex_shape(&part)
        .ok_or_else(|| AdapterError::Rig(format!("bone {bone}'s part has no convex hull (flat or degenerate)")))
}

pub(crate) fn rig_error(e: dentbend::bend::BendError) -> AdapterError {
    AdapterError::Rig(e.to_string())
}

fn check_settings(s: &BendSettings) -> Result<(), AdapterError> {
    let bad = |name, value: f32, reason| AdapterError::InvalidParameter { name, value: value.to_string(), reason };
    if !(s.density.is_finite() && s.density > 0.0) {
        return Err(bad("density", s.density, "must be finite and > 0"));
    }
    if !(s.friction.is_finite() && s.friction >= 0.0) {
        return Err(bad("friction", s.friction, "must be finite and ≥ 0"));
    }
    if let Some(v) = s.split_speed
        && !(v.is_finite() && v >= 0.0)
    {
        return Err(bad("split_speed", v, "must be finite and ≥ 0"));
    }
    if !(s.min_joint_spacing.is_finite() && s.min_joint_spacing >= 0.0) {
        return Err(bad("min_joint_spacing", s.min_joint_spacing, "must be finite and ≥ 0"));
    }
    Ok(())
}
