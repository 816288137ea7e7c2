//! What can go wrong replicating damage; every error leaves the server's or client's state as
//! it was.

use crate::dent::DentError;
use crate::fracture::FractureError;
use crate::mesh::MeshError;
use crate::record::RecordError;

/// A refused replication call: nothing changed.
#[derive(Debug, thiserror::Error)]
pub enum ReplicationError {
    /// The bytes end before what they declare.
    #[error("truncated replication data: {what} needs {needed} more bytes, {available} are left")]
    Truncated {
        /// What was being read.
        what: &'static str,
        /// Bytes it needs.
        needed: usize,
        /// Bytes left.
        available: usize,
    },
    /// Not a replication message or snapshot of this version, or inconsistent inside.
    #[error("malformed replication data: {0}")]
    Malformed(String),
    /// A message from later in the stream: one before it was lost or reordered.
    #[error(
        "message {found} arrived while message {expected} was expected: deliver the stream in order (TCP, or your own reliable ordered channel)"
    )]
    OutOfOrder {
        /// The number the client expected.
        expected: u64,
        /// The number the message carries.
        found: u64,
    },
    /// A message the client has already applied.
    #[error("message {found} was already applied (the client is at {expected})")]
    Repeated {
        /// The number the client expected.
        expected: u64,
        /// The number the message carries.
        found: u64,
    },
    /// A message before any snapshot.
    #[error("the client has not joined: apply the server's snapshot (ReplicationServer::snapshot) first")]
    NotJoined,
    /// The stream names a body the client was not given.
    #[error(
        "body {id}: the client has no base mesh for it (ReplicationClient::add_body with the mesh the server tracks)"
    )]
    MissingBase {
        /// The body's wire id.
        id: u32,
    },
    /// A body's base mesh or dent settings differ from the server's, or a message was made for
    /// another mesh than the client's.
    #[error(
        "body {id}: {what} is {found} on this side, {expected} in the stream: the data comes from another mesh or other settings"
    )]
    OtherMesh {
        /// The body's wire id.
        id: u32,
        /// What differs.
        what: &'static str,
        /// The stream's value.
        expected: String,
        /// This side's value.
        found: String,
    },
    /// A body id is tracked twice, or a projectile id registered twice for another mesh.
    #[error("{what} {id} is already used")]
    DuplicateId {
        /// Body or projectile.
        what: &'static str,
        /// The id.
        id: u32,
    },
    /// A dent's projectile is neither a tracked body nor a registered projectile mesh.
    #[error("{0}")]
    UnknownProjectile(String),
    /// A dent on a body the server does not know.
    #[error("unknown body {0}")]
    UnknownBody(String),
    /// Something the stream cannot carry (a custom falloff function).
    #[error("cannot replicate {0}")]
    NotReplicable(String),
    /// A dent failed on the client.
    #[error("body {id}: dent {dent} does not apply: {error}")]
    Dent {
        /// The body's wire id.
        id: u32,
        /// Index of the dent in its group.
        dent: usize,
        /// Why.
        #[source]
        error: DentError,
    },
    /// A fracture in the stream does not replay on the body's mesh.
    #[error("body {id}: its fracture does not replay: {error}")]
    Fracture {
        /// The body's wire id.
        id: u32,
        /// Why.
        #[source]
        error: FractureError,
    },
    /// An edit or mesh in the stream is not a valid mesh for the body.
    #[error("body {id}: {error}")]
    Mesh {
        /// The body's wire id.
        id: u32,
        /// Why.
        #[source]
        error: MeshError,
    },
}

impl From<RecordError> for ReplicationError {
    fn from(e: RecordError) -> Self {
        match e {
            RecordError::Truncated { what, needed, available } => Self::Truncated { what, needed, available },
            other => Self::Malformed(other.to_string()),
        }
    }
}
