//! Narrow phase: contact manifolds of overlapping pairs through parry3d, in world coordinates.

use glam::Vec3;
use parry3d::math::Pose;
use parry3d::query::{ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher};
use rayon::prelude::*;

use super::RigidBody;

/// One contact point of a pair (a, b).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ContactPoint {
    /// Closest point on a, world, m.
    pub on_a: Vec3,
    /// Closest point on b, world, m.
    pub on_b: Vec3,
    /// Unit normal from a towards b, world.
    pub normal: Vec3,
    /// Signed distance along the normal, m (negative when the bodies overlap).
    pub distance: f32,
    /// Which part of a composite collider of a (a compound's shape, a mesh's triangle) the point
    /// is on; 0 for simple shapes.
    pub part_a: u32,
    /// The same for b.
    pub part_b: u32,
}

impl ContactPoint {
    /// The midpoint of the two closest points, world, m.
    pub fn point(&self) -> Vec3 {
        0.5 * (self.on_a + self.on_b)
    }
}

/// The contact points of one pair.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PairContacts {
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

/// Contacts of every pair closer than `prediction(a, b)` metres, pairs with no point dropped.
/// Pairs run in parallel; the result keeps the order of `pairs`.
pub(crate) fn find_contacts(
    bodies: &[RigidBody],
    pairs: &[(usize, usize)],
    prediction: impl Fn(usize, usize) -> f32 + Sync,
) -> Vec<PairContacts> {
    pairs
        .par_iter()
        .filter_map(|&(a, b)| {
            let points = pair_points(&bodies[a], &bodies[b], prediction(a, b));
            (!points.is_empty()).then_some(PairContacts { a, b, points })
        })
        .collect()
}

/// The manifold points of bodies a and b within `prediction` metres.
fn pair_points(a: &RigidBody, b: &RigidBody, prediction: f32) -> Vec<ContactPoint> {
    let (pose_a, pose_b) = (pose(a), pose(b));
    let pose_ab = pose_a.inv_mul(&pose_b);
    let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
    let mut workspace = None;
    let dispatcher = DefaultQueryDispatcher;
    if dispatcher
        .contact_manifolds(&pose_ab, a.shape.as_ref(), b.shape.as_ref(), prediction, &mut manifolds, &mut workspace)
        .is_err()
    {
        log::warn!("no contact algorithm between the colliders of \"{}\" and \"{}\"", a.name, b.name);
        return Vec::new();
    }
    let mut points = Vec::new();
    for manifold in &manifolds {
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
                part_a: manifold.subshape1,
                part_b: manifold.subshape2,
            });
        }
    }
    points
}
