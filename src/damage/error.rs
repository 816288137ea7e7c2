//! What can go wrong planning a step's damage.

use crate::dent::DentError;
use crate::fracture::FractureError;

/// What went wrong in [`Damage::plan`](super::Damage::plan); nothing of the caller's changed.
#[derive(Debug, thiserror::Error)]
pub enum DamageError {
    /// A hit names a body the caller does not have (removed between steps?).
    #[error("hit {hit}: unknown body {body}")]
    UnknownBody {
        /// Index of the hit.
        hit: usize,
        /// The id, formatted.
        body: String,
    },
    /// A hit's contact or body states are unusable (NaN, ∞, zero normal), or its dent failed
    /// ([`DentError::Backend`] when the backend did: a GPU lost mid-batch).
    #[error("hit {hit} (target {target}): {error}")]
    Dent {
        /// Index of the hit.
        hit: usize,
        /// The target's id, formatted.
        target: String,
        /// What was wrong.
        #[source]
        error: DentError,
    },
    /// A breakable body could not break at its hit: its mesh is not closed, its transform
    /// scales, or the placement is degenerate.
    #[error("hit {hit} (body {target}) cannot break: {error}")]
    Fracture {
        /// Index of the breaking hit.
        hit: usize,
        /// The body's id, formatted.
        target: String,
        /// What was wrong.
        #[source]
        error: FractureError,
    },
}
