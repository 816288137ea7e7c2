//! Scaled entities (common in glTF imports): the plug-in keeps a dentable's or projectile's mesh
//! with its entity's scale baked in, so that dents are sized in metres and poses are rigid, and
//! writes the dented mesh back into the asset without it (Bevy scales the asset, bevy_rapier3d
//! the collider).

use std::borrow::Cow;

use bevy::prelude::*;
use dentbend::TriMesh;
use dentbend::glam::Affine3A;
use dentbend::mesh::MeshError;

/// Per-axis scales this close to 1 count as unscaled.
const UNIT_SCALE_TOLERANCE: f32 = 1e-4;
/// Smallest per-axis scale served, and largest ratio between two axes.
const SCALE_LIMITS: (f32, f32) = (1e-4, 1e4);

/// The scale of `transform`, `None` when it is 1 on every axis.
///
/// # Errors
/// A scale that is not finite, mirrors (negative), is below 1e-4 or whose axes differ by more
/// than 1e4 times: the reason and the fix.
pub(crate) fn entity_scale(transform: &GlobalTransform) -> Result<Option<Vec3>, String> {
    let scale = transform.to_scale_rotation_translation().0;
    if !scale.is_finite() || scale.min_element() <= 0.0 {
        return Err(format!("it is scaled by {scale}, which mirrors or flattens it (bake the scale into its mesh)"));
    }
    if scale.min_element() < SCALE_LIMITS.0 || scale.max_element() > SCALE_LIMITS.1 * scale.min_element() {
        return Err(format!("its scale {scale} is out of the range served (bake the scale into its mesh)"));
    }
    Ok(((scale - Vec3::ONE).abs().max_element() > UNIT_SCALE_TOLERANCE).then_some(scale))
}

/// Why a body of this `transform` cannot take part where scales are not served (bendable
/// bodies, a collider standing for a mesh on another entity): its bones or contacts are sized in
/// its mesh's own coordinates, which a scale would stretch.
pub(crate) fn scale_refusal(transform: &GlobalTransform) -> Option<String> {
    match entity_scale(transform) {
        Ok(None) => None,
        Ok(Some(scale)) => Some(format!("it is scaled by {scale} (bake the scale into its mesh)")),
        Err(reason) => Some(reason),
    }
}

/// `transform` without its scale: mesh coordinates (scale baked in) → world.
pub(crate) fn rigid(transform: &GlobalTransform) -> Affine3A {
    rigid_pose(transform.affine())
}

/// `pose` without its scale (a contact's pose given with one).
pub(crate) fn rigid_pose(pose: Affine3A) -> Affine3A {
    let (_, rotation, translation) = pose.to_scale_rotation_translation();
    Affine3A::from_rotation_translation(rotation, translation)
}

/// `tri` scaled by `scale` (its normals by the inverse, renormalized).
///
/// # Errors
/// A scaled vertex out of range.
pub(crate) fn scaled(tri: &TriMesh, scale: Vec3) -> Result<TriMesh, MeshError> {
    map(tri, scale, scale.recip())
}

/// `tri` with `scale` taken out (for the asset Bevy scales again).
///
/// # Errors
/// As [`scaled`].
fn unscaled(tri: &TriMesh, scale: Vec3) -> Result<TriMesh, MeshError> {
    map(tri, scale.recip(), scale)
}

/// `tri` as the asset holds it: without `scale` (the entity's, baked into `tri`), or `tri`
/// itself for an unscaled body.
///
/// # Errors
/// As [`scaled`].
pub(crate) fn for_asset(tri: &TriMesh, scale: Option<Vec3>) -> Result<Cow<'_, TriMesh>, MeshError> {
    match scale {
        Some(s) => unscaled(tri, s).map(Cow::Owned),
        None => Ok(Cow::Borrowed(tri)),
    }
}

fn map(tri: &TriMesh, positions_by: Vec3, normals_by: Vec3) -> Result<TriMesh, MeshError> {
    let positions = tri.positions().iter().map(|&p| p * positions_by).collect();
    let normals = tri.normals().iter().map(|&n| (n * normals_by).normalize_or_zero()).collect();
    TriMesh::with_normals(positions, tri.faces().to_vec(), normals)
}
