//! Network replication of damage: a server sends each step's dents and fractures as small messages (about
//! 54 bytes a dent: the contact in the target's coordinates as [`LocalContact`] codes it, the
//! dent distance and the crop reach), and each client recomputes them on the CPU from the same
//! meshes, getting bit-identical meshes; every group of dents carries the low 32 bits of the
//! server's resulting mesh hash, and a client that would differ refuses the message. A body
//! that breaks sends its fracture as data too (about 50 bytes: the number, the pattern's
//! parameters, where it was placed, the density); clients replay it on the mesh it broke and get
//! the server's rest and pieces bit for bit, checked by hash. A client
//! that joins late starts from a snapshot whose size is bounded by the meshes, not by the hits
//! that came before: each body is sent as the smaller of its edit from the base mesh and its
//! whole mesh.
//!
//! Both sides are given every body's base mesh and dent settings and the projectile meshes
//! up front (game assets); the stream names them by small ids. Dents to recompute need a server
//! that dents on the CPU backend: a GPU's f32 results are not the CPU's, and clients would refuse
//! them. A server whose dents run on a GPU sends exact mesh edits instead
//! ([`ReplicationServer::with_mesh_edits`]), as a progressive body always does (its dents are
//! rebuilt from a pre-dent surface the clients do not have).
//!
//! [`LocalContact`]: crate::dent::LocalContact

mod client;
mod error;
mod server;
mod wire;

pub use client::{ReplicaChange, ReplicaFracture, ReplicationClient};
pub use error::ReplicationError;
pub use server::{ReplicationServer, SnapshotBytes};

use super::bytes::ByteWriter;
use super::params_codec::write_params;
use crate::dent::{DentParams, DentSettings};
use crate::mesh::{fnv1a64, fnv1a64_start};

/// A digest of what a client needs of a body's settings to dent as the server: its dent
/// parameters (every field but the distance, which each dent carries), its cap (the deepest
/// dent a message may carry) and whether it is progressive.
///
/// # Errors
/// [`ReplicationError::NotReplicable`] for a custom falloff (a function, not data).
fn settings_digest(settings: &DentSettings) -> Result<u64, ReplicationError> {
    let mut out = ByteWriter::default();
    write_params(&mut out, &DentParams { dent_distance: 0.0, ..settings.params.clone() })
        .map_err(|e| ReplicationError::NotReplicable(format!("these dent settings: {e}")))?;
    out.f32(settings.material.cap);
    out.u8(u8::from(settings.progressive));
    Ok(fnv1a64(fnv1a64_start(), &out.bytes))
}
