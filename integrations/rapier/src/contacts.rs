//! Contacts from Rapier's solver, one per impact.
//!
//! Which contacts count as impacts: Rapier's [`ContactForceEvent::started`] is true on the step
//! a pair's total contact force first exceeds the collider's
//! `contact_force_event_threshold` (coming from below or from not touching). With
//! [`ActiveEvents::CONTACT_FORCE_EVENTS`] and a threshold of 0 N that is the first step a pair
//! pushes, and again after every bounce: one dent per impact, none while a body rests. The
//! collector keeps the other force events too, flagged not `started`: progressive targets
//! (paper Figure 3) deepen their dent on every step a push goes on above the dent threshold.
//! The contact itself comes from the pair's *solver* manifolds (Rapier may cluster manifolds;
//! only the solver's carry impulses): the impulse-weighted mean of the contacts that pushed.

use std::sync::Mutex;

use glam::Vec3;
use rapier3d::prelude::{
    ColliderHandle, ColliderSet, CollisionEvent, ContactForceEvent, ContactPair, EventHandler, Real, RigidBodySet,
    SoftBodySet, SoftBodyTearEvent,
};

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

impl EventHandler for ImpactCollector {
    fn handle_collision_event(&self, _: &RigidBodySet, _: &ColliderSet, _: CollisionEvent, _: Option<&ContactPair>) {}

    fn handle_contact_force_event(
        &self,
        dt: Real,
        _: &RigidBodySet,
        _: &ColliderSet,
        pair: &ContactPair,
        total_force_magnitude: Real,
    ) {
        let started = ContactForceEvent::from_contact_pair(dt, pair, total_force_magnitude).started;
        if let Some(raw) = raw_impact(pair, started) {
            self.raw.lock().unwrap_or_else(|e| e.into_inner()).push(raw);
        }
    }

    fn handle_soft_body_tear_event(&self, _: &SoftBodySet, _: &SoftBodyTearEvent) {}
}

/// The contacts of `pair`'s solver manifolds that pushed, and the normal of the manifold that
/// pushed most; `None` when none pushed.
fn raw_impact(pair: &ContactPair, started: bool) -> Option<RawImpact> {
    let mut points = Vec::new();
    let (mut best, mut normal) = (0.0, Vec3::ZERO);
    for m in pair.solver_manifolds() {
        let total: f32 = m.contacts().iter().map(|c| c.data.impulse.max(0.0)).sum();
        if total > best {
            (best, normal) = (total, m.data.normal);
        }
        points.extend(
            m.contacts().iter().filter(|c| c.data.impulse > 0.0).map(|c| (c.local_p1, c.local_p2, c.data.impulse)),
        );
    }
    (!points.is_empty()).then_some(RawImpact {
        collider1: pair.collider1,
        collider2: pair.collider2,
        points,
        normal,
        started,
    })
}

/// `raw` in world coordinates: the impulse-weighted mean of the midpoints of the two
/// colliders' contact points.
fn to_contact(raw: &RawImpact, states: &BodyStates) -> Option<Contact> {
    let pose1 = states.collider_pose(raw.collider1)?;
    let pose2 = states.collider_pose(raw.collider2)?;
    let impulse: f32 = raw.points.iter().map(|p| p.2).sum();
    let point = raw.points.iter().fold(Vec3::ZERO, |acc, (p1, p2, j)| {
        acc + 0.5 * (pose1.transform_point3(*p1) + pose2.transform_point3(*p2)) * *j
    }) / impulse;
    Some(Contact {
        collider1: raw.collider1,
        collider2: raw.collider2,
        point,
        normal: raw.normal,
        impulse,
        started: raw.started,
    })
}
