//! The time step (ARCHITECTURE.md §2), in two halves so that a caller can look at what a step is about
//! to hit before it is taken (the bending layer's dummy step): [`World::detect`] (broad phase,
//! narrow phase, closing speeds) and [`World::advance`] (collision, gravity, springs, contact,
//! joint pre-stabilization, positions, joint post-stabilization, sleep).

use std::time::Instant;

use glam::{Quat, Vec3};

use super::super::contact_parts::Parts;
use super::super::joint_rounds::JointedContacts;
use super::super::joints;
use super::super::solver::{self, Constraint, SolverBody};
use super::super::{Aabb, BodyKind, CollisionEvent, PairContacts, RigidBody, StepReport};
use super::super::{broad_phase, contacts, joint_rounds, sleep};
use super::World;
use super::world_seen::Seen;

/// What the first half of a step found ([`World::detect`]), to be finished by
/// [`World::advance`] on the same state.
#[derive(Debug)]
pub(crate) struct Detection {
    /// The world's step count and body count when detected (a stale detection is refused).
    pub(super) step: u64,
    pub(super) bodies: usize,
    /// The world's count of lifted collision filters when detected.
    pub(super) filters_lifted: u64,
    started: Instant,
    /// Bounding radius of each body about its centre of mass, m.
    radius: Vec<f32>,
    /// The broad phase's pairs, sorted.
    pub(super) pairs: Vec<(usize, usize)>,
    /// Each pair's contacts, in pair order (pairs without points left out).
    pub(super) found: Vec<PairContacts>,
    /// What each body was when its contacts were found (see `world_redetect`).
    pub(super) seen: Vec<Seen>,
    solver_bodies: Vec<SolverBody>,
    /// The contact constraints, reordered part by part (see `contact_parts`).
    constraints: Vec<Constraint>,
    parts: Parts,
}

impl World {
    /// Advances the world by one time step and reports the collisions.
    pub fn step(&mut self) -> StepReport {
        let detected = self.detect();
        self.advance(detected)
    }

    /// The first half of a step: broad and narrow phase on the current state, sleeping bodies
    /// that moving ones touch woken, and every contact's closing speed before any impulse.
    /// [`Detection::impacts`] tells what the step is about to hit; [`advance`](Self::advance)
    /// finishes the step. Any edit of the world in between makes the detection stale: detect
    /// again.
    pub(crate) fn detect(&mut self) -> Detection {
        let started = Instant::now();
        let (radius, reach) = self.extents();
        // Bodies condensed into a cluster collide through its proxy: only the simulated ones are
        // swept (in increasing index order, so pairs map back sorted).
        let live = self.live();
        let boxes = self.swept_boxes(&live, &reach);
        let pairs: Vec<(usize, usize)> =
            broad_phase::overlapping_pairs(&boxes, |a, b| self.skip_pair(live[a], live[b]))
                .into_iter()
                .map(|(a, b)| (live[a], live[b]))
                .collect();
        let found = self.contacts_of(&pairs, &reach);
        self.finish_detection(started, radius, pairs, found)
    }

    /// Each body's bounding radius about its centre of mass (0 for static bodies; rim speed =
    /// |ω| × radius) and [`reach`](Self::reach) this step, m.
    pub(super) fn extents(&self) -> (Vec<f32>, Vec<f32>) {
        let radius: Vec<f32> = self
            .bodies
            .iter()
            .map(|b| if b.kind == BodyKind::Static { 0.0 } else { b.shape.compute_local_bounding_sphere().radius })
            .collect();
        let reach: Vec<f32> = self.bodies.iter().zip(&radius).map(|(b, &r)| self.reach(b, r)).collect();
        (radius, reach)
    }

    /// The simulated bodies, increasing.
    pub(super) fn live(&self) -> Vec<usize> {
        (0..self.bodies.len()).filter(|&i| self.bodies[i].is_simulated()).collect()
    }

    /// The narrow phase on `pairs`, each within the margin plus both bodies' `reach`.
    pub(super) fn contacts_of(&self, pairs: &[(usize, usize)], reach: &[f32]) -> Vec<PairContacts> {
        let margin = self.settings.margin;
        contacts::find_contacts(&self.bodies, pairs, |i, j| margin + reach[i] + reach[j])
    }

