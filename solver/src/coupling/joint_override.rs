//! Joints of a bending body with their own kind: most of a body's joints share
//! [`BendableDesc::joint`](super::BendableDesc::joint), and a few are given another (paper
//! Figure 15: an armadillo whose body holds while four joints of its right arm bend).

use crate::sim::{JointKind, SimError};
use dentbend::bend::Skeleton;

/// The joint at bone `child`'s head (where it hangs from its parent) made of kind `joint`
/// instead of the body's [`joint`](super::BendableDesc::joint).
///
/// # Example
/// ```
/// use dentbend_solver::coupling::{BendableDesc, JointOverride, SkeletonSpec};
/// use dentbend_solver::sim::JointKind;
/// let mut desc = BendableDesc::new("bar", dentbend::mesh::plank(2.0, 0.2, 0.2, 16).unwrap());
/// desc.skeleton = SkeletonSpec::Auto { bones: 3 };
/// desc.joint_overrides = vec![JointOverride { child: 2, joint: JointKind::Ball }];
/// assert_eq!(desc.joint_kind(1), JointKind::Rigid);
/// assert_eq!(desc.joint_kind(2), JointKind::Ball);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointOverride {
    /// Index of the joint's child bone in the skeleton (a bone with a parent).
    pub child: usize,
    /// The joint's kind.
    pub joint: JointKind,
}

/// Kind of the joint at bone `child`'s head: its override in `overrides`, or `default`.
pub(super) fn kind_of(overrides: &[JointOverride], default: JointKind, child: usize) -> JointKind {
    overrides.iter().find(|o| o.child == child).map_or(default, |o| o.joint)
}

/// Checks the numbers of bendable body `body`'s `overrides` and that no bone has two.
///
/// # Errors
/// [`SimError::Invalid`] naming the first bad override.
pub(super) fn validate(overrides: &[JointOverride], body: &str) -> Result<(), SimError> {
    for (k, o) in overrides.iter().enumerate() {
        let what = format!("bendable body \"{body}\": joint_overrides[{k}]");
        o.joint.validate().map_err(|e| match e {
            // "joint strength" → "joint_overrides[k].joint.strength".
            SimError::Invalid { what: field, value, reason } => SimError::Invalid {
                what: format!("{what}.joint.{}", field.strip_prefix("joint ").unwrap_or(&field)),
                value,
                reason,
            },
            other => other,
        })?;
        if overrides[..k].iter().any(|earlier| earlier.child == o.child) {
            return Err(SimError::Invalid {
                what: format!("{what}.child"),
                value: o.child.to_string(),
                reason: "gives that joint a second kind",
            });
        }
    }
    Ok(())
}

/// Checks that each of bendable body `body`'s `overrides` names a joint of `skeleton`: a bone
/// in range that has a parent.
///
/// # Errors
/// [`SimError::Invalid`] naming the first override that does not.
pub(super) fn check_against(overrides: &[JointOverride], skeleton: &Skeleton, body: &str) -> Result<(), SimError> {
    for (k, o) in overrides.iter().enumerate() {
        let reason = match skeleton.bone(o.child) {
            None => "is not a bone of the skeleton",
            Some(bone) if bone.parent.is_none() => "is the root bone, which hangs from no joint",
            Some(_) => continue,
        };
        return Err(SimError::Invalid {
            what: format!("bendable body \"{body}\": joint_overrides[{k}].child"),
            value: format!("{} (of {} bones)", o.child, skeleton.len()),
            reason,
        });
    }
    Ok(())
}
