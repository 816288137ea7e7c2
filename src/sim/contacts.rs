//! Narrow phase: contact manifolds of overlapping pairs through parry3d, in world coordinates.

use std::collections::HashMap;

use glam::Vec3;
use parry3d::math::Pose;
use parry3d::query::{ContactManifold, ContactManifoldsWorkspace, DefaultQueryDispatcher, PersistentQueryDispatcher};
use rayon::prelude::*;

use super::RigidBody;

/// One contact point of a pair (a, b).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPoint {
    /// Closest point on a, world, m.
    pub on_a: Vec3,
    /// Closest point on b, world, m.
    pub on_b: Vec3,
    /// Unit normal from a towards b, world.
    pub normal: Vec3,
    /// Signed distance along the normal, m (negative when the bodies overlap).
    pub distance: f32,
}

impl ContactPoint {
    /// The midpoint of the two closest points, world, m.
    pub fn point(&self) -> Vec3 {
        0.5 * (self.on_a + self.on_b)
    }
}

/// The contact points of one pair.
#[derive(Debug, Clone, PartialEq)]
pub struct PairContacts {
    /// Index of body a.
    pub a: usize,
    /// Index of body b (> a).
    pub b: usize,
    /// Its points (several for face contacts, from one or more manifolds).
    pub points: Vec<ContactPoint>,
}

/// The body's collider pose.
pub(crate) fn pose(body: &RigidBody) -> Pose {
    Pose::from_parts(body.position, body.orientation)
}

/// What parry keeps for one pair between steps: its manifolds and its workspace (for a triangle
/// mesh, the triangles near the other body, re-queried only when that body leaves a loosened
/// box), valid while neither collider changes shape.
#[derive(Default)]
pub(crate) struct PairCache {
    manifolds: Vec<ContactManifold<(), ()>>,
    workspace: Option<ContactManifoldsWorkspace>,
    versions: (u64, u64),
}

/// Per-pair narrow-phase caches, kept by the world from one step to the next.
#[derive(Default)]
pub(crate) struct NarrowPhaseCache {
    pairs: HashMap<(usize, usize), PairCache>,
}

impl std::fmt::Debug for NarrowPhaseCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NarrowPhaseCache").field("pairs", &self.pairs.len()).finish()
    }
}

impl Clone for NarrowPhaseCache {
    /// A clone starts cold: parry's workspaces cannot be cloned, and are only a speed-up.
    fn clone(&self) -> Self {
        Self::default()
    }
}

/// Contacts of every pair closer than `prediction(a, b)` metres, pairs with no point dropped.
/// Pairs run in parallel; the result keeps the order of `pairs`.
pub fn find_contacts(
    bodies: &[RigidBody],
    pairs: &[(usize, usize)],
    prediction: impl Fn(usize, usize) -> f32 + Sync,
) -> Vec<PairContacts> {
    find_contacts_cached(bodies, pairs, prediction, &mut NarrowPhaseCache::default())
}

/// [`find_contacts`] reusing last step's per-pair caches; afterwards `cache` holds this step's
/// pairs only.
pub(crate) fn find_contacts_cached(
    bodies: &[RigidBody],
    pairs: &[(usize, usize)],
    prediction: impl Fn(usize, usize) -> f32 + Sync,
    cache: &mut NarrowPhaseCache,
) -> Vec<PairContacts> {
    let versions = |a: usize, b: usize| (bodies[a].shape_version, bodies[b].shape_version);
    let mut states: Vec<PairCache> = pairs
        .iter()
        .map(|&(a, b)| {
            let fresh = PairCache { versions: versions(a, b), ..PairCache::default() };
            cache.pairs.remove(&(a, b)).filter(|state| state.versions == fresh.versions).unwrap_or(fresh)
        })
        .collect();
    let found = pairs
        .par_iter()
        .zip(states.par_iter_mut())
        .map(|(&(a, b), state)| {
            let points = pair_points(&bodies[a], &bodies[b], prediction(a, b), state);
            (!points.is_empty()).then_some(PairContacts { a, b, points })
        })
        .collect::<Vec<_>>()
        .into_iter()
        .flatten()
        .collect();
    cache.pairs = pairs.iter().copied().zip(states).collect();
    found
}

/// The manifold points of bodies a and b within `prediction` metres.
fn pair_points(a: &RigidBody, b: &RigidBody, prediction: f32, state: &mut PairCache) -> Vec<ContactPoint> {
    let (pose_a, pose_b) = (pose(a), pose(b));
    let pose_ab = pose_a.inv_mul(&pose_b);
    let dispatcher = DefaultQueryDispatcher;
    let PairCache { manifolds, workspace, .. } = state;
    if dispatcher
        .contact_manifolds(&pose_ab, a.shape.as_ref(), b.shape.as_ref(), prediction, manifolds, workspace)
        .is_err()
    {
        log::warn!("no contact algorithm between the colliders of \"{}\" and \"{}\"", a.name, b.name);
        return Vec::new();
    }
    let mut points = Vec::new();
    for manifold in manifolds.iter() {
        // Points and normals are in each shape's frame, or its sub-shape's for composite shapes.
        let frame_a = manifold.subshape_pos1().map_or(pose_a, |sub| pose_a * *sub);
        let frame_b = manifold.subshape_pos2().map_or(pose_b, |sub| pose_b * *sub);
        let normal = frame_a.transform_vector(manifold.local_n1).normalize_or_zero();
        if normal == Vec3::ZERO {
            continue;
        }
        for contact in &manifold.points {
            points.push(ContactPoint {
                on_a: frame_a.transform_point(contact.local_p1),
                on_b: frame_b.transform_point(contact.local_p2),
                normal,
                distance: contact.dist,
            });
        }
    }
    points
}
