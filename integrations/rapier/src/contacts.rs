//! Contacts from Rapier's solver, one per impact.
//!
//! [`ImpactReader`] reads them from the narrow phase after the step, for the colliders the
//! adapter knows: the game's event settings (`ActiveEvents`, `contact_force_event_threshold`)
//! play no part, and the game keeps its own event handler and hooks. A pair's impact starts on
//! the first step its solver contacts push (after a step they did not), again after every
//! bounce; pairs that go on pushing are kept, flagged not `started`, for progressive targets.
//!
//! [`ImpactCollector`] is an event handler for engines that hand over contact force events
//! instead of the narrow phase: Rapier's [`ContactForceEvent::started`] is true on the step
//! a pair's total contact force first exceeds the collider's
//! `contact_force_event_threshold` (coming from below or from not touching). With
//! [`ActiveEvents::CONTACT_FORCE_EVENTS`] and a threshold of 0 N that is the first step a pair
//! pushes, and again after every bounce: one dent per impact, none while a body rests. The
//! collector keeps the other force events too, flagged not `started`: progressive targets
//! (paper Figure 3) deepen their dent on every step a push goes on above the dent threshold.
//! The contact itself comes from the pair's *solver* manifolds (Rapier may cluster manifolds;
//! only the solver's carry impulses): the impulse-weighted mean of the contacts that pushed.

use std::sync::Mutex;

use glam::{Affine3A, Vec3};
use rapier3d::prelude::{
    ColliderHandle, ColliderSet, CollisionEvent, ContactForceEvent, ContactPair, EventHandler, NarrowPhase, Real,
    RigidBodySet, SoftBodySet, SoftBodyTearEvent,
};

use rustc_hash::FxHashSet as HashSet;

use crate::{AdapterError, BodyStates};

/// One impact between two colliders, as the adapter dents from it. World coordinates at the
/// start of the step (the poses in [`BodyStates`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// First collider of the pair.
    pub collider1: ColliderHandle,
    /// Second collider of the pair.
    pub collider2: ColliderHandle,
    /// Contact point, world, m.
    pub point: Vec3,
    /// Contact normal, world, pointing from `collider1` towards `collider2` (need not be unit,
    /// must be non-zero).
    pub normal: Vec3,
    /// Normal impulse the solver applied over the step, N·s (0 when unknown).
    pub impulse: f32,
    /// Whether this is the impact's first step (`ContactForceEvent::started`); later steps of
    /// a push only dent progressive targets.
    pub started: bool,
}

impl Contact {
    /// Checks that the point and normal are finite and the normal non-zero.
    ///
    /// # Errors
    /// [`AdapterError::NonFiniteContact`] or [`AdapterError::ZeroNormal`].
    pub fn validate(&self) -> Result<(), AdapterError> {
        let (collider1, collider2) = (self.collider1, self.collider2);
        for (field, v) in [("point", self.point), ("normal", self.normal)] {
            if !v.is_finite() {
                return Err(AdapterError::NonFiniteContact { collider1, collider2, field, value: v.to_string() });
            }
        }
        if self.normal.abs().max_element() == 0.0 {
            return Err(AdapterError::ZeroNormal { collider1, collider2 });
        }
        if !self.impulse.is_finite() {
            let value = self.impulse.to_string();
            return Err(AdapterError::NonFiniteContact { collider1, collider2, field: "impulse", value });
        }
        Ok(())
    }
}

/// A raw impact as the event handler saw it: contact points in the colliders' own frames.
#[derive(Debug, Clone)]
struct RawImpact {
    collider1: ColliderHandle,
    collider2: ColliderHandle,
    /// (point on 1 in 1's frame, point on 2 in 2's frame, normal impulse N·s).
    points: Vec<(Vec3, Vec3, f32)>,
    /// World normal, 1 → 2.
    normal: Vec3,
    started: bool,
    /// Each collider's pose when it cannot move (no body, or a fixed one), read during or
    /// after the step: the states do not record such colliders.
    still: [Option<Affine3A>; 2],
}

