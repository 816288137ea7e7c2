//! The world: bodies, joints and saved states (its settings are in `world_settings.rs`). The
//! time step is in `world_step.rs` (ARCHITECTURE.md §2): broad phase → narrow phase →
//! collision (restitution) → gravity → elastic joint springs → contact (inelastic, shock
//! propagation) → joint pre-stabilization → positions → joint post-stabilization.

use rustc_hash::FxHashSet;

use glam::{Quat, Vec3};

use super::activity::Activity;
use super::cluster::{Cluster, Role};
use super::error::invalid;
use super::joints::{self, Joint, JointKind};
use super::warm_start::ContactCache;
use super::{BodyDesc, RigidBody, SimError, WorldSettings};

#[path = "world_cluster.rs"]
mod world_cluster;
#[path = "world_edit.rs"]
mod world_edit;
#[path = "world_redetect.rs"]
mod world_redetect;
#[path = "world_seen.rs"]
mod world_seen;
#[path = "world_step.rs"]
mod world_step;

/// The moving state of a [`World`], from [`World::snapshot`].
#[derive(Debug, Clone)]
pub struct WorldState {
    /// Per body: position, orientation, linear and angular velocity, sleep bookkeeping.
    bodies: Vec<(Vec3, Quat, Vec3, Vec3, Activity)>,
    joints: Vec<Joint>,
    joined: FxHashSet<(usize, usize)>,
    cache: ContactCache,
    time: f64,
    steps: u64,
    layout: u64,
}

/// Rigid bodies and the settings that step them.
#[derive(Debug, Clone)]
pub struct World {
    bodies: Vec<RigidBody>,
    settings: WorldSettings,
    time: f64,
    steps: u64,
    /// Joints between bodies, in the order they were added.
    joints: Vec<Joint>,
    /// Body pairs (smaller index first) joined by a joint: they do not collide. (Fx hashing: the
    /// broad phase looks pairs up by the ten thousand every step.)
    joined: FxHashSet<(usize, usize)>,
    /// Body pairs (smaller index first) that do not collide whether joined or not
    /// ([`ignore_collisions`](Self::ignore_collisions)).
    ignored: FxHashSet<(usize, usize)>,
    /// How many edits have let a pair collide again (a joined or ignored pair dropped): a
    /// detection kept across such an edit would miss that pair's contacts.
    filters_lifted: u64,
    /// Last step's contact impulses, to warm-start this step's.
    cache: ContactCache,
    /// Rigid clusters, active and dissolved (their proxies kept for reuse).
    clusters: Vec<Cluster>,
    /// Counts changes of which bodies are condensed, so a snapshot is only restored onto the
    /// layout it was taken in.
    layout: u64,
}

impl World {
    /// An empty world.
    ///
    /// # Errors
    /// [`SimError::Invalid`] for bad settings.
    pub fn new(settings: WorldSettings) -> Result<Self, SimError> {
        settings.validate()?;
        Ok(Self {
            bodies: Vec::new(),
            settings,
            time: 0.0,
            steps: 0,
            joints: Vec::new(),
            joined: FxHashSet::default(),
            ignored: FxHashSet::default(),
            filters_lifted: 0,
            cache: ContactCache::default(),
            clusters: Vec::new(),
            layout: 0,
        })
    }

    /// Adds a body and returns its index.
    ///
    /// # Errors
    /// As [`RigidBody::new`], or a name already taken.
    pub fn add(&mut self, desc: BodyDesc) -> Result<usize, SimError> {
        if self.bodies.iter().any(|b| b.name == desc.name) {
            return Err(invalid("body name", &desc.name, "is already taken"));
        }
        self.bodies.push(RigidBody::new(desc)?);
        Ok(self.bodies.len() - 1)
    }

    /// The bodies, in the order they were added.
    pub fn bodies(&self) -> &[RigidBody] {
        &self.bodies
    }

    /// Mutable access to the bodies (set velocities, poses…).
    pub fn bodies_mut(&mut self) -> &mut [RigidBody] {
        &mut self.bodies
    }

