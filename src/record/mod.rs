//! Damage as data: a body's dents, bends and fractures as a compact file that replays
//! to bit-identical meshes — for save games, and for multiplayer clients that receive impacts
//! instead of meshes.
//!
//! A body's damage ([`BodyDamage`]) names its base mesh by counts and a stable
//! [`content_hash`](crate::mesh::content_hash) (FNV-1a 64), lists its records in order (dent
//! batches as [`MeshEdit`](crate::mesh::MeshEdit)s and/or impacts, bends, splits, fractures, a
//! bent body's skinned surface) and names its final mesh the same way. [`replay_body`] rebuilds
//! the final mesh, checking every step; a file that is truncated, of another version, from
//! another mesh or tampered with is refused with a typed [`RecordError`]. [`DamageRecorder`]
//! records what a user of [`Damage`](crate::damage::Damage) applies; `coupling::DamageLog`
//! records a simulation. On disk ([`DamageFile::to_json`], `io` feature) the records are
//! little-endian binary in base64 inside a small JSON object. [`replication`] streams a server's
//! dents to clients as they happen.

mod break_codec;
mod bytes;
mod edit_codec;
mod error;
mod file;
#[cfg(feature = "io")]
mod json;
mod params_codec;
mod recorder;
mod records;
mod replay;
mod replay_asset;
pub mod replication;

pub use bytes::{base64_decode, base64_encode};
pub use error::RecordError;
pub(crate) use error::hex64;
pub use file::{BodyDamage, DamageFile, MeshStamp, SceneRef};
pub use recorder::{DamageRecorder, RecordForms};
pub use records::{
    BoneSplit, DamageRecord, DentBatch, FracturePiece, FractureRecord, ImpactDent, JointBend, JointRest, ProjectileRef,
    decode_records, encode_records,
};
pub use replay::{DentForm, Projectiles, ReplayStep, Replayed, replay_body, replay_body_traced};
pub use replay_asset::replay_body_asset;
