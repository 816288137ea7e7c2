//! The world: bodies, settings, and the time step (DESIGN.md §2): broad phase → narrow phase →
//! collision (restitution) → gravity → elastic joint springs → contact (inelastic, shock
//! propagation) → joint pre-stabilization → positions → joint post-stabilization.

use std::collections::HashSet;
use std::time::Instant;

use glam::{Quat, Vec3};

use super::cluster::{Cluster, Role};
use super::joints::{self, Joint, JointKind};
use super::sleep::{self, Activity};
use super::solver::{self, SolverBody};
use super::warm_start::ContactCache;
use super::{Aabb, BodyDesc, BodyKind, CollisionEvent, PairContacts, RigidBody, SimError, StepReport};
use super::{broad_phase, contacts, error::invalid, joint_rounds};

#[path = "world_cluster.rs"]
mod world_cluster;
#[path = "world_edit.rs"]
mod world_edit;

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
        if !self.gravity.is_finite() {
            return Err(invalid("gravity", self.gravity, "must be finite"));
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
        if !(self.max_turn.is_finite() && self.max_turn > 0.0) {
            return Err(invalid("max_turn", self.max_turn, "must be finite and > 0"));
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
    joined: HashSet<(usize, usize)>,
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
    /// Body pairs (smaller index first) joined by a joint: they do not collide.
    joined: HashSet<(usize, usize)>,
    /// Body pairs (smaller index first) that do not collide whether joined or not
    /// ([`ignore_collisions`](Self::ignore_collisions)).
    ignored: HashSet<(usize, usize)>,
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
            joined: HashSet::new(),
            ignored: HashSet::new(),
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
    /// from later with [`restore`](Self::restore): the paper's "dummy step" (Algorithm 2) that
    /// finds the hits before joints are added where they land. Meshes are not saved.
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

    /// Advances the world by one time step and reports the collisions.
    pub fn step(&mut self) -> StepReport {
        let started = Instant::now();
        let s = self.settings;
        // Bounding radius about the centre of mass, m: rim speed = |ω| × radius (static: unused).
        let radius: Vec<f32> = self
            .bodies
            .iter()
            .map(|b| if b.kind == BodyKind::Static { 0.0 } else { b.shape.compute_local_bounding_sphere().radius })
            .collect();
        let reach: Vec<f32> = self.bodies.iter().zip(&radius).map(|(b, &r)| self.reach(b, r)).collect();
        let boxes: Vec<Aabb> = self.bodies.iter().zip(&reach).map(|(b, &r)| self.swept_box(b, r)).collect();
        let pairs = broad_phase::overlapping_pairs(&boxes, |i, j| self.skip_pair(i, j));
        let found = contacts::find_contacts(&self.bodies, &pairs, |i, j| s.margin + reach[i] + reach[j]);
        self.wake_touched(&found, &radius);
        joints::sync_sleep(&self.joints, &mut self.bodies);

        let up = -s.gravity.normalize_or(Vec3::NEG_Y);
        let mut solver_bodies: Vec<SolverBody> = self.bodies.iter().map(|b| solver_body(b, up)).collect();
        let surface = |i: usize, j: usize| {
            let (a, b) = (&self.bodies[i].surface, &self.bodies[j].surface);
            (a.restitution.max(b.restitution), (a.friction * b.friction).sqrt(), s.rolling_resistance)
        };
        let mut constraints = solver::constraints(&found, &solver_bodies, s.dt, surface);
        self.cache.seed(&mut constraints, |i| self.bodies[i].orientation);
        solver::collide(&mut solver_bodies, &mut constraints, &s);
        for (body, sb) in self.bodies.iter().zip(solver_bodies.iter_mut()) {
            if moves_freely(body) {
                sb.linear += s.gravity * s.dt;
            }
        }
        joints::apply_springs(&mut self.joints, &self.bodies, &mut solver_bodies, &s);
        solver::contact(&mut solver_bodies, &mut constraints, &s);
        let mut pseudo = solver::position_correction(&solver_bodies, &mut constraints, &s);
        joints::prestabilize(&mut self.joints, &self.bodies, &mut solver_bodies, &mut pseudo, &s, true);
        let jointed = self.jointed_contacts(&constraints);
        let (joints, bodies) = (&mut self.joints, &self.bodies);
        joint_rounds::joint_contact_rounds(
            joints,
            bodies,
            &mut solver_bodies,
            &mut constraints,
            &mut pseudo,
            &jointed,
            &s,
        );
        self.cache.store(&constraints, |i| self.bodies[i].orientation);
        let events = events(&found, &constraints, |body, part| self.member_hit(body, part));
        self.integrate(&solver_bodies, &pseudo);
        let bends = joints::poststabilize(&mut self.joints, &mut self.bodies, &s);
        self.sync_members();
        // Islands: bodies touching, and bodies joined by a joint.
        let links: Vec<(usize, usize)> =
            found.iter().map(|p| (p.a, p.b)).chain(self.joints.iter().map(|j| (j.a(), j.b()))).collect();
        sleep::settle(&mut self.bodies, &radius, &links, &s, self.steps);
        self.time += f64::from(s.dt);
        self.steps += 1;
        StepReport {
            events,
            bends,
            broad_pairs: pairs.len(),
            contact_points: constraints.len(),
            seconds: started.elapsed().as_secs_f64(),
        }
    }

    /// Indices of the constraints on bodies that a joint holds to a dynamic body.
    fn jointed_contacts(&self, constraints: &[solver::Constraint]) -> Vec<usize> {
        if self.joints.is_empty() {
            return Vec::new();
        }
        let mut held = vec![false; self.bodies.len()];
        let dynamic = |i: usize| self.bodies[i].kind == BodyKind::Dynamic && self.bodies[i].is_simulated();
        for joint in &self.joints {
            if dynamic(joint.a) && dynamic(joint.b) {
                held[joint.a] = true;
                held[joint.b] = true;
            }
        }
        (0..constraints.len()).filter(|&k| held[constraints[k].a] || held[constraints[k].b]).collect()
    }

    /// How far a body's surface (within `radius` of its centre of mass) can move in one step, m.
    fn reach(&self, body: &RigidBody, radius: f32) -> f32 {
        if body.kind == BodyKind::Static || body.activity.asleep {
            return 0.0;
        }
        let speed = body.linear_velocity.length() + body.angular_velocity.length() * radius;
        let fall = if body.kind == BodyKind::Dynamic { self.settings.gravity.length() * self.settings.dt } else { 0.0 };
        (speed + fall) * self.settings.dt
    }

    /// The body's box grown by the margin and by `reach`, how far it can move in one step.
    fn swept_box(&self, body: &RigidBody, reach: f32) -> Aabb {
        let aabb = body.shape.compute_aabb(&contacts::pose(body));
        let grow = Vec3::splat(self.settings.margin + reach);
        Aabb { min: aabb.mins - grow, max: aabb.maxs + grow }
    }

    /// Pairs that cannot interact: neither body free to move, or joined by a joint.
    fn skip_pair(&self, i: usize, j: usize) -> bool {
        if !self.bodies[i].is_simulated() || !self.bodies[j].is_simulated() {
            return true;
        }
        let still = |b: &RigidBody| b.kind == BodyKind::Static || (b.kind == BodyKind::Dynamic && b.activity.asleep);
        still(&self.bodies[i]) && still(&self.bodies[j])
            || !moves(&self.bodies[i]) && !moves(&self.bodies[j])
            || self.joined.contains(&joints::pair(i, j))
            || self.ignored.contains(&joints::pair(i, j))
    }

    /// Wakes the islands of sleeping bodies touched by moving ones.
    fn wake_touched(&mut self, found: &[PairContacts], radius: &[f32]) {
        let threshold = self.settings.sleep_speed;
        for pair in found {
            let active = |k: usize| {
                let body = &self.bodies[k];
                match body.kind {
                    BodyKind::Static => false,
                    BodyKind::Kinematic => moves(body),
                    BodyKind::Dynamic => body.activity.disturbs(body, radius[k], threshold),
                }
            };
            if self.bodies[pair.a].activity.asleep && active(pair.b) {
                sleep::wake_island(&mut self.bodies, pair.a);
            } else if self.bodies[pair.b].activity.asleep && active(pair.a) {
                sleep::wake_island(&mut self.bodies, pair.b);
            }
        }
    }

    /// New velocities in, positions advanced, sleep bookkeeping.
    fn integrate(&mut self, solved: &[SolverBody], pseudo: &[(Vec3, Vec3)]) {
        let s = self.settings;
        for ((body, sb), &(push, twist)) in self.bodies.iter_mut().zip(solved).zip(pseudo) {
            if !body.is_simulated() {
                continue;
            }
            match body.kind {
                BodyKind::Static => continue,
                BodyKind::Dynamic if body.activity.asleep => continue,
                BodyKind::Dynamic => {
                    body.linear_velocity = sb.linear;
                    body.angular_velocity = s.limit_spin(sb.angular * (1.0 - s.angular_damping * s.dt).max(0.0));
                }
                BodyKind::Kinematic => {}
            }
            body.position += (body.linear_velocity + push) * s.dt;
            let w = body.angular_velocity + twist;
            let spin = Quat::from_xyzw(w.x, w.y, w.z, 0.0) * body.orientation;
            body.orientation = (body.orientation + spin * (0.5 * s.dt)).normalize();
        }
    }
}

/// Whether gravity and impulses move the body this step.
fn moves_freely(body: &RigidBody) -> bool {
    body.kind == BodyKind::Dynamic && !body.activity.asleep && body.is_simulated()
}

/// Whether the body can move at all (dynamic, or kinematic with a velocity).
fn moves(body: &RigidBody) -> bool {
    match body.kind {
        BodyKind::Static => false,
        BodyKind::Dynamic => true,
        BodyKind::Kinematic => body.linear_velocity != Vec3::ZERO || body.angular_velocity != Vec3::ZERO,
    }
}

fn solver_body(body: &RigidBody, up: Vec3) -> SolverBody {
    let free = moves_freely(body);
    SolverBody {
        linear: body.linear_velocity,
        angular: body.angular_velocity,
        position: body.position,
        inverse_mass: if free { body.inverse_mass } else { 0.0 },
        inverse_inertia: if free { body.inverse_inertia_world() } else { glam::Mat3::ZERO },
        height: body.position.dot(up),
    }
}

/// One event per pair with a closing contact: impulse-weighted point, the pair's normal, the
/// relative velocity there before the step. A cluster's proxy is reported as the member hit
/// (`member(body, part)`, the part of the closest contact), a before b in index order.
fn events(
    found: &[PairContacts],
    constraints: &[solver::Constraint],
    member: impl Fn(usize, u32) -> usize,
) -> Vec<CollisionEvent> {
    let mut out = Vec::new();
    let mut k = 0;
    for (pair, contact) in found.iter().enumerate() {
        let start = k;
        while k < constraints.len() && constraints[k].pair == pair {
            k += 1;
        }
        let mine = &constraints[start..k];
        let Some((closest_index, closest)) =
            mine.iter().enumerate().filter(|(_, c)| c.colliding).min_by(|x, y| x.1.approach.total_cmp(&y.1.approach))
        else {
            continue;
        };
        let impulse: Vec3 = mine.iter().map(|c| c.total).sum();
        let weight: f32 = mine.iter().map(|c| c.total.dot(c.normal).max(0.0)).sum();
        let point = if weight > 0.0 {
            mine.iter().map(|c| c.point * c.total.dot(c.normal).max(0.0)).sum::<Vec3>() / weight
        } else {
            closest.point
        };
        // Constraints are made one per contact point, in order.
        let at = &contact.points[closest_index];
        let (a, b) = (member(contact.a, at.part_a), member(contact.b, at.part_b));
        let event = CollisionEvent {
            a,
            b,
            point,
            normal: closest.normal,
            relative_velocity: closest.relative_velocity,
            normal_speed: -closest.approach,
            impulse,
        };
        out.push(if a < b { event } else { event.swapped() });
    }
    out
}
