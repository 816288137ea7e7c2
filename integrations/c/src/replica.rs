//! Damage over the network, a client's side: a `DbReplica` applies a server's snapshot and
//! messages to the same base meshes and gets the server's meshes (and fractures) bit for bit,
//! or refuses a message that is out of order, repeated, truncated or for other meshes,
//! changing nothing.

use std::collections::HashMap;
use std::ffi::c_int;

use dentbend::TriMesh;
use dentbend::damage::{PieceId, piece_hull_points};
use dentbend::dent::DentSettings;
use dentbend::glam::{Vec2, Vec3};
use dentbend::mesh::Asset;
use dentbend::record::replication::{ReplicaChange, ReplicaFracture, ReplicationClient, ReplicationError};

use crate::attributes::{self, Attributes};
use crate::damage::{DbDentSettings, dent_settings};
use crate::fracture::{DbPiece, piece_view, write_out};
use crate::handles;
use crate::mesh::DbMesh;
use crate::status::{Failure, guarded, guarded_value, hand_out};

/// Most bytes of one message or snapshot the client reads (a larger length is taken for
/// garbage).
pub const DB_MAX_MESSAGE_BYTES: usize = 1 << 30;

/// A client's copy of the bodies a server's stream carries (opaque in C).
#[derive(Debug, Default)]
pub struct DbReplica {
    client: ReplicationClient,
    /// The vertices the last message or snapshot moved or added, per wire id.
    moved: HashMap<u32, Vec<u32>>,
    /// The last message's fractures.
    fractures: Vec<ReplicaBreak>,
    /// The attributes (UVs, authored normals) of the bodies that have them.
    attributes: Attributes<u32>,
}

/// A fracture the last message replayed.
#[derive(Debug)]
pub struct ReplicaBreak {
    /// The wire id of the body that broke.
    pub body: u32,
    /// Whether the pattern took the whole body (the replica no longer has it).
    pub whole: bool,
    /// The server's fracture and pieces.
    pub fracture: ReplicaFracture,
    /// Each piece's collider points (as `piece_hull_points` makes them).
    pub hulls: Vec<Vec<Vec3>>,
    /// Each piece's asset (UVs and normals carried over), when the body had attributes.
    pub assets: Option<Vec<Asset>>,
}

