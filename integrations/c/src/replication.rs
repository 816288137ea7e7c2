//! Damage over the network: a server's context writes each step's dents as a message (about
//! 60 bytes a dent) and a late joiner's snapshot; a client (`DbReplica`) applies them to the
//! same base meshes and gets the server's meshes bit for bit, or refuses a message that is out
//! of order, repeated, truncated or for other meshes, changing nothing.

use std::collections::{HashMap, HashSet};
use std::ffi::c_int;

use dentbend::TriMesh;
use dentbend::damage::{AppliedDent, BodyFracture, TargetSet};
use dentbend::record::replication::{ReplicationClient, ReplicationServer};

use crate::damage::{DbDamage, DbDentSettings, dent_settings};
use crate::handles;
use crate::mesh::DbMesh;
use crate::status::{Failure, guarded, guarded_value, hand_out};

/// Most bytes of one message or snapshot the client reads (a larger length is taken for
/// garbage).
pub const DB_MAX_MESSAGE_BYTES: usize = 1 << 30;

/// A context's stream: the bodies it carries, the last step's message, the last snapshot.
#[derive(Debug, Default)]
pub(crate) struct Stream {
    server: ReplicationServer<u64>,
    /// The bodies carried.
    carried: HashSet<u64>,
    message: Vec<u8>,
    snapshot: Vec<u8>,
}

impl Stream {
    /// Makes the message of a step's `dents` and `fractures`, applied to `targets`, the
    /// projectiles' surfaces from `surface`; nothing when no body is carried.
    pub(crate) fn after_step<'m>(
        &mut self,
        dents: &[AppliedDent<u64>],
        fractures: &[BodyFracture<u64>],
        targets: &'m TargetSet<u64>,
        surface: impl Fn(u64) -> Option<&'m TriMesh>,
    ) -> Result<(), Failure> {
        if !self.carries_any() {
            self.message.clear();
            return Ok(());
        }
        let made = self.server.message(dents, fractures, |k| targets.mesh(k), surface);
        self.message = made.map_err(|e| Failure::invalid(e.to_string()))?.unwrap_or_default();
        Ok(())
    }

    /// Whether any body is carried.
    pub(crate) fn carries_any(&self) -> bool {
        !self.carried.is_empty()
    }

    /// Whether body `id` is carried.
    pub(crate) fn carries(&self, id: u64) -> bool {
        self.carried.contains(&id)
    }

    /// Stops carrying body `id` (replaced or removed).
    pub(crate) fn forget(&mut self, id: u64) {
        if self.carried.remove(&id) {
            self.server.forget(id);
        }
    }
}

/// Carries body `id` on the context's stream as wire id `wire_id`: its mesh now is the base
/// every client must add (`db_replica_add_body`), with the same settings.
///
/// # Safety
/// `damage` is null or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_replicate(damage: *mut DbDamage, id: u64, wire_id: u32) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let damage = unsafe { DbDamage::get_mut(damage)? };
        let (mesh, settings) = match (damage.targets.mesh(id), damage.targets.settings(id)) {
            (Some(mesh), Some(settings)) => (mesh, settings),
            _ => return Err(Failure::invalid(format!("body {id} does not dent (add it with db_damage_add_body)"))),
        };
        damage.stream.server.track(id, wire_id, mesh, settings).map_err(|e| Failure::invalid(e.to_string()))?;
        damage.stream.carried.insert(id);
        Ok(())
    })
}

/// Names a projectile's surface `shape_id` on the stream: dents made by bodies with this mesh
/// (its own coordinates) name it by id, and clients add the same mesh under it.
///
/// # Safety
/// `damage` and `mesh` are null or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_add_wire_projectile(
    damage: *mut DbDamage,
    shape_id: u32,
    mesh: *const DbMesh,
) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let (damage, mesh) = unsafe { (DbDamage::get_mut(damage)?, DbMesh::get(mesh, "mesh")?) };
        damage.stream.server.add_projectile(shape_id, mesh.mesh()).map_err(|e| Failure::invalid(e.to_string()))
    })
}

/// The last step's message for the clients (its length written to `length`); null and 0 when
/// it carried nothing. Valid until the next `db_damage_step`.
///
/// # Safety
/// `damage` is null or live; `length` is null or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_message(damage: *const DbDamage, length: *mut usize) -> *const u8 {
    // SAFETY: the caller's contract.
    let bytes =
        guarded_value(|| unsafe { DbDamage::get(damage) }.map(|d| (d.stream.message.as_ptr(), d.stream.message.len())));
    // SAFETY: the caller's contract.
    unsafe { hand_out(bytes, length) }
}