/// A Rapier [`EventHandler`] that keeps the pairs with a contact force event this step, with
/// their solver contacts and whether the event `started`. Pass it to `PhysicsPipeline::step`, then take
/// [`contacts`](Self::take_contacts).
#[derive(Debug, Default)]
pub struct ImpactCollector {
    raw: Mutex<Vec<RawImpact>>,
}

impl ImpactCollector {
    /// Nothing collected.
    pub fn new() -> Self {
        Self::default()
    }

    /// The step's impacts in world coordinates at the start of the step (`states`' poses),
    /// emptying the collector. Pairs whose colliders were not recorded are skipped.
    pub fn take_contacts(&self, states: &BodyStates) -> Vec<Contact> {
        let raw = std::mem::take(&mut *self.raw.lock().unwrap_or_else(|e| e.into_inner()));
        raw.iter().filter_map(|r| to_contact(r, states)).collect()
    }
}

/// Reads each step's impacts from Rapier's narrow phase (see the module doc), remembering which
/// pairs pushed on the step before.
#[derive(Debug, Default)]
pub struct ImpactReader {
    pushing: HashSet<(ColliderHandle, ColliderHandle)>,
    /// This step's pushing pairs while they are read (kept for its memory).
    pushing_now: HashSet<(ColliderHandle, ColliderHandle)>,
    /// The pairs read this step (kept for its memory).
    read: HashSet<(ColliderHandle, ColliderHandle)>,
}

impl ImpactReader {
    /// No pair pushing yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// The impacts of the step just taken between `colliders` (those the adapter knows:
    /// dentable, projectile and bendable colliders) and anything, world coordinates at the start
    /// of the step (`states`' poses; a collider on a fixed body or none at its pose now).
    /// Cost: the pairs of `colliders` only.
    pub fn read(
        &mut self,
        narrow_phase: &NarrowPhase,
        colliders: impl IntoIterator<Item = ColliderHandle>,
        states: &BodyStates,
        bodies: &RigidBodySet,
        set: &ColliderSet,
    ) -> Vec<Contact> {
        self.pushing_now.clear();
        self.read.clear();
        let mut out = Vec::new();
        for handle in colliders {
            for pair in narrow_phase.contact_pairs_with(handle) {
                // A pair of two known colliders is met from both: read once.
                let key = (pair.collider1, pair.collider2);
                if !self.read.insert(key) {
                    continue;
                }
                // A pair whose contact cannot be placed (a moving collider added after the
                // states were recorded) is not marked: its impact starts on the next step.
                let pose = |h| states.collider_pose(h).or_else(|| still_pose(h, bodies, set));
                let (Some(pose1), Some(pose2)) = (pose(pair.collider1), pose(pair.collider2)) else { continue };
                if let Some(contact) = pair_contact(pair, !self.pushing.contains(&key), pose1, pose2) {
                    self.pushing_now.insert(key);
                    out.push(contact);
                }
            }
        }
        std::mem::swap(&mut self.pushing, &mut self.pushing_now);
        out
    }
}

impl EventHandler for ImpactCollector {
    fn handle_collision_event(&self, _: &RigidBodySet, _: &ColliderSet, _: CollisionEvent, _: Option<&ContactPair>) {}

    fn handle_contact_force_event(
        &self,
        dt: Real,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        pair: &ContactPair,
        total_force_magnitude: Real,
    ) {
        let started = ContactForceEvent::from_contact_pair(dt, pair, total_force_magnitude).started;
        if let Some(raw) = raw_impact(pair, started, bodies, colliders) {
            self.raw.lock().unwrap_or_else(|e| e.into_inner()).push(raw);
        }
    }

    fn handle_soft_body_tear_event(&self, _: &SoftBodySet, _: &SoftBodyTearEvent) {}
}