/// A client replica's view of one fracture, for C.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct DbReplicaFracture {
    /// The wire id of the body that broke: it keeps this id with its rest, unless `whole`.
    pub body: u32,
    /// Non-zero: the pattern took the whole body; the replica no longer has it.
    pub whole: c_int,
    /// The server's fracture number: its pieces' `fracture`.
    pub number: u64,
    /// How many pieces broke loose.
    pub piece_count: usize,
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

    /// Adds the body the server carries as `wire_id`: its base `asset` (the server's mesh when
    /// it was carried; its attributes, UVs and authored normals, follow every message) and the
    /// server's `settings` for it.
    ///
    /// # Errors
    /// A wire id already added, settings the stream cannot carry, or attributes on a body that
    /// dents progressively (its dents travel as meshes).
    pub fn add_body(&mut self, wire_id: u32, asset: Asset, settings: &DentSettings) -> Result<(), Failure> {
        if settings.progressive && attributes::any(asset.attributes()) {
            return Err(Failure::invalid(format!(
                "body {wire_id} dents progressively: its dents travel as meshes, which do not say which edge each new \
                 vertex split, so its attributes (UVs, normals) cannot follow; add it without them"
            )));
        }
        self.client.add_body(wire_id, asset.mesh().clone(), settings).map_err(|e| Failure::invalid(e.to_string()))?;
        self.attributes.keep(wire_id, asset);
        Ok(())
    }

    /// Adds projectile surface `shape_id` (the mesh the server named so).
    ///
    /// # Errors
    /// `shape_id` naming another mesh already.
    pub fn add_projectile(&mut self, shape_id: u32, mesh: TriMesh) -> Result<(), Failure> {
        self.client.add_projectile(shape_id, mesh).map_err(|e| Failure::invalid(e.to_string()))
    }

    /// Starts from a server's snapshot, for a client joining late.
    ///
    /// # Errors
    /// A snapshot that does not parse or is for other meshes; nothing changes then.
    pub fn join(&mut self, snapshot: &[u8]) -> Result<(), Failure> {
        check_length(snapshot.len())?;
        self.update(|client| client.join(snapshot))
    }

    /// Applies a server's message, in order: the bodies it names get the server's meshes bit
    /// for bit, its fractures the server's pieces. An empty message (a step that changed no
    /// carried body) changes nothing.
    ///
    /// # Errors
    /// A message out of order, repeated, truncated or for other meshes; nothing changes then.
    pub fn apply(&mut self, message: &[u8]) -> Result<(), Failure> {
        check_length(message.len())?;
        // A step that changed no carried body has no message: nothing to apply.
        if message.is_empty() {
            self.take(Vec::new(), Vec::new());
            return Ok(());
        }
        self.update(|client| client.apply(message))
    }

    /// Runs `change` on the client and brings the bodies' attributes along, all or nothing:
    /// with attributes to follow, on a copy of the client, kept once they have followed.
    fn update(
        &mut self,
        change: impl FnOnce(&mut ReplicationClient) -> Result<Vec<ReplicaChange>, ReplicationError>,
    ) -> Result<(), Failure> {
        let refused = |e: ReplicationError| Failure::invalid(e.to_string());
        if self.attributes.is_empty() {
            let changes = change(&mut self.client).map_err(refused)?;
            self.take(changes, Vec::new());
            return Ok(());
        }
        let mut client = self.client.clone();
        let changes = change(&mut client).map_err(refused)?;
        let mut followed = self.attributes.follow_replica(&changes, |id| client.mesh(id), |id| id)?;
        self.client = client;
        self.attributes.commit(&mut followed);
        self.take(changes, std::mem::take(&mut followed.pieces));
        Ok(())
    }

    /// Keeps the last snapshot's or message's changes, with the pieces' assets of the
    /// fractures among them (in order; empty when no body has attributes).
    fn take(&mut self, changes: Vec<ReplicaChange>, mut assets: Vec<Option<Vec<Asset>>>) {
        self.moved.clear();
        self.fractures.clear();
        assets.reverse();
        for change in changes {
            if change.removed {
                self.moved.remove(&change.id);
            } else if change.fracture.is_some() {
                // The rest: every vertex is new, as on the server.
                let count = self.client.mesh(change.id).map_or(0, TriMesh::vertex_count) as u32;
                self.moved.insert(change.id, (0..count).collect());
            } else {
                self.moved.insert(change.id, change.moved);
            }
            if let Some(fracture) = change.fracture {
                let hulls = fracture.pieces.iter().map(|(_, p)| piece_hull_points(&p.mesh, p.mass.center)).collect();
                let assets = assets.pop().flatten();
                self.fractures.push(ReplicaBreak { body: change.id, whole: change.removed, fracture, hulls, assets });
            }
        }
    }

    /// Body `wire_id`'s mesh now, if the replica has it.
    pub fn mesh(&self, wire_id: u32) -> Option<&TriMesh> {
        self.client.mesh(wire_id)
    }

    /// Body `wire_id`'s normals to shade with: its authored ones, brought along, when it was
    /// added with them; else its mesh's.
    pub fn normals(&self, wire_id: u32) -> Option<&[Vec3]> {
        let mesh = self.client.mesh(wire_id)?;
        Some(self.attributes.normals(wire_id).unwrap_or(mesh.normals()))
    }

    /// Body `wire_id`'s first UV set, new vertices interpolated, when it was added with UVs.
    pub fn uvs(&self, wire_id: u32) -> Option<&[Vec2]> {
        self.client.mesh(wire_id)?;
        self.attributes.uvs(wire_id)
    }

    /// The vertices of body `wire_id` the last message or snapshot moved or added, ascending.
    pub fn moved(&self, wire_id: u32) -> &[u32] {
        self.moved.get(&wire_id).map_or(&[], Vec::as_slice)
    }

    /// The last message's fractures.
    pub fn fractures(&self) -> &[ReplicaBreak] {
        &self.fractures
    }

    /// Stops keeping piece `id` (the game removed it; the server forgets it too).
    pub fn forget_piece(&mut self, id: PieceId) {
        self.client.forget_piece(id);
    }

    /// The last message's fracture `index`, or the failure naming the count.
    fn fracture(&self, index: usize) -> Result<&ReplicaBreak, Failure> {
        let count = self.fractures.len();
        self.fractures.get(index).ok_or_else(|| Failure::invalid(format!("fracture {index} of {count}")))
    }
}

/// Refuses a message or snapshot longer than `DB_MAX_MESSAGE_BYTES`.
fn check_length(length: usize) -> Result<(), Failure> {
    if length > DB_MAX_MESSAGE_BYTES {
        return Err(Failure::invalid(format!("{length} bytes: the limit is {DB_MAX_MESSAGE_BYTES}")));
    }
    Ok(())
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
        // SAFETY: null or a `DbDentSettings` by the caller's contract.
        let settings = unsafe { settings.as_ref() }.ok_or_else(|| Failure::null("settings"))?;
        replica.add_body(wire_id, mesh.asset.clone(), &dent_settings(settings))
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
        replica.add_projectile(shape_id, mesh.mesh().clone())
    })
}

/// Reads `length` bytes at `bytes`.
///
/// # Safety
/// `bytes` holds `length` bytes when `length` > 0.
unsafe fn message<'a>(bytes: *const u8, length: usize) -> Result<&'a [u8], Failure> {
    check_length(length)?;
    if length == 0 {
        return Ok(&[]);
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
        replica.join(bytes)
    })
}