/// A late joiner's start (its length written to `length`): every carried body's mesh now, as
/// the smaller of its edit from the base and the whole mesh, bounded by the meshes however many
/// dents came before. Take it after the last step's message was sent. Valid until the next
/// snapshot or step.
///
/// # Safety
/// `damage` is null or live; `length` is null or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_snapshot(damage: *mut DbDamage, length: *mut usize) -> *const u8 {
    let bytes = guarded_value(|| {
        // SAFETY: the caller's contract.
        let damage = unsafe { DbDamage::get_mut(damage)? };
        let targets = &damage.targets;
        let made = damage.stream.server.snapshot(|k| targets.mesh(k)).map_err(|e| Failure::invalid(e.to_string()))?;
        damage.stream.snapshot = made.bytes;
        Ok((damage.stream.snapshot.as_ptr(), damage.stream.snapshot.len()))
    });
    // SAFETY: the caller's contract.
    unsafe { hand_out(bytes, length) }
}

/// A client's copy of the bodies a server's stream carries (opaque in C).
#[derive(Debug, Default)]
pub struct DbReplica {
    client: ReplicationClient,
    /// The vertices the last message or snapshot moved or added, per wire id.
    moved: HashMap<u32, Vec<u32>>,
}

impl DbReplica {
    /// The replica behind `handle`, checked as meshes are.
    ///
    /// # Safety
    /// `handle` is null or a live replica of `db_replica_new`; no other reference to it is in
    /// use.
    unsafe fn get<'a>(handle: *mut DbReplica) -> Result<&'a mut DbReplica, Failure> {
        // SAFETY: the caller's contract.
        unsafe { handles::get_mut(handle, "replica") }
    }

    /// As [`get`](Self::get), to read.
    ///
    /// # Safety
    /// `handle` is null or a live replica of `db_replica_new`.
    unsafe fn read<'a>(handle: *const DbReplica) -> Result<&'a DbReplica, Failure> {
        // SAFETY: the caller's contract.
        unsafe { handles::get(handle, "replica") }
    }
}

/// A new client replica with no body. Free it with `db_replica_free`.
#[unsafe(no_mangle)]
pub extern "C" fn db_replica_new() -> *mut DbReplica {
    handles::make(DbReplica::default())
}

/// Frees `replica` (null: nothing); as `db_mesh_free` for a second free.
///
/// # Safety
/// `replica` is null or a replica of `db_replica_new` not freed yet.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_free(replica: *mut DbReplica) {
    // SAFETY: the caller's contract.
    unsafe { handles::free(replica, "db_replica_free") }
}

/// Adds the body the server carries as `wire_id`: a copy of its base `mesh` (the server's mesh
/// when it was carried) and the server's `settings` for it. With every body and projectile
/// added, join with the server's snapshot (`db_replica_join`), then apply its messages.
///
/// # Safety
/// `replica` and `mesh` are null or live; `settings` is null or points to a `DbDentSettings`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_add_body(
    replica: *mut DbReplica,
    wire_id: u32,
    mesh: *const DbMesh,
    settings: *const DbDentSettings,
) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let (replica, mesh) = unsafe { (DbReplica::get(replica)?, DbMesh::get(mesh, "mesh")?) };
        if settings.is_null() {
            return Err(Failure::null("settings"));
        }
        // SAFETY: not null, a `DbDentSettings` by the caller's contract.
        let settings = dent_settings(unsafe { &*settings });
        replica.client.add_body(wire_id, mesh.mesh().clone(), &settings).map_err(|e| Failure::invalid(e.to_string()))
    })
}

/// Adds projectile surface `shape_id` (the mesh the server named so).
///
/// # Safety
/// `replica` and `mesh` are null or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_add_projectile(
    replica: *mut DbReplica,
    shape_id: u32,
    mesh: *const DbMesh,
) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let (replica, mesh) = unsafe { (DbReplica::get(replica)?, DbMesh::get(mesh, "mesh")?) };
        replica.client.add_projectile(shape_id, mesh.mesh().clone()).map_err(|e| Failure::invalid(e.to_string()))
    })
}

