//! What can go wrong reading, recording or replaying damage; a failed operation changes nothing.

use crate::dent::DentError;
use crate::mesh::MeshError;

/// Everything a damage file, a recorder or a replay can refuse.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The file or one of its records ends before what it declares.
    #[error("truncated damage data: {what} needs {needed} more bytes, {available} are left")]
    Truncated {
        /// What was being read.
        what: &'static str,
        /// Bytes it needs.
        needed: usize,
        /// Bytes left.
        available: usize,
    },
    /// The file is of a format version this build does not read.
    #[error(
        "damage file version {found} is not supported (this build writes version {supported} and reads 1 to {supported})"
    )]
    Version {
        /// The file's version.
        found: u32,
        /// The version this build writes (it reads every version from 1 to this one).
        supported: u32,
    },
    /// The file is not a damage file, or a field is malformed (bad JSON, base64, tag, flag).
    #[error("malformed damage data: {0}")]
    Malformed(String),
    /// A count or size beyond what this build accepts: refused before anything is allocated.
    #[error("damage data declares {count} {what}, more than the {limit} accepted")]
    TooLarge {
        /// What was counted.
        what: &'static str,
        /// The declared count or size.
        count: u64,
        /// The most accepted.
        limit: u64,
    },
    /// A body's base mesh is not the one the damage was recorded on.
    #[error(
        "body \"{body}\": the damage was recorded on another mesh (base hash {expected}, this mesh hashes to {found})"
    )]
    BaseMismatch {
        /// The body.
        body: String,
        /// The base hash the file names, hex.
        expected: String,
        /// The hash of the mesh given, hex.
        found: String,
    },
    /// A record does not apply, or its result is not the mesh it names: the file was altered.
    #[error("body \"{body}\", record {record}: tampered or corrupt damage data: {reason}")]
    Tampered {
        /// The body.
        body: String,
        /// Index of the record in the body's list (the final-mesh check is one past the last).
        record: usize,
        /// What did not match.
        reason: String,
    },
    /// A record this build cannot replay (a progressive dent from its impact).
    #[error("body \"{body}\", record {record}: {what} cannot be replayed yet")]
    Unsupported {
        /// The body.
        body: String,
        /// Index of the record.
        record: usize,
        /// What it is.
        what: String,
    },
    /// A fracture record the fracture module refuses (a bad pattern, placement or density, or a
    /// mesh that is not closed): the file was altered or belongs to another mesh.
    #[error("body \"{body}\", record {record}: the fracture does not replay: {error}")]
    Fracture {
        /// The body.
        body: String,
        /// Index of the record.
        record: usize,
        /// What the fracture module said.
        #[source]
        error: crate::fracture::FractureError,
    },
    /// An impact record names a projectile mesh the replay was not given.
    #[error("no projectile mesh with content hash {hash} (built-in {builtin:?}) was given to the replay")]
    MissingProjectile {
        /// The projectile's content hash, hex.
        hash: String,
        /// Its built-in name, if it has one.
        builtin: Option<String>,
    },
    /// A body the caller asked about was not tracked or is not in the file.
    #[error("unknown body {0}")]
    UnknownBody(String),
    /// A dent's parameters cannot be recorded as data (a custom falloff function).
    #[error("cannot record {0}")]
    NotRecordable(String),
    /// Recomputing a dent failed.
    #[error("dent: {0}")]
    Dent(#[from] DentError),
    /// A mesh could not be built.
    #[error("mesh: {0}")]
    Mesh(#[from] MeshError),
}

/// A 64-bit hash as the file writes it: 16 lower-case hex digits.
pub(crate) fn hex64(hash: u64) -> String {
    format!("{hash:016x}")
}