/// Calls `visit` with each contact of `pair`'s solver manifolds that pushed (point on 1 in
/// 1's frame, point on 2 in 2's frame, normal impulse N·s), in order; returns the world normal
/// (1 → 2) of the manifold that pushed most, `None` when none pushed.
fn pushed_contacts(pair: &ContactPair, mut visit: impl FnMut(Vec3, Vec3, f32)) -> Option<Vec3> {
    let (mut best, mut normal, mut any) = (0.0, Vec3::ZERO, false);
    for m in pair.solver_manifolds() {
        let total: f32 = m.contacts().iter().map(|c| c.data.impulse.max(0.0)).sum();
        if total > best {
            (best, normal) = (total, m.data.normal);
        }
        for c in m.contacts().iter().filter(|c| c.data.impulse > 0.0) {
            any = true;
            visit(c.local_p1, c.local_p2, c.data.impulse);
        }
    }
    any.then_some(normal)
}

/// The pose of collider `h` when it cannot move (no body, or a fixed one).
fn still_pose(h: ColliderHandle, bodies: &RigidBodySet, colliders: &ColliderSet) -> Option<Affine3A> {
    let c = colliders.get(h)?;
    let fixed = c.parent().is_none_or(|b| bodies.get(b).is_none_or(|rb| rb.is_fixed()));
    fixed.then(|| crate::to_affine(c.position()))
}

/// The contacts of `pair`'s solver manifolds that pushed, and the normal of the manifold that
/// pushed most; `None` when none pushed.
fn raw_impact(pair: &ContactPair, started: bool, bodies: &RigidBodySet, colliders: &ColliderSet) -> Option<RawImpact> {
    let mut points = Vec::new();
    let normal = pushed_contacts(pair, |p1, p2, j| points.push((p1, p2, j)))?;
    Some(RawImpact {
        collider1: pair.collider1,
        collider2: pair.collider2,
        points,
        normal,
        started,
        still: [still_pose(pair.collider1, bodies, colliders), still_pose(pair.collider2, bodies, colliders)],
    })
}

/// `pair`'s impact at the colliders' poses `pose1` and `pose2`, as [`world_contact`] makes it,
/// without gathering its contacts first; `None` when none pushed.
fn pair_contact(pair: &ContactPair, started: bool, pose1: Affine3A, pose2: Affine3A) -> Option<Contact> {
    let mut sum = Weighted::default();
    let normal = pushed_contacts(pair, |p1, p2, j| sum.add(pose1, pose2, p1, p2, j))?;
    Some(sum.contact(pair.collider1, pair.collider2, normal, started))
}

/// The impulse-weighted sum of the midpoints of two colliders' contact points.
#[derive(Default)]
struct Weighted {
    impulse: f32,
    point: Vec3,
}

impl Weighted {
    /// Adds the contact between `p1` (1's frame, at `pose1`) and `p2` (2's frame, at `pose2`)
    /// with impulse `j`, N·s.
    fn add(&mut self, pose1: Affine3A, pose2: Affine3A, p1: Vec3, p2: Vec3, j: f32) {
        self.impulse += j;
        self.point += 0.5 * (pose1.transform_point3(p1) + pose2.transform_point3(p2)) * j;
    }

    /// The contact at the weighted mean point.
    fn contact(self, collider1: ColliderHandle, collider2: ColliderHandle, normal: Vec3, started: bool) -> Contact {
        Contact { collider1, collider2, point: self.point / self.impulse, normal, impulse: self.impulse, started }
    }
}

/// `raw` in world coordinates from `states`' poses (a still collider's own); `None` when a
/// moving collider was not recorded.
fn to_contact(raw: &RawImpact, states: &BodyStates) -> Option<Contact> {
    let pose1 = states.collider_pose(raw.collider1).or(raw.still[0])?;
    let pose2 = states.collider_pose(raw.collider2).or(raw.still[1])?;
    Some(world_contact(raw, pose1, pose2))
}

/// `raw` at the colliders' poses `pose1` and `pose2`: the impulse-weighted mean of the
/// midpoints of the two colliders' contact points.
fn world_contact(raw: &RawImpact, pose1: Affine3A, pose2: Affine3A) -> Contact {
    let mut sum = Weighted::default();
    for &(p1, p2, j) in &raw.points {
        sum.add(pose1, pose2, p1, p2, j);
    }
    sum.contact(raw.collider1, raw.collider2, raw.normal, raw.started)
}
