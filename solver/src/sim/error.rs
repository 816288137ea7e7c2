//! Errors of the simulation core.

use dentbend::dent::DentError;
use dentbend::mesh::MeshError;

/// What went wrong building or stepping a [`World`](super::World).
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// A body description or a world setting is out of range (NaN, ∞, negative mass…).
    #[error("{what}: {value} {reason}")]
    Invalid {
        /// The offending field, e.g. `body "left": density`.
        what: String,
        /// Its value, printed.
        value: String,
        /// Why it was refused.
        reason: &'static str,
    },
    /// A body's mesh cannot serve for mass properties or a collider.
    #[error("body \"{body}\": {reason}")]
    BadShape {
        /// The body's name.
        body: String,
        /// Why.
        reason: String,
    },
    /// A mesh operation failed.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Denting a body failed.
    #[error("denting body \"{body}\": {error}")]
    Dent {
        /// The dented body's name.
        body: String,
        /// The dent pipeline's error.
        #[source]
        error: DentError,
    },
    /// A body's fracture settings are out of range, or breaking it failed.
    #[error("fracture of body \"{body}\": {error}")]
    Fracture {
        /// The body's name.
        body: String,
        /// What the fracture refused.
        #[source]
        error: dentbend::fracture::FractureError,
    },
    /// The GPU dent batch failed.
    #[error("GPU denting: {0}")]
    Gpu(String),
    /// Skinning the bending bodies on the GPU failed (a device error or an upload over the
    /// device's limits).
    #[error("GPU skinning: {0}")]
    GpuSkinning(String),
}

/// A [`SimError::Invalid`] for `what` = `value`.
pub(crate) fn invalid(what: impl Into<String>, value: impl std::fmt::Debug, reason: &'static str) -> SimError {
    SimError::Invalid { what: what.into(), value: format!("{value:?}"), reason }
}