/// Applies a server's message (`db_damage_message`), in order: the bodies it names get the
/// server's meshes bit for bit, and its fractures the server's pieces
/// (`db_replica_fracture`). An empty message (length 0: a step that changed no carried body)
/// changes nothing. A message out of order, repeated, truncated or for other meshes is refused
/// and changes nothing.
///
/// # Safety
/// `replica` is null or live; `bytes` holds `length` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_apply(replica: *mut DbReplica, bytes: *const u8, length: usize) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let (replica, bytes) = unsafe { (DbReplica::get(replica)?, message(bytes, length)?) };
        replica.apply(bytes)
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
        let mesh = replica.mesh(wire_id).ok_or_else(|| Failure::invalid(format!("no body {wire_id}")))?;
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

/// The replica's body `wire_id`: its vertex normals (its authored ones brought along, when its
/// mesh came with them), as `db_replica_positions`.
///
/// # Safety
/// As `db_replica_positions`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_normals(
    replica: *const DbReplica,
    wire_id: u32,
    vertex_count: *mut usize,
) -> *const f32 {
    let found = guarded_value(|| {
        // SAFETY: the caller's contract.
        let replica = unsafe { DbReplica::read(replica)? };
        let normals = replica.normals(wire_id).ok_or_else(|| Failure::invalid(format!("no body {wire_id}")))?;
        Ok((normals.as_ptr().cast(), normals.len()))
    });
    // SAFETY: the caller's contract.
    unsafe { hand_out(found, vertex_count) }
}

/// The replica's body `wire_id`: its UVs (2 floats a vertex, new vertices interpolated), as
/// `db_replica_positions`; null and 0 for a body whose mesh came without UVs.
///
/// # Safety
/// As `db_replica_positions`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_uvs(
    replica: *const DbReplica,
    wire_id: u32,
    vertex_count: *mut usize,
) -> *const f32 {
    let found = guarded_value(|| {
        // SAFETY: the caller's contract.
        let replica = unsafe { DbReplica::read(replica)? };
        replica.mesh(wire_id).ok_or_else(|| Failure::invalid(format!("no body {wire_id}")))?;
        let uvs = replica.uvs(wire_id).unwrap_or(&[]);
        Ok((uvs.as_ptr().cast(), uvs.len()))
    });
    // SAFETY: the caller's contract.
    unsafe { hand_out(found, vertex_count) }
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
        let moved = unsafe { DbReplica::read(replica)? }.moved(wire_id);
        Ok((moved.as_ptr(), moved.len()))
    });
    // SAFETY: the caller's contract.
    unsafe { hand_out(found, count) }
}

/// How many bodies the last message or snapshot broke (0 for a null or dead replica).
///
/// # Safety
/// `replica` is null or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_fracture_count(replica: *const DbReplica) -> usize {
    // SAFETY: the caller's contract.
    guarded_value(|| unsafe { DbReplica::read(replica) }.map(|r| r.fractures.len())).unwrap_or(0)
}

/// Writes the last message's fracture `index` to `out`.
///
/// # Safety
/// `replica` is null or live; `out` is null or points to a writable `DbReplicaFracture`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_fracture(
    replica: *const DbReplica,
    index: usize,
    out: *mut DbReplicaFracture,
) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let made = unsafe { DbReplica::read(replica)? }.fracture(index)?;
        let view = DbReplicaFracture {
            body: made.body,
            whole: c_int::from(made.whole),
            number: made.fracture.number,
            piece_count: made.fracture.pieces.len(),
        };
        // SAFETY: the caller's contract.
        unsafe { write_out(out, view) }
    })
}

/// Writes piece `piece` of the last message's fracture `fracture` to `out` (the server's piece
/// bit for bit; its velocities are zero: they are the game's state to replicate). Its arrays
/// are valid until the next `db_replica_apply` or `db_replica_join`.
///
/// # Safety
/// `replica` is null or live; `out` is null or points to a writable `DbPiece`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_piece(
    replica: *const DbReplica,
    fracture: usize,
    piece: usize,
    out: *mut DbPiece,
) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let made = unsafe { DbReplica::read(replica)? }.fracture(fracture)?;
        let count = made.fracture.pieces.len();
        let (id, p) =
            made.fracture.pieces.get(piece).ok_or_else(|| Failure::invalid(format!("piece {piece} of {count}")))?;
        let asset = made.assets.as_ref().map(|a| &a[piece]);
        let view = piece_view(*id, &p.mesh, asset, &p.mass, (Vec3::ZERO, Vec3::ZERO), &made.hulls[piece]);
        // SAFETY: the caller's contract.
        unsafe { write_out(out, view) }
    })
}

/// Stops keeping piece (`fracture_number`, `index`): call when the game removes it (the
/// server calls `db_damage_forget_piece`).
///
/// # Safety
/// `replica` is null or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_replica_forget_piece(replica: *mut DbReplica, fracture_number: u64, index: u32) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        unsafe { DbReplica::get(replica)? }.forget_piece(PieceId { fracture: fracture_number, index });
        Ok(())
    })
}