    /// Joins bodies `a` and `b` (indices) at world point `anchor` (m) with a joint of `kind` that
    /// holds their current relative orientation as its target; returns the joint's index. The
    /// two bodies no longer collide with each other.
    ///
    /// # Errors
    /// [`SimError::Invalid`] for an index that is not a body, the same body twice, two bodies
    /// neither of which is dynamic, a non-finite anchor, or a bad number in `kind` (see
    /// [`JointKind::validate`]).
    pub fn add_joint(&mut self, a: usize, b: usize, anchor: Vec3, kind: JointKind) -> Result<usize, SimError> {
        for (what, index) in [("joint body a", a), ("joint body b", b)] {
            if self.bodies.get(index).is_some_and(|body| body.role != Role::Free) {
                return Err(invalid(what, index, "is condensed into a cluster or is a cluster's proxy"));
            }
        }
        let joint = Joint::new(&self.bodies, a, b, anchor, kind)?;
        self.joined.insert(joints::pair(a, b));
        self.joints.push(joint);
        Ok(self.joints.len() - 1)
    }

    /// The joints, in the order they were added.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// Mutable access to the joints.
    pub fn joints_mut(&mut self) -> &mut [Joint] {
        &mut self.joints
    }

    /// Rebuilds body `index` from `desc` in place (same index, so joints and events keep
    /// naming it): a bending body's sub-body after its bone was split. Joints on the body stay
    /// where they are in the world. The body is woken.
    ///
    /// # Errors
    /// As [`RigidBody::new`]; an index that is not a body, or a name taken by another body.
    /// On error the world is unchanged.
    pub fn rebuild_body(&mut self, index: usize, desc: BodyDesc) -> Result<(), SimError> {
        if index >= self.bodies.len() {
            return Err(invalid("body index", index, "is not a body of the world"));
        }
        if self.bodies.iter().enumerate().any(|(k, b)| k != index && b.name == desc.name) {
            return Err(invalid("body name", &desc.name, "is already taken"));
        }
        if self.bodies[index].role != Role::Free {
            return Err(invalid("body index", index, "is condensed into a cluster or is a cluster's proxy"));
        }
        let body = RigidBody::new(desc)?;
        let old = (self.bodies[index].position, self.bodies[index].orientation);
        for joint in &mut self.joints {
            joint.rebase(index, old, (body.position, body.orientation));
        }
        self.bodies[index] = body;
        Ok(())
    }

    /// The moving state of the world (poses, velocities, sleep, joints, time), to step again
    /// from later with [`restore`](Self::restore), e.g. to try a step and take it back. Meshes
    /// are not saved.
    pub fn snapshot(&self) -> WorldState {
        WorldState {
            bodies: self
                .bodies
                .iter()
                .map(|b| (b.position, b.orientation, b.linear_velocity, b.angular_velocity, b.activity))
                .collect(),
            joints: self.joints.clone(),
            joined: self.joined.clone(),
            cache: self.cache.clone(),
            time: self.time,
            steps: self.steps,
            layout: self.layout,
        }
    }

    /// Puts back a [`snapshot`](Self::snapshot)'s state.
    ///
    /// # Errors
    /// [`SimError::Invalid`] when bodies were added since the snapshot; the world is unchanged.
    pub fn restore(&mut self, state: &WorldState) -> Result<(), SimError> {
        if state.bodies.len() != self.bodies.len() {
            return Err(invalid("snapshot", state.bodies.len(), "has a different number of bodies than the world"));
        }
        if state.layout != self.layout {
            return Err(invalid("snapshot", state.layout, "was taken before bodies were condensed or uncondensed"));
        }
        for (body, &(position, orientation, linear, angular, activity)) in self.bodies.iter_mut().zip(&state.bodies) {
            body.position = position;
            body.orientation = orientation;
            body.linear_velocity = linear;
            body.angular_velocity = angular;
            body.activity = activity;
        }
        self.joints.clone_from(&state.joints);
        self.joined.clone_from(&state.joined);
        self.filters_lifted += 1;
        self.cache = state.cache.clone();
        self.time = state.time;
        self.steps = state.steps;
        Ok(())
    }

    /// The index of the body called `name`.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// The settings.
    pub fn settings(&self) -> &WorldSettings {
        &self.settings
    }

    /// Simulated time, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Total kinetic energy of the dynamic bodies, J.
    pub fn kinetic_energy(&self) -> f64 {
        self.bodies.iter().filter(|b| b.is_simulated()).map(|b| f64::from(b.kinetic_energy())).sum()
    }
}
