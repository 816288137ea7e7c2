//! Body states recorded before Rapier's step. Rapier detects contacts at the start of a step
//! and solves them inside it, so the velocities that caused a contact are the ones the bodies
//! had before `PhysicsPipeline::step`; the contact points it reports are in the colliders'
//! frames as they were then.

use dentbend::dent::BodyState;
use glam::{Affine3A, Mat3};
use rapier3d::math::Pose;
use rapier3d::prelude::{Collider, ColliderHandle, ColliderSet, RigidBody, RigidBodyHandle, RigidBodySet};
use rustc_hash::FxHashMap as HashMap;

use crate::AdapterError;

/// Every moving body's state and its colliders' poses, world coordinates, taken before a step.
/// Fixed bodies and colliders without a body are not recorded: a step never moves them, so
/// their state and pose are read when asked (a fixed body has no velocity).
#[derive(Debug, Clone, Default)]
pub struct BodyStates {
    bodies: HashMap<RigidBodyHandle, BodyState>,
    poses: HashMap<RigidBodyHandle, Pose>,
    colliders: HashMap<ColliderHandle, Affine3A>,
    parents: HashMap<ColliderHandle, RigidBodyHandle>,
}

impl BodyStates {
    /// Records the dynamic and kinematic bodies of `bodies` and their colliders as they are now
    /// (call right before the step). Cost: a pass over the bodies, and a record of each moving
    /// one: a world of thousands of fixed bodies costs a few microseconds.
    pub fn record(bodies: &RigidBodySet, colliders: &ColliderSet) -> Self {
        let mut out = Self::default();
        out.record_again(bodies, colliders);
        out
    }

    /// As [`record`](Self::record), into this record (what it held is dropped; its memory is
    /// kept for the next step).
    pub fn record_again(&mut self, bodies: &RigidBodySet, colliders: &ColliderSet) {
        let Self { bodies: states, poses, colliders: poses_of_colliders, parents } = self;
        states.clear();
        poses.clear();
        poses_of_colliders.clear();
        parents.clear();
        for (h, rb) in bodies.iter().filter(|(_, rb)| !rb.is_fixed()) {
            poses.insert(h, *rb.position());
            states.insert(h, body_state(rb));
            for &c in rb.colliders() {
                if let Some(collider) = colliders.get(c) {
                    poses_of_colliders.insert(c, to_affine(collider.position()));
                    parents.insert(c, h);
                }
            }
        }
    }

    /// Body `handle`'s state before the step: recorded, or read now for a fixed body;
    /// [`AdapterError::RemovedBody`] when it was recorded but `bodies` no longer has it,
    /// [`AdapterError::NotRecorded`] for a moving body added after the record,
    /// [`AdapterError::UnknownBody`] when neither knows it.
    ///
    /// # Errors
    /// As above.
    pub fn body(&self, handle: RigidBodyHandle, bodies: &RigidBodySet) -> Result<BodyState, AdapterError> {
        match (self.bodies.get(&handle), bodies.get(handle)) {
            (Some(state), Some(_)) => Ok(*state),
            (Some(_), None) => Err(AdapterError::RemovedBody(handle)),
            (None, Some(rb)) if rb.is_fixed() => Ok(body_state(rb)),
            (None, Some(_)) => Err(AdapterError::NotRecorded(handle)),
            (None, None) => Err(AdapterError::UnknownBody(handle)),
        }
    }

    /// Body `handle`'s recorded pose (body frame → world); `None` for a body not recorded (a
    /// fixed one: its pose now is its pose then).
    pub fn body_pose(&self, handle: RigidBodyHandle) -> Option<Pose> {
        self.poses.get(&handle).copied()
    }

    /// Collider `handle`'s recorded pose (collider frame → world); `None` for one not recorded
    /// (on a fixed body or none: its pose now is its pose then).
    pub fn collider_pose(&self, handle: ColliderHandle) -> Option<Affine3A> {
        self.colliders.get(&handle).copied()
    }

    /// The body collider `handle` was attached to when recorded.
    pub fn collider_parent(&self, handle: ColliderHandle) -> Option<RigidBodyHandle> {
        self.parents.get(&handle).copied()
    }

    /// Collider `handle`'s pose at the start of the step (its pose now if it was not recorded)
    /// and its body's state then, restitution the collider's ([`BodyState::FIXED`] without a
    /// body).
    ///
    /// # Errors
    /// As [`collider`](Self::collider) and [`body`](Self::body).
    pub fn collider_state(
        &self,
        handle: ColliderHandle,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
    ) -> Result<(Affine3A, BodyState), AdapterError> {
        let collider = self.collider(handle, bodies, colliders)?;
        let pose = self.collider_pose(handle).unwrap_or_else(|| to_affine(collider.position()));
        let mut state = match collider.parent() {
            Some(body) => self.body(body, bodies)?,
            None => BodyState::FIXED,
        };
        state.restitution = collider.restitution().clamp(0.0, 1.0);
        Ok((pose, state))
    }

    /// Collider `handle` from `colliders`, or why it is missing: its recorded body was removed
    /// ([`AdapterError::RemovedBody`]), it was removed itself
    /// ([`AdapterError::RemovedCollider`]), or it was never there
    /// ([`AdapterError::UnknownCollider`]).
    ///
    /// # Errors
    /// As above.
    pub fn collider<'c>(
        &self,
        handle: ColliderHandle,
        bodies: &RigidBodySet,
        colliders: &'c ColliderSet,
    ) -> Result<&'c Collider, AdapterError> {
        if let Some(c) = colliders.get(handle) {
            return Ok(c);
        }
        match self.collider_parent(handle) {
            Some(body) if !bodies.contains(body) => Err(AdapterError::RemovedBody(body)),
            _ if self.colliders.contains_key(&handle) => Err(AdapterError::RemovedCollider(handle)),
            _ => Err(AdapterError::UnknownCollider(handle)),
        }
    }

    /// Overrides body `handle`'s recorded state (for tests and callers with their own
    /// bookkeeping).
    pub fn set_body(&mut self, handle: RigidBodyHandle, state: BodyState) {
        self.bodies.insert(handle, state);
    }
}

/// A Rapier body as the dent decision sees it: world centre of mass (m), velocities (m/s,
/// rad/s), inverse mass (1/kg) and world inverse inertia (1/(kg·m²)); fixed and kinematic
/// bodies take no impulse (zero inverses).
pub fn body_state(rb: &RigidBody) -> BodyState {
    let (inverse_mass, inverse_inertia) = if rb.is_dynamic() && rb.mass() > 0.0 {
        (1.0 / rb.mass(), rb.mass_properties().effective_world_inv_inertia.mul_mat(Mat3::IDENTITY))
    } else {
        (0.0, Mat3::ZERO)
    };
    BodyState {
        center_of_mass: rb.center_of_mass(),
        linear_velocity: rb.linvel(),
        angular_velocity: rb.angvel(),
        inverse_mass,
        inverse_inertia,
        restitution: 0.0,
    }
}

/// A Rapier pose as a glam affine map (rigid).
pub fn to_affine(pose: &Pose) -> Affine3A {
    Affine3A::from_rotation_translation(pose.rotation, pose.translation)
}
