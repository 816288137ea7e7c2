//! Damage over the network, the server's side: a context writes each step's dents and
//! fractures as a message (about 60 bytes a dent) and a late joiner's snapshot, for clients
//! (`DbReplica`) to apply.

use std::collections::HashSet;
use std::ffi::c_int;

use dentbend::TriMesh;
use dentbend::damage::{AppliedDent, BodyFracture, PieceId};
use dentbend::record::replication::{ReplicationError, ReplicationServer};

use crate::damage::DbDamage;
use crate::mesh::DbMesh;
use crate::status::{Failure, guarded, guarded_value, hand_out};

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
    /// Makes the message of a step's `dents` and `fractures`: `mesh` gives each body's mesh
    /// after the step, `surface` each projectile's surface; nothing when no body is carried.
    /// On failure the stream is as it was.
    pub(crate) fn after_step<'m>(
        &mut self,
        dents: &[AppliedDent<u64>],
        fractures: &[BodyFracture<u64>],
        mesh: impl Fn(u64) -> Option<&'m TriMesh>,
        surface: impl Fn(u64) -> Option<&'m TriMesh>,
    ) -> Result<(), Failure> {
        if !self.carries_any() {
            self.message.clear();
            return Ok(());
        }
        let made = self.server.message(dents, fractures, mesh, surface).map_err(|e| match e {
            ReplicationError::UnknownProjectile(_) => Failure::invalid(
                "the step's message cannot name a projectile's surface: name it with \
                 db_damage_add_wire_projectile (Python: Damage.add_wire_projectile), and add it to every replica",
            ),
            e => Failure::invalid(e.to_string()),
        })?;
        self.message = made.unwrap_or_default();
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

    /// Stops naming piece `id` (the game removed it).
    pub(crate) fn forget_piece(&mut self, id: PieceId) {
        self.server.forget_piece(id);
    }
}

impl DbDamage {
    /// Carries body `id` on the stream as wire id `wire_id`: its mesh now is the base every
    /// client must add, with the same settings.
    ///
    /// # Errors
    /// A body that does not dent, or a wire id taken by another body.
    pub fn replicate(&mut self, id: u64, wire_id: u32) -> Result<(), Failure> {
        let (mesh, settings) = match (self.targets.mesh(id), self.targets.settings(id)) {
            (Some(mesh), Some(settings)) => (mesh, settings),
            _ => return Err(Failure::invalid(format!("body {id} does not dent (add it as a body that dents first)"))),
        };
        self.stream.server.track(id, wire_id, mesh, settings).map_err(|e| Failure::invalid(e.to_string()))?;
        self.stream.carried.insert(id);
        Ok(())
    }

    /// Names a projectile's surface `shape_id` on the stream: dents made by bodies with this
    /// mesh (its own coordinates) name it by id, and clients add the same mesh under it.
    ///
    /// # Errors
    /// `shape_id` naming another mesh already.
    pub fn add_wire_projectile(&mut self, shape_id: u32, mesh: &TriMesh) -> Result<(), Failure> {
        self.stream.server.add_projectile(shape_id, mesh).map_err(|e| Failure::invalid(e.to_string()))
    }

    /// The last step's message for the clients; empty when the step changed no carried body.
    pub fn message(&self) -> &[u8] {
        &self.stream.message
    }

    /// A late joiner's start: every carried body's mesh now. Take it after the last step's
    /// message was sent.
    ///
    /// # Errors
    /// A snapshot that cannot be made (it always can for bodies the context has).
    pub fn snapshot(&mut self) -> Result<&[u8], Failure> {
        let targets = &self.targets;
        let made = self.stream.server.snapshot(|k| targets.mesh(k)).map_err(|e| Failure::invalid(e.to_string()))?;
        self.stream.snapshot = made.bytes;
        Ok(&self.stream.snapshot)
    }
}

/// Carries body `id` on the context's stream as wire id `wire_id`: its mesh now is the base
/// every client must add (`db_replica_add_body`), with the same settings.
///
/// # Safety
/// `damage` is null or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_replicate(damage: *mut DbDamage, id: u64, wire_id: u32) -> c_int {
    // SAFETY: the caller's contract.
    guarded(|| unsafe { DbDamage::get_mut(damage)? }.replicate(id, wire_id))
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
        damage.add_wire_projectile(shape_id, mesh.mesh())
    })
}

/// The last step's message for the clients (its length written to `length`); null and 0 when
/// the step changed no carried body (send nothing, or send it empty: `db_replica_apply` takes
/// length 0 as no change). Valid until the next `db_damage_step`.
///
/// # Safety
/// `damage` is null or live; `length` is null or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_message(damage: *const DbDamage, length: *mut usize) -> *const u8 {
    // SAFETY: the caller's contract.
    let bytes = guarded_value(|| unsafe { DbDamage::get(damage) }.map(|d| (d.message().as_ptr(), d.message().len())));
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
        let snapshot = unsafe { DbDamage::get_mut(damage)? }.snapshot()?;
        Ok((snapshot.as_ptr(), snapshot.len()))
    });
    // SAFETY: the caller's contract.
    unsafe { hand_out(bytes, length) }
}
