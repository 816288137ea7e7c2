//! The C API of dentbend: dent and bend rigid bodies from C, C++, C# (Unity's P/Invoke), Unreal
//! and Godot (GDExtension), through opaque handles and flat arrays.
//!
//! - Every function returns a status (`DB_OK` is 0) or a null handle on failure, and leaves
//!   the thread's message for [`db_last_error`]. No panic crosses the boundary: one is caught
//!   and reported as `DB_ERR_INTERNAL`.
//! - Arrays are passed as a pointer and a count; positions are 3 floats a vertex, triangles 3
//!   `uint32_t` indices each. The library copies what it keeps and hands back pointers into
//!   its own memory, valid until the next change of the object they belong to.
//! - A call that fails changes nothing.
//!
//! From Rust (the Python package builds on it), [`DbDamage`]'s methods are the same damage
//! context without pointers.
//!
//! The header, `include/dentbend.h`, is generated from this crate by cbindgen and committed;
//! a test fails when it is stale.

#![warn(missing_docs)]

mod attributes;
mod damage;
mod dent;
mod fracture;
mod handles;
mod mesh;
mod replica;
mod replication;
mod save;
mod status;

pub use damage::{
    DB_MAX_HITS, DbAppliedDent, DbBodyState, DbDamage, DbDentSettings, DbHit, body_state, db_damage_add_body,
    db_damage_add_projectile, db_damage_dent, db_damage_dent_count, db_damage_free, db_damage_indices, db_damage_moved,
    db_damage_new, db_damage_normals, db_damage_positions, db_damage_set_pose, db_damage_step, db_damage_uvs,
    db_dent_settings_default, dent_settings, hit,
};
pub use dent::{DbDentOptions, DbDentReport, DbImpact, db_dent, db_dent_ex, db_dent_options_default};
pub use fracture::{
    DB_FRACTURE_DENT, DB_FRACTURE_ENERGY, DbFracture, DbFractureSettings, DbPiece, StepFracture,
    db_damage_forget_piece, db_damage_fracture, db_damage_fracture_count, db_damage_piece, db_damage_piece_mesh,
    db_damage_set_fracture, db_fracture_settings_default,
};
pub use mesh::{
    DB_MAX_TRIANGLES, DB_MAX_VERTICES, DbMesh, db_mesh_free, db_mesh_indices, db_mesh_moved, db_mesh_moved_count,
    db_mesh_new, db_mesh_new_with_attributes, db_mesh_normals, db_mesh_positions, db_mesh_triangle_count, db_mesh_uvs,
    db_mesh_vertex_count,
};
pub use replica::{
    DB_MAX_MESSAGE_BYTES, DbReplica, DbReplicaFracture, ReplicaBreak, db_replica_add_body, db_replica_add_projectile,
    db_replica_apply, db_replica_forget_piece, db_replica_fracture, db_replica_fracture_count, db_replica_free,
    db_replica_indices, db_replica_join, db_replica_moved, db_replica_new, db_replica_normals, db_replica_piece,
    db_replica_positions, db_replica_uvs,
};
pub use replication::{db_damage_add_wire_projectile, db_damage_message, db_damage_replicate, db_damage_snapshot};
pub use save::{db_damage_record, db_damage_restore, db_damage_save};
pub use status::{
    DB_ERR_DENT, DB_ERR_INTERNAL, DB_ERR_INVALID_ARGUMENT, DB_ERR_NULL_POINTER, DB_OK, Failure, db_last_error,
};
