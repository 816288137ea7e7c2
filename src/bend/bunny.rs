//! The four-bone skeleton of the built-in Stanford bunny (paper Figure 12): a body bone, a head
//! bone that leaves the body behind the neck and comes back in at the head, and one bone per ear.
//! The one place it is defined; the `bunny-bones` scene, the tests and the benches use it.

use glam::Vec3;

use super::{BendError, BoneDesc, Skeleton};

/// Index of the body (back) bone, the root.
pub const BUNNY_BODY: usize = 0;
/// Index of the head bone: from the top of the back to the head, poking out behind the neck.
pub const BUNNY_HEAD: usize = 1;
/// Index of the bunny's right ear (−z side, standing up), a child of the head.
pub const BUNNY_RIGHT_EAR: usize = 2;
/// Index of the bunny's left ear (laid back towards the tail), a child of the head.
pub const BUNNY_LEFT_EAR: usize = 3;

/// Head, tail and parent of each bone in the built-in bunny's model frame (`mesh::builtin("bunny")`:
/// about 10 across, y up from 0 to 9.66, the nose towards −x), m.
const BONES: [([f32; 3], [f32; 3], Option<usize>); 4] = [
    ([2.0, 2.5, 0.8], [0.5, 5.6, 0.8], None),
    ([0.5, 5.6, 0.8], [-3.3, 7.4, 0.8], Some(BUNNY_BODY)),
    ([-3.3, 7.6, 0.2], [-3.43, 9.0, -3.0], Some(BUNNY_HEAD)),
    ([-2.0, 7.6, 0.3], [-0.45, 9.1, -0.9], Some(BUNNY_HEAD)),
];

/// The bunny's four bones for the built-in bunny scaled uniformly by `scale` about the origin
/// (the same scale as the mesh's), m.
///
/// # Errors
/// [`BendError::InvalidParameter`] for a scale that is not finite and positive.
///
/// # Example
/// ```
/// use dentbend::bend::{BUNNY_HEAD, Skeleton, bunny_bones};
/// let bunny = dentbend::mesh::builtin("bunny").unwrap();
/// let skeleton = Skeleton::new(bunny_bones(1.0).unwrap()).unwrap();
/// skeleton.check_against(&bunny).unwrap(); // the head bone pokes out, which is allowed
/// assert_eq!(skeleton.children(BUNNY_HEAD), vec![2, 3]);
/// ```
pub fn bunny_bones(scale: f32) -> Result<Vec<BoneDesc>, BendError> {
    if !(scale.is_finite() && scale > 0.0) {
        let value = scale.to_string();
        return Err(BendError::InvalidParameter { name: "scale", value, reason: "must be finite and > 0" });
    }
    Ok(BONES
        .iter()
        .map(|&(head, tail, parent)| {
            BoneDesc::new(Vec3::from_array(head) * scale, Vec3::from_array(tail) * scale, parent)
        })
        .collect())
}

/// The bunny's skeleton for the built-in bunny scaled by `scale`; see [`bunny_bones`].
///
/// # Errors
/// As [`bunny_bones`].
pub fn bunny_skeleton(scale: f32) -> Result<Skeleton, BendError> {
    Skeleton::new(bunny_bones(scale)?)
}
