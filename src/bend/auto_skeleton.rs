//! A skeleton for elongated bodies without an artist: a chain of bones along the principal axis
//! of the body's volume (planks, bars, cylinders, the paper's Figure 14).

use super::{BendError, BoneDesc, Skeleton};
use crate::mesh::TriMesh;
use crate::mesh::principal_axis;

/// Most bones [`auto_skeleton`] makes.
pub const MAX_AUTO_BONES: usize = 256;
/// Fraction of the body's length left free at each end of the chain.
pub(crate) const AUTO_INSET: f32 = 0.05;

/// A chain of `bones` equal bones along the principal axis of `mesh`.
///
/// The axis is the direction of largest second moment of the enclosed volume about its centroid
/// (principal component of the solid; the vertices' for an open or flat mesh), through the
/// centroid, oriented so its largest component is positive. The chain spans the mesh's extent
/// along the axis, inset by 5 % of it at each end; bone 0 is the root at the
/// negative end and bone i+1 is bone i's child.
///
/// # Errors
/// [`BendError::InvalidParameter`] for `bones` outside 1..=[`MAX_AUTO_BONES`] or a mesh with no
/// extent (all vertices coincide).
///
/// # Example
/// ```
/// let plank = dentbend::mesh::builtin("plank").unwrap(); // 8 long along x
/// let skeleton = dentbend::bend::auto_skeleton(&plank, 4).unwrap();
/// assert_eq!(skeleton.len(), 4);
/// assert!((skeleton.bones()[0].head.x + 3.6).abs() < 1e-3);
/// ```
pub fn auto_skeleton(mesh: &TriMesh, bones: usize) -> Result<Skeleton, BendError> {
    if !(1..=MAX_AUTO_BONES).contains(&bones) {
        let value = bones.to_string();
        return Err(BendError::InvalidParameter { name: "bones", value, reason: "must be in 1..=256" });
    }
    let (centre, axis) = principal_axis(mesh).ok_or_else(|| BendError::InvalidParameter {
        name: "mesh",
        value: format!("{} vertices", mesh.vertex_count()),
        reason: "has no extent: its vertices coincide",
    })?;
    let (lo, hi) = mesh
        .positions()
        .iter()
        .map(|&p| (p - centre).dot(axis))
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), s| (lo.min(s), hi.max(s)));
    let inset = AUTO_INSET * (hi - lo);
    let (start, end) = (lo + inset, hi - inset);
    let point = |i: usize| centre + axis * (start + (end - start) * i as f32 / bones as f32);
    let descs = (0..bones).map(|i| BoneDesc::new(point(i), point(i + 1), i.checked_sub(1))).collect();
    Skeleton::new(descs)
}
