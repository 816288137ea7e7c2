//! What can go wrong when a body breaks.

/// Everything a fracture can refuse; the caller's mesh and body are unchanged then.
#[derive(Debug, thiserror::Error)]
pub enum FractureError {
    /// A pattern or setting field is NaN, infinite, negative or out of its range.
    #[error("invalid fracture parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// Field name, as in [`PatternParams`](super::PatternParams) or
        /// [`FractureSettings`](super::FractureSettings).
        name: &'static str,
        /// The value given, formatted.
        value: String,
        /// The range accepted.
        reason: &'static str,
    },
    /// The placement's point or normal is not finite, or the normal is zero.
    #[error("invalid fracture placement: {0}")]
    InvalidPlacement(String),
    /// The mesh is not closed: an edge is not shared by exactly two faces of opposite
    /// orientation (after welding coincident vertices), so it bounds no solid to break.
    #[error("the mesh is not closed: edge ({a}, {b}) is used by {count} face(s) in that direction")]
    OpenMesh {
        /// First vertex of the edge (welded index).
        a: u32,
        /// Second vertex.
        b: u32,
        /// How many faces use the edge from `a` to `b` (1 is closed when one face goes back).
        count: usize,
    },
    /// The break would make more pieces than the body's settings allow: it is refused and the
    /// body stays whole.
    #[error(
        "the break would make {pieces} pieces, more than the limit of {limit}: raise FractureSettings::max_pieces \
         (`max_pieces` in a scene file) or use a pattern with fewer cells"
    )]
    TooManyPieces {
        /// Pieces the break would make.
        pieces: usize,
        /// The settings' limit.
        limit: u32,
    },
    /// A piece or the rest came out unusable (a mesh error while building it): a bug.
    #[error("fracture produced an invalid mesh: {0}")]
    Mesh(#[from] crate::mesh::MeshError),
}

/// An [`FractureError::InvalidParameter`].
pub(crate) fn invalid(name: &'static str, value: impl std::fmt::Display, reason: &'static str) -> FractureError {
    FractureError::InvalidParameter { name, value: value.to_string(), reason }
}
