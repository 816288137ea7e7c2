//! The adapter's one error type. Every failing entry point returns it before changing any
//! mesh, collider, body or joint.

use dentbend::bend::BendError;
use dentbend::damage::DamageError;
use dentbend::dent::DentError;
use dentbend::fracture::FractureError;
use dentbend::mesh::MeshError;
use dentbend::record::RecordError;
use rapier3d::prelude::{ColliderHandle, ImpulseJointHandle, RigidBodyHandle};

/// What went wrong in the adapter; nothing of the caller's changed.
#[derive(Debug, thiserror::Error)]
pub enum AdapterError {
    /// A contact's point or normal holds NaN or ∞.
    #[error("contact between {collider1:?} and {collider2:?}: {field} {value} is not finite")]
    NonFiniteContact {
        /// First collider of the pair.
        collider1: ColliderHandle,
        /// Second collider of the pair.
        collider2: ColliderHandle,
        /// `point` or `normal`.
        field: &'static str,
        /// The value, formatted.
        value: String,
    },
    /// A contact's normal is the zero vector (no direction to dent along).
    #[error("contact between {collider1:?} and {collider2:?}: the normal is the zero vector")]
    ZeroNormal {
        /// First collider of the pair.
        collider1: ColliderHandle,
        /// Second collider of the pair.
        collider2: ColliderHandle,
    },
    /// A collider the adapter or the caller named is not in the collider set.
    #[error("unknown collider {0:?}")]
    UnknownCollider(ColliderHandle),
    /// A rigid body the adapter or the caller named is not in the body set.
    #[error("unknown rigid body {0:?}")]
    UnknownBody(RigidBodyHandle),
    /// A body whose state was recorded before the step is gone after it (removed between steps).
    #[error("rigid body {0:?} was removed between the recorded state and the contacts")]
    RemovedBody(RigidBodyHandle),
    /// A body added after the states were recorded ([`BodyStates::record`](crate::BodyStates::record)).
    #[error("rigid body {0:?} has no recorded state (added after the record?)")]
    NotRecorded(RigidBodyHandle),
    /// A collider recorded before the step is gone after it (removed between steps).
    #[error("collider {0:?} was removed between the recorded state and the contacts")]
    RemovedCollider(ColliderHandle),
    /// A joint the adapter manages is gone from the impulse-joint set.
    #[error("unknown impulse joint {0:?}")]
    UnknownJoint(ImpulseJointHandle),
    /// A collider's shape cannot take the dented mesh (wrong kind, or another vertex count).
    #[error("collider {collider:?}: {reason}")]
    Refit {
        /// The collider.
        collider: ColliderHandle,
        /// Why.
        reason: String,
    },
    /// The damage planning failed (a bad body state, a failed dent).
    #[error(transparent)]
    Damage(#[from] DamageError),
    /// Bad dent settings, or a non-finite pose.
    #[error(transparent)]
    Dent(#[from] DentError),
    /// A mesh could not be built.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Damage records that do not restore (recorded on another mesh, corrupt), or a record
    /// that cannot be made.
    #[error(transparent)]
    Record(#[from] RecordError),
    /// A collider cannot be made breakable (bad settings, a mesh that bounds no solid).
    #[error("collider {collider:?} cannot break: {error}")]
    Fracture {
        /// The collider.
        collider: ColliderHandle,
        /// Why.
        #[source]
        error: FractureError,
    },
    /// The rig (skeleton, weights, sub-bodies) could not be built.
    #[error("bending rig: {0}")]
    Rig(String),
    /// A parameter is out of range.
    #[error("invalid parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// The parameter.
        name: &'static str,
        /// Its value, formatted.
        value: String,
        /// The rule it breaks.
        reason: &'static str,
    },
}

impl From<BendError> for AdapterError {
    /// A parameter out of range keeps its name; anything else is the rig's.
    fn from(error: BendError) -> Self {
        match error {
            BendError::InvalidParameter { name, value, reason } => Self::InvalidParameter { name, value, reason },
            other => Self::Rig(other.to_string()),
        }
    }
}
