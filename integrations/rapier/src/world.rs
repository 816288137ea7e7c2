//! A Rapier world in one struct: every set and the pipeline, so the adapter can step it and
//! split bodies (which touches most sets) through one `&mut`. Its fields are public: build it
//! from sets you already have.

use glam::Vec3;
use rapier3d::prelude::{
    BroadPhaseBvh, CCDSolver, ColliderSet, EventHandler, ImpulseJointSet, IntegrationParameters, IslandManager,
    MultibodyJointSet, NarrowPhase, PhysicsHooks, PhysicsPipeline, RigidBodyHandle, RigidBodySet, SoftBodySet,
};

/// Everything `PhysicsPipeline::step` takes, owned.
#[derive(Default)]
pub struct PhysicsWorld {
    /// Gravity, m/s².
    pub gravity: Vec3,
    /// Step length (`dt`, s) and solver settings.
    pub params: IntegrationParameters,
    /// The pipeline's working memory.
    pub pipeline: PhysicsPipeline,
    /// Islands of touching bodies.
    pub islands: IslandManager,
    /// Broad phase.
    pub broad_phase: BroadPhaseBvh,
    /// Narrow phase (the contact pairs).
    pub narrow_phase: NarrowPhase,
    /// Rigid bodies.
    pub bodies: RigidBodySet,
    /// Colliders.
    pub colliders: ColliderSet,
    /// Impulse joints.
    pub impulse_joints: ImpulseJointSet,
    /// Multibody joints.
    pub multibody_joints: MultibodyJointSet,
    /// Soft bodies (unused by the adapter; Rapier's step wants them).
    pub soft_bodies: SoftBodySet,
    /// Continuous collision detection.
    pub ccd: CCDSolver,
}

impl PhysicsWorld {
    /// An empty world with `gravity` (m/s²) stepping `dt` s.
    pub fn new(gravity: Vec3, dt: f32) -> Self {
        let params = IntegrationParameters { dt, ..IntegrationParameters::default() };
        Self { gravity, params, ..Self::default() }
    }

    /// One Rapier step, reporting to `events`.
    pub fn step(&mut self, events: &dyn EventHandler) {
        self.step_with(&(), events);
    }

    /// One Rapier step with the game's `hooks` (contact filters and modifiers), reporting to
    /// `events`.
    pub fn step_with(&mut self, hooks: &dyn PhysicsHooks, events: &dyn EventHandler) {
        self.pipeline.step(
            self.gravity,
            &self.params,
            &mut self.islands,
            &mut self.broad_phase,
            &mut self.narrow_phase,
            &mut self.bodies,
            &mut self.colliders,
            &mut self.impulse_joints,
            &mut self.multibody_joints,
            &mut self.soft_bodies,
            &mut self.ccd,
            hooks,
            events,
        );
    }

    /// Removes body `handle` with its colliders and joints; whether it existed.
    pub fn remove_body(&mut self, handle: RigidBodyHandle) -> bool {
        self.bodies
            .remove(
                handle,
                &mut self.islands,
                &mut self.colliders,
                &mut self.impulse_joints,
                &mut self.multibody_joints,
                &mut self.soft_bodies,
                true,
            )
            .is_some()
    }
}
