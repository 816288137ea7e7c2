//! The world: bodies, joints, settings and saved states; the time step is in `world_step.rs`
//! (ARCHITECTURE.md §2): broad phase → narrow phase → collision (restitution) → gravity → elastic joint
//! springs → contact (inelastic, shock propagation) → joint pre-stabilization → positions → joint
//! post-stabilization.

use rustc_hash::FxHashSet;

use glam::{Quat, Vec3};

use super::cluster::{Cluster, Role};
use super::error::invalid;
use super::joints::{self, Joint, JointKind};
use super::sleep::Activity;
use super::warm_start::ContactCache;
use super::{BodyDesc, RigidBody, SimError};

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

/// Global settings of a world.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WorldSettings {
    /// Gravity, m/s².
    pub gravity: Vec3,
    /// Time step, s.
    pub dt: f32,
    /// Sweeps of the collision (restitution) phase.
    pub collision_iterations: u32,
    /// Sweeps of the contact phase (the last one with shock propagation).
    pub contact_iterations: u32,
    /// Closing speeds below this bounce with no restitution (resting contact), m/s.
    pub restitution_threshold: f32,
    /// Overlap left alone by the position correction, m.
    pub slop: f32,
    /// Fraction of the overlap beyond the slop removed per step (by a split position
    /// correction that adds no velocity).
    pub baumgarte: f32,
    /// Contacts are sought this far beyond touching, plus how far the bodies move in a step, m.
    pub margin: f32,
    /// GBF shock propagation in the last contact sweep (stable stacks).
    pub shock_propagation: bool,
    /// An island of touching bodies falls asleep when every body in it has been slower than this
    /// (centre plus rim, velocities smoothed over 0.1 s), m/s, for `sleep_time`.
    pub sleep_speed: f32,
    /// Seconds of stillness before a body sleeps; ≤ 0 disables sleeping.
    pub sleep_time: f32,
    /// Fraction of angular velocity lost per second (air drag stand-in), 1/s.
    pub angular_damping: f32,
    /// Rolling (and spinning) resistance coefficient, dimensionless: at each resting contact
    /// the contact phase resists the bodies' relative rotation with an angular impulse of at
    /// most this × the contact's normal impulse × the rolling radius (the shorter distance from
    /// a centre of mass to the point). Real contacts are patches, not points; without this a
    /// ball rolls on a floor or spins on its support until `angular_damping` stops it, and a
    /// pile never settles. A ball stays on slopes with tan α ≤ this and rolls down steeper ones
    /// at (5/7) g (sin α − this × cos α). 0.005 (a 0.5 mm lever on a 10 cm ball, hard materials)
    /// stops a ball rolling at 5 cm/s on a floor in about 1.5 s; much larger values let balls
    /// dropped onto each other stand as columns.
    pub rolling_resistance: f32,
    /// Most a body's angular velocity may turn it in one step, rad (finite, > 0): a faster spin
    /// left by a step is scaled down to this (as Box2D and Bullet do). The position update's
    /// first-order quaternion step and the joints' linearization of it are only accurate for
    /// modest turns per step; a thin strut rolling on its axis (inertia m r²/2 of a 2.5 cm
    /// radius) can be spun past 10 rad per step by one friction impulse, and its joints then
    /// run away. π/2 is 94 rad/s at 60 steps per second.
    pub max_turn: f32,
    /// Fastest a joint's drift (anchors apart, m) is closed, m/s (finite, > 0). Pre-stabilization
    /// removes drift with real velocity, so closing d metres in one step leaves the bodies
    /// d/dt faster: a 10 cm drift closed at once is 6 m/s at 60 steps per second, and a
    /// truss whose joints were torn apart that way by one hard step gained energy step after
    /// step. Drift beyond this × dt is left for the following steps.
    pub joint_correction_speed: f32,
    /// Fastest a locked joint's angular drift (relative orientation off its target, rad) is
    /// closed, rad/s (finite, > 0); as `joint_correction_speed`.
    pub joint_correction_spin: f32,
}

impl Default for WorldSettings {
    fn default() -> Self {
        Self {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            dt: 1.0 / 60.0,
            collision_iterations: 5,
            contact_iterations: 12,
            restitution_threshold: 0.5,
            slop: 0.002,
            baumgarte: 0.2,
            margin: 0.01,
            shock_propagation: true,
            sleep_speed: 0.05,
            sleep_time: 0.5,
            angular_damping: 0.05,
            rolling_resistance: 0.005,
            max_turn: std::f32::consts::FRAC_PI_2,
            joint_correction_speed: 1.0,
            joint_correction_spin: std::f32::consts::PI,
        }
    }
}

impl WorldSettings {
    /// `spin` (rad/s) scaled down to at most `max_turn` per step.
    pub(crate) fn limit_spin(&self, spin: Vec3) -> Vec3 {
        let limit = self.max_turn / self.dt;
        let speed = spin.length();
        if speed > limit { spin * (limit / speed) } else { spin }
    }

    /// Checks every number.
    ///
    /// # Errors
    /// [`SimError::Invalid`] naming the first bad field.
    pub fn validate(&self) -> Result<(), SimError> {
        if !(self.gravity.is_finite() && self.gravity.length() <= 1.0e4) {
            return Err(invalid("gravity", self.gravity, "must be finite and at most 1e4 m/s² (a thousand g)"));
        }
        if !(self.dt.is_finite() && self.dt > 0.0 && self.dt <= 1.0) {
            return Err(invalid("dt", self.dt, "must be in (0, 1] s"));
        }
        for (what, value) in [
            ("restitution_threshold", self.restitution_threshold),
            ("slop", self.slop),
            ("margin", self.margin),
            ("sleep_speed", self.sleep_speed),
            ("angular_damping", self.angular_damping),
            ("rolling_resistance", self.rolling_resistance),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(invalid(what, value, "must be finite and >= 0"));
            }
        }
        for (what, value) in [
            ("max_turn", self.max_turn),
            ("joint_correction_speed", self.joint_correction_speed),
            ("joint_correction_spin", self.joint_correction_spin),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(invalid(what, value, "must be finite and > 0"));
            }
        }
        if !(0.0..=1.0).contains(&self.baumgarte) {
            return Err(invalid("baumgarte", self.baumgarte, "must be in [0, 1]"));
        }
        if !self.sleep_time.is_finite() {
            return Err(invalid("sleep_time", self.sleep_time, "must be finite"));
        }
        if self.contact_iterations == 0 || self.contact_iterations > 1000 || self.collision_iterations > 1000 {
            return Err(invalid("contact_iterations", self.contact_iterations, "must be in 1..=1000"));
        }
        Ok(())
    }
}

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
