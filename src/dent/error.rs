//! Errors raised while building dent maps and applying them.

use crate::mesh::MeshError;

/// Everything that can go wrong between an impact and a dented mesh.
///
/// Every entry point validates its input before touching a mesh, so an error always leaves the
/// caller's meshes unchanged.
#[derive(Debug, thiserror::Error)]
pub enum DentError {
    /// A [`DentParams`](super::DentParams) field is out of range.
    #[error("invalid dent parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// Field name, as in `DentParams`.
        name: &'static str,
        /// The value given, formatted.
        value: String,
        /// What range is accepted.
        reason: &'static str,
    },
    /// An [`Impact`](super::Impact) field is unusable (non-finite, zero normal).
    #[error("invalid impact: {0}")]
    InvalidImpact(String),
    /// The relative velocity points away from the target: the bodies are separating.
    #[error("the projectile moves away from the target (velocity·normal = {normal_speed} m/s); nothing to dent")]
    Separating {
        /// Relative velocity component along the denting normal, m/s (negative).
        normal_speed: f32,
    },
    /// The whole projectile lies beyond the collision plane, inside the target's half-space.
    #[error("the projectile lies entirely behind the collision plane (its nearest point is {distance} units past it)")]
    ProjectileBehindPlane {
        /// Distance of the projectile's rearmost point past the plane, world units.
        distance: f32,
    },
    /// The projectile has no area: every triangle is degenerate.
    #[error("the projectile is degenerate: its triangles have zero total area")]
    DegenerateProjectile,
    /// The target has no area: every triangle is degenerate (all its vertices on a line or a
    /// point), so it has no surface to dent.
    #[error("the target is degenerate: its triangles have zero total area, so it has no surface to dent")]
    DegenerateTarget,
    /// Nothing is left of the profile: σ or d is far outside the projectile's scale.
    #[error(
        "the projectile leaves no imprint: its profile vanished on the dent grid (check sigma and dent_distance against its size)"
    )]
    EmptyProfile,
    /// A mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// An artist dent map image could not be read or has an unsupported layout.
    #[error("dent map image {path}: {message}")]
    Image {
        /// The image file.
        path: std::path::PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A body's state ([`BodyState`](super::BodyState)) is unusable: non-finite, negative mass.
    #[error("body {body}: {field} = {value} is invalid")]
    InvalidBody {
        /// Which body (the caller's id, formatted, or "target" / "projectile").
        body: String,
        /// The field.
        field: String,
        /// The value given, formatted.
        value: String,
    },
    /// The batch's backend failed (a GPU device lost or out of memory mid-batch).
    #[error("dent backend: {0}")]
    Backend(String),
    /// Two vertices under the dent nearly share a position without sharing it exactly: a seam
    /// (hard edge, UV seam) whose sides no stage can keep together. Weld the mesh's seams so that
    /// their vertices' positions are bit-identical.
    #[error(
        "vertices {a} and {b} lie {distance:e} apart under the dent: a seam whose sides nearly but not exactly \
         coincide would crack open; snap its vertices to bit-identical positions (weld the seam) before denting"
    )]
    NearlyCoincidentVertices {
        /// One vertex.
        a: u32,
        /// The other.
        b: u32,
        /// Their distance, world units.
        distance: f32,
    },
    /// Applying the map would move a vertex out of finite space or beyond
    /// [`MAX_COORDINATE`](crate::mesh::MAX_COORDINATE); the mesh is left unchanged.
    #[error(
        "the dent would move vertex {index} to a non-finite position or beyond ±1e6, the supported coordinate range"
    )]
    NonFiniteResult {
        /// Index of the vertex.
        index: usize,
    },
}

/// Builds an [`DentError::InvalidParameter`].
pub(crate) fn invalid(name: &'static str, value: impl std::fmt::Display, reason: &'static str) -> DentError {
    DentError::InvalidParameter { name, value: value.to_string(), reason }
}