/// Reads `length` bytes at `bytes`.
///
/// # Safety
/// `bytes` holds `length` bytes when `length` > 0.
unsafe fn message<'a>(bytes: *const u8, length: usize) -> Result<&'a [u8], Failure> {
    if length > DB_MAX_MESSAGE_BYTES {
        return Err(Failure::invalid(format!("{length} bytes: the limit is {DB_MAX_MESSAGE_BYTES}")));
    }
    if bytes.is_null() {
        return Err(Failure::null("bytes"));
    }
    // SAFETY: not null, `length` bytes by the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(bytes, length) })
}

/// Starts from a server's snapshot (`db_damage_snapshot`), for a client joining late.
///
/// # Safety
/// `replica` is null or live; `bytes` holds `length` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_join(replica: *mut DbReplica, bytes: *const u8, length: usize) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let (replica, bytes) = unsafe { (DbReplica::get(replica)?, message(bytes, length)?) };
        let changes = replica.client.join(bytes).map_err(|e| Failure::invalid(e.to_string()))?;
        replica.moved = changes.into_iter().map(|c| (c.id, c.moved)).collect();
        Ok(())
    })
}

/// Applies a server's message (`db_damage_message`), in order: the bodies it names get the
/// server's meshes bit for bit. A message out of order, repeated, truncated or for other
/// meshes is refused and changes nothing.
///
/// # Safety
/// `replica` is null or live; `bytes` holds `length` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_apply(replica: *mut DbReplica, bytes: *const u8, length: usize) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let (replica, bytes) = unsafe { (DbReplica::get(replica)?, message(bytes, length)?) };
        let changes = replica.client.apply(bytes).map_err(|e| Failure::invalid(e.to_string()))?;
        replica.moved = changes.into_iter().map(|c| (c.id, c.moved)).collect();
        Ok(())
    })
}

/// Reads one of the replica's body `wire_id`'s mesh arrays: its pointer, its count into
/// `count` (when not null); null and 0 for a body it does not have.
///
/// # Safety
/// `replica` is null or live; `count` is null or writable.
unsafe fn replica_array<T>(
    replica: *const DbReplica,
    wire_id: u32,
    count: *mut usize,
    array: impl FnOnce(&TriMesh) -> (*const T, usize),
) -> *const T {
    let found = guarded_value(|| {
        // SAFETY: the caller's contract.
        let replica = unsafe { DbReplica::read(replica)? };
        let mesh = replica.client.mesh(wire_id).ok_or_else(|| Failure::invalid(format!("no body {wire_id}")))?;
        Ok(array(mesh))
    });
    // SAFETY: the caller's contract.
    unsafe { hand_out(found, count) }
}

/// The replica's body `wire_id`: its positions (3 floats a vertex), the count written to
/// `vertex_count`; null and 0 for a body it does not have. Valid until the next
/// `db_replica_apply` or `db_replica_join`.
///
/// # Safety
/// `replica` is null or live; `vertex_count` is null or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_positions(
    replica: *const DbReplica,
    wire_id: u32,
    vertex_count: *mut usize,
) -> *const f32 {
    // SAFETY: the caller's contract.
    unsafe { replica_array(replica, wire_id, vertex_count, |m| (m.positions().as_ptr().cast(), m.vertex_count())) }
}

/// The replica's body `wire_id`: its triangles (3 indices each), the count written to
/// `triangle_count`; as `db_replica_positions`.
///
/// # Safety
/// As `db_replica_positions`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_indices(
    replica: *const DbReplica,
    wire_id: u32,
    triangle_count: *mut usize,
) -> *const u32 {
    // SAFETY: the caller's contract.
    unsafe { replica_array(replica, wire_id, triangle_count, |m| (m.faces().as_ptr().cast(), m.face_count())) }
}

/// The vertices of body `wire_id` the last message or snapshot moved or added (ascending), the
/// count written to `count` (0 when it left the body alone).
///
/// # Safety
/// As `db_replica_positions`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_moved(replica: *const DbReplica, wire_id: u32, count: *mut usize) -> *const u32 {
    let found = guarded_value(|| {
        // SAFETY: the caller's contract.
        let replica = unsafe { DbReplica::read(replica)? };
        Ok(replica.moved.get(&wire_id).map_or((std::ptr::null(), 0), |m| (m.as_ptr(), m.len())))
    });
    // SAFETY: the caller's contract.
    unsafe { hand_out(found, count) }
}