    /// The rest of a detection once the pairs and their contacts are known: what the bodies
    /// are now, sleeping bodies that moving ones touch woken, and the contacts' constraints.
    pub(super) fn finish_detection(
        &mut self,
        started: Instant,
        radius: Vec<f32>,
        pairs: Vec<(usize, usize)>,
        found: Vec<PairContacts>,
    ) -> Detection {
        let s = self.settings;
        // Before waking: a body woken here has changed since its contacts were found.
        let seen = self.bodies.iter().map(Seen::of).collect();
        self.wake_touched(&found, &radius);
        joints::sync_sleep(&self.joints, &mut self.bodies);
        let up = -s.gravity.normalize_or(Vec3::NEG_Y);
        let solver_bodies: Vec<SolverBody> = self.bodies.iter().map(|b| solver_body(b, up)).collect();
        let surface = |i: usize, j: usize| {
            let (a, b) = (&self.bodies[i].surface, &self.bodies[j].surface);
            (a.restitution.max(b.restitution), (a.friction * b.friction).sqrt(), s.rolling_resistance)
        };
        let mut constraints = solver::constraints(&found, &solver_bodies, s.dt, surface);
        let parts = Parts::split(&mut constraints, &solver_bodies);
        Detection {
            step: self.steps,
            bodies: self.bodies.len(),
            filters_lifted: self.filters_lifted,
            started,
            radius,
            pairs,
            found,
            seen,
            solver_bodies,
            constraints,
            parts,
        }
    }

    /// The collisions `detected` is about to resolve, as [`StepReport::events`] will report them
    /// but before any impulse: each at its fastest-closing point, with a zero impulse.
    pub(crate) fn impacts(&self, detected: &Detection) -> Vec<CollisionEvent> {
        events(&detected.found, &detected.constraints, |body, part| self.member_hit(body, part))
    }

    /// The second half of a step begun by [`detect`](Self::detect) on this very state: impulses,
    /// joints, positions, sleep.
    pub(crate) fn advance(&mut self, detected: Detection) -> StepReport {
        assert!(
            detected.step == self.steps && detected.bodies == self.bodies.len(),
            "a detection is finished on the state it was made from"
        );
        let Detection { started, radius, pairs, found, mut solver_bodies, mut constraints, parts, .. } = detected;
        let broad_pairs = pairs.len();
        let s = self.settings;
        self.cache.seed(&mut constraints, |i| self.bodies[i].orientation);
        solver::collide(&mut solver_bodies, &mut constraints, &parts, &s);
        for (body, sb) in self.bodies.iter().zip(solver_bodies.iter_mut()) {
            if moves_freely(body) {
                sb.linear += s.gravity * s.dt;
            }
        }
        joints::apply_springs(&mut self.joints, &self.bodies, &mut solver_bodies, &s);
        solver::contact(&mut solver_bodies, &mut constraints, &parts, &s);
        let mut pseudo = solver::position_correction(&solver_bodies, &mut constraints, &parts, &s);
        // With jointed contacts, the joint-contact rounds follow and finish with a full pass.
        let jointed = self.jointed_contacts(&constraints);
        let newton = if jointed.is_empty() { joints::NEWTON } else { 1 };
        joints::prestabilize(&mut self.joints, &self.bodies, &mut solver_bodies, &mut pseudo, &s, true, newton);
        let (joints, bodies) = (&mut self.joints, &self.bodies);
        let contacts = JointedContacts { constraints: &mut constraints, parts: &parts, jointed: &jointed };
        joint_rounds::joint_contact_rounds(joints, bodies, &mut solver_bodies, contacts, &mut pseudo, &s);
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
            broad_pairs,
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

    /// The swept boxes of bodies `which` (see [`swept_box`](Self::swept_box)), each grown by
    /// its `reach` (per world body).
    pub(super) fn swept_boxes(&self, which: &[usize], reach: &[f32]) -> Vec<Aabb> {
        which.iter().map(|&i| self.swept_box(&self.bodies[i], reach[i])).collect()
    }

    /// The body's box grown by the margin and by `reach`, how far it can move in one step.
    fn swept_box(&self, body: &RigidBody, reach: f32) -> Aabb {
        let aabb = body.shape.compute_aabb(&contacts::pose(body));
        let grow = Vec3::splat(self.settings.margin + reach);
        Aabb { min: aabb.mins - grow, max: aabb.maxs + grow }
    }

    /// Pairs of simulated bodies that cannot interact: neither body free to move, or joined by
    /// a joint (condensed bodies never reach the sweep).
    pub(super) fn skip_pair(&self, i: usize, j: usize) -> bool {
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
                    BodyKind::Dynamic => {
                        body.activity.disturbs([body.linear_velocity, body.angular_velocity], radius[k], threshold)
                    }
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

/// One event per pair with a closing contact, in pair order: impulse-weighted point, the pair's
/// normal, the relative velocity there before the step. A cluster's proxy is reported as the
/// member hit (`member(body, part)`, the part of the closest contact), a before b in index order.
fn events(
    found: &[PairContacts],
    constraints: &[solver::Constraint],
    member: impl Fn(usize, u32) -> usize,
) -> Vec<CollisionEvent> {
    // A pair's constraints are contiguous and in point order, though the parts reorder pairs.
    let mut spans = vec![0..0; found.len()];
    let mut start = 0;
    for k in 1..=constraints.len() {
        if k == constraints.len() || constraints[k].pair != constraints[start].pair {
            spans[constraints[start].pair] = start..k;
            start = k;
        }
    }
    let mut out = Vec::new();
    for (contact, span) in found.iter().zip(spans) {
        let mine = &constraints[span];
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
