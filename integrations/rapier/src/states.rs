//! Body states recorded before Rapier's step. Rapier detects contacts at the start of a step
//! and solves them inside it, so the velocities that caused a contact are the ones the bodies
//! had before `PhysicsPipeline::step`; the contact points it reports are in the colliders'
//! frames as they were then.

use std::collections::HashMap;

use dentbend::dent::BodyState;
use glam::{Affine3A, Mat3};
use rapier3d::math::Pose;
use rapier3d::prelude::{Collider, ColliderHandle, ColliderSet, RigidBody, RigidBodyHandle, RigidBodySet};

use crate::AdapterError;

/// Every body's state and every collider's pose, world coordinates, taken before a step.
#[derive(Debug, Clone, Default)]
pub struct BodyStates {
    bodies: HashMap<RigidBodyHandle, BodyState>,
    poses: HashMap<RigidBodyHandle, Pose>,
    colliders: HashMap<ColliderHandle, Affine3A>,
    parents: HashMap<ColliderHandle, RigidBodyHandle>,
}

impl BodyStates {
    /// Records `bodies` and `colliders` as they are now (call right before the step).
    pub fn record(bodies: &RigidBodySet, colliders: &ColliderSet) -> Self {
        let poses = bodies.iter().map(|(h, rb)| (h, *rb.position())).collect();
        let bodies = bodies.iter().map(|(h, rb)| (h, body_state(rb))).collect();
        let parents = colliders.iter().filter_map(|(h, c)| c.parent().map(|b| (h, b))).collect();
        let colliders = colliders.iter().map(|(h, c)| (h, to_affine(c.position()))).collect();
        Self { bodies, poses, colliders, parents }
    }

    /// Body `handle`'s recorded state: [`AdapterError::RemovedBody`] when it was recorded but
    /// `bodies` no longer has it, [`AdapterError::NotRecorded`] when it was added after the
    /// record, [`AdapterError::UnknownBody`] when neither knows it.
    ///
    /// # Errors
    /// As above.
    pub fn body(&self, handle: RigidBodyHandle, bodies: &RigidBodySet) -> Result<BodyState, AdapterError> {
        match (self.bodies.get(&handle), bodies.contains(handle)) {
            (Some(state), true) => Ok(*state),
            (Some(_), false) => Err(AdapterError::RemovedBody(handle)),
            (None, true) => Err(AdapterError::NotRecorded(handle)),
            (None, false) => Err(AdapterError::UnknownBody(handle)),
        }
    }

    /// Body `handle`'s recorded pose (body frame → world).
    pub fn body_pose(&self, handle: RigidBodyHandle) -> Option<Pose> {
        self.poses.get(&handle).copied()
    }

    /// Collider `handle`'s recorded pose (collider frame → world).
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
