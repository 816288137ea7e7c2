//! The server's side: after each step's dents are applied, one message for every client; a
//! snapshot for a client that joins late.

use std::hash::Hash;

use super::wire::{
    BodyForm, Group, GroupChange, Message, ProjectileId, Snapshot, SnapshotBody, WireBreak, WireDent, check_of,
    outcome_check, write_message, write_snapshot,
};
use super::{ReplicationError, settings_digest};
use crate::damage::{AppliedDent, BodyFracture, PieceId};
use crate::dent::{DentSettings, VolumeMode};
use crate::mesh::{MeshEdit, TriMesh, content_hash};

/// A late joiner's start, with what sending every mesh whole would have cost.
#[derive(Debug, Clone)]
pub struct SnapshotBytes {
    /// The snapshot ([`ReplicationClient::join`](super::ReplicationClient::join)).
    pub bytes: Vec<u8>,
    /// Bytes of the same snapshot with every body's mesh sent whole: `bytes.len()` is never
    /// more, however many dents came before (each body takes the smaller of its edit from the
    /// base and its whole mesh).
    pub full_mesh_bytes: usize,
}

#[derive(Debug, Clone)]
struct ServerBody<K> {
    key: K,
    id: u32,
    base: TriMesh,
    base_hash: u64,
    settings: u64,
    /// Progressive bodies: the mesh the clients have (their groups are edits from it).
    sent: Option<TriMesh>,
    /// Whether its dents read its vertex normals (the rim of `VolumeMode::Preserve`), which a
    /// snapshot then sends.
    normals: bool,
}

/// The server's replication state: which of its bodies the stream carries (keyed by the
/// caller's ids, named on the wire by small ids), the projectile meshes clients know, and the
/// next message's number.
#[derive(Debug, Clone)]
pub struct ReplicationServer<K> {
    bodies: Vec<ServerBody<K>>,
    /// Registered projectile meshes: (content hash, id).
    shapes: Vec<(u64, u32)>,
    /// Ids of bodies a fracture took whole (a late joiner removes them).
    removed: Vec<u32>,
    /// Pieces of carried fractures still in play: (content hash, id, mesh).
    pieces: Vec<(u64, PieceId, TriMesh)>,
    /// Whether every body's changes go as exact mesh edits ([`with_mesh_edits`](Self::with_mesh_edits)).
    edits: bool,
    next: u64,
}

impl<K> Default for ReplicationServer<K> {
    fn default() -> Self {
        Self { bodies: Vec::new(), shapes: Vec::new(), removed: Vec::new(), pieces: Vec::new(), edits: false, next: 0 }
    }
}

impl<K: Copy + Eq + Hash + std::fmt::Debug> ReplicationServer<K> {
    /// No body tracked, no message sent.
    pub fn new() -> Self {
        Self::default()
    }

    /// A server whose bodies (tracked from now on) send their changes as exact mesh edits
    /// instead of dents for clients to recompute: for a server whose dents run on a GPU, whose
    /// f32 results are not the CPU's bit for bit. Clients apply the edits and end bit-identical
    /// all the same; an edit costs more bytes than a dent to recompute (about 54 bytes): it names
    /// every vertex the dent moved and carries the ones refinement added, 220–380 bytes for
    /// the 30–50 vertex dents of `tests/replication_edits.rs`.
    pub fn with_mesh_edits(mut self) -> Self {
        self.edits = true;
        self
    }

    /// Carries body `key` as wire id `id`, its mesh now `base` (its own coordinates; clients
    /// are given the same mesh), denting with `settings` (clients are given the same).
    ///
    /// # Errors
    /// [`ReplicationError::DuplicateId`] for an id another body has,
    /// [`ReplicationError::NotReplicable`] for a custom falloff; nothing changes then.
    pub fn track(&mut self, key: K, id: u32, base: &TriMesh, settings: &DentSettings) -> Result<(), ReplicationError> {
        if self.bodies.iter().any(|b| b.id == id && b.key != key) {
            return Err(ReplicationError::DuplicateId { what: "body", id });
        }
        let digest = settings_digest(settings)?;
        let body = ServerBody {
            key,
            id,
            base: base.clone(),
            base_hash: content_hash(base),
            settings: digest,
            sent: (settings.progressive || self.edits).then(|| base.clone()),
            normals: settings.params.volume == VolumeMode::Preserve,
        };
        match self.bodies.iter_mut().find(|b| b.key == key) {
            Some(slot) => *slot = body,
            None => self.bodies.push(body),
        }
        self.removed.retain(|&r| r != id);
        Ok(())
    }

    /// Stops carrying body `key` (removed from the game).
    pub fn forget(&mut self, key: K) {
        self.bodies.retain(|b| b.key != key);
    }

    /// Stops naming piece `id` of a carried fracture (the game removed it); a later snapshot
    /// leaves it out. Clients call [`ReplicationClient::forget_piece`](super::ReplicationClient::forget_piece)
    /// when the game removes it on their side.
    pub fn forget_piece(&mut self, id: PieceId) {
        self.pieces.retain(|(_, p, _)| *p != id);
    }

    /// Registers a projectile mesh (its own coordinates, as its surface dents) as id `id`:
    /// dents by bodies with this mesh name it by id. Clients register the same mesh.
    ///
    /// # Errors
    /// [`ReplicationError::DuplicateId`] when `id` names another mesh.
    pub fn add_projectile(&mut self, id: u32, mesh: &TriMesh) -> Result<(), ReplicationError> {
        let hash = content_hash(mesh);
        if self.shapes.iter().any(|&(h, i)| i == id && h != hash) {
            return Err(ReplicationError::DuplicateId { what: "projectile", id });
        }
        if !self.shapes.contains(&(hash, id)) {
            self.shapes.push((hash, id));
        }
        Ok(())
    }

    /// The number the next message will carry.
    pub fn next_message(&self) -> u64 {
        self.next
    }

    /// The message of one step's `dents` and `fractures` (from
    /// [`Damage::plan`](crate::damage::Damage::plan) on the CPU backend, already applied):
    /// `mesh` gives each tracked body's mesh now, and `surface` each projectile's surface as it
    /// dented (its mesh, own coordinates). Dents and fractures of bodies the stream does not
    /// carry are left out; `None` when nothing is carried (no message is numbered then). A
    /// body a fracture took whole is no longer carried.
    ///
    /// # Errors
    /// [`ReplicationError::UnknownProjectile`] for a projectile that is neither tracked nor
    /// registered, [`ReplicationError::UnknownBody`] for a tracked body `mesh` does not know;
    /// nothing changes then.
    pub fn message<'m, 'f>(
        &mut self,
        dents: &[AppliedDent<K>],
        fractures: impl IntoIterator<Item = &'f BodyFracture<K>>,
        mesh: impl Fn(K) -> Option<&'m TriMesh>,
        surface: impl Fn(K) -> Option<&'m TriMesh>,
    ) -> Result<Option<Vec<u8>>, ReplicationError>
    where
        K: 'f,
    {
        let mut groups: Vec<(usize, Group)> = Vec::new();
        for d in dents {
            let Some(slot) = self.bodies.iter().position(|b| b.key == d.target) else { continue };
            let wire = if self.bodies[slot].sent.is_some() { None } else { Some(self.wire_dent(d, &surface)?) };
            if let GroupChange::Dents(list) = &mut self.group(&mut groups, slot).change {
                list.extend(wire);
            }
        }
        // Each broken body's slot, fracture and pieces' content hashes (for the check, then to
        // name the pieces when they dent).
        let mut broken: Vec<(usize, &BodyFracture<K>, Vec<u64>)> = Vec::new();
        for f in fractures {
            let Some(slot) = self.bodies.iter().position(|b| b.key == f.body) else { continue };
            let hashes: Vec<u64> = f.pieces.iter().map(|p| content_hash(&p.mesh)).collect();
            let check = outcome_check(f.rest.as_ref(), hashes.iter().copied());
            self.group(&mut groups, slot).fracture = Some(WireBreak { number: f.number, record: f.record, check });
            broken.push((slot, f, hashes));
        }
        if groups.is_empty() {
            return Ok(None);
        }
        let mut sent = Vec::new();
        for (slot, group) in &mut groups {
            let body = &self.bodies[*slot];
            let fracture = broken.iter().find(|(s, ..)| s == slot).map(|(_, f, _)| *f);
            // The group's change ends at the mesh the body broke, when it broke.
            let now = match fracture {
                Some(f) => &f.broken_mesh,
                None => mesh(body.key).ok_or_else(|| ReplicationError::UnknownBody(format!("{:?}", body.key)))?,
            };
            group.check = check_of(content_hash(now));
            if let Some(before) = &body.sent {
                group.change = match MeshEdit::between(before, now) {
                    Ok(edit) => GroupChange::Edit(edit),
                    Err(_) => GroupChange::Whole(now.clone()),
                };
                let after = match fracture {
                    Some(f) => f.rest.clone(),
                    None => Some(now.clone()),
                };
                sent.push((*slot, after));
            }
        }
        let message = Message { number: self.next, groups: groups.into_iter().map(|(_, g)| g).collect() };
        // Everything built: commit.
        for (slot, after) in sent {
            self.bodies[slot].sent = after;
        }
        for (_, f, hashes) in &broken {
            // Pieces dent as projectiles: both sides name them by id.
            self.pieces.extend(f.pieces.iter().zip(hashes).map(|(p, &hash)| (hash, p.id, p.mesh.clone())));
        }
        let whole: Vec<K> = broken.iter().filter(|(_, f, _)| f.rest.is_none()).map(|(_, f, _)| f.body).collect();
        for key in whole {
            if let Some(slot) = self.bodies.iter().position(|b| b.key == key) {
                self.removed.push(self.bodies.remove(slot).id);
            }
        }
        self.next += 1;
        Ok(Some(write_message(&message)))
    }

    /// The group of body `slot` in `groups`, added (with no change yet) if it has none.
    fn group<'g>(&self, groups: &'g mut Vec<(usize, Group)>, slot: usize) -> &'g mut Group {
        let at = match groups.iter().position(|(s, _)| *s == slot) {
            Some(at) => at,
            None => {
                let body = &self.bodies[slot];
                let change = match body.sent {
                    Some(_) => GroupChange::Edit(MeshEdit::default()),
                    None => GroupChange::Dents(Vec::new()),
                };
                groups.push((slot, Group { id: body.id, check: 0, change, fracture: None }));
                groups.len() - 1
            }
        };
        &mut groups[at].1
    }

    /// A late joiner's start: every tracked body's mesh now (`mesh` gives it) as the smaller of
    /// its edit from the base and the whole mesh (the whole mesh when it is no edit of the
    /// base), and the next message's number. Take it after the [`message`](Self::message) of
    /// the last step applied, so that the joiner starts where the stream goes on.
    ///
    /// # Errors
    /// [`ReplicationError::UnknownBody`] for a tracked body `mesh` does not know.
    pub fn snapshot<'m>(&self, mesh: impl Fn(K) -> Option<&'m TriMesh>) -> Result<SnapshotBytes, ReplicationError> {
        let mut bodies = Vec::with_capacity(self.bodies.len());
        let mut whole = Vec::with_capacity(self.bodies.len());
        for b in &self.bodies {
            let now = mesh(b.key).ok_or_else(|| ReplicationError::UnknownBody(format!("{:?}", b.key)))?;
            let base = (b.base.vertex_count() as u32, b.base.face_count() as u32, b.base_hash);
            let edit = MeshEdit::between(&b.base, now).ok();
            let normals = b.normals.then(|| now.normals().to_vec());
            let entry = |form| SnapshotBody {
                id: b.id,
                base,
                settings: b.settings,
                form,
                normals: normals.clone(),
                hash: content_hash(now),
            };
            let whole_entry = entry(BodyForm::Whole(now.clone()));
            let size = |body: &SnapshotBody| {
                let alone = Snapshot { next: 0, bodies: vec![body.clone()], removed: Vec::new(), pieces: Vec::new() };
                write_snapshot(&alone).len()
            };
            let chosen = match edit.map(|e| entry(BodyForm::Edit(e))) {
                Some(as_edit) if size(&as_edit) <= size(&whole_entry) => as_edit,
                _ => whole_entry.clone(),
            };
            bodies.push(chosen);
            whole.push(whole_entry);
        }
        let removed = self.removed.clone();
        let pieces: Vec<(PieceId, TriMesh)> = self.pieces.iter().map(|(_, id, mesh)| (*id, mesh.clone())).collect();
        let full = Snapshot { next: self.next, bodies: whole, removed, pieces };
        let bytes = write_snapshot(&Snapshot { bodies, ..full.clone() });
        let full_mesh_bytes = write_snapshot(&full).len();
        Ok(SnapshotBytes { bytes, full_mesh_bytes })
    }

    /// `d` as the stream carries it.
    fn wire_dent<'m>(
        &self,
        d: &AppliedDent<K>,
        surface: &impl Fn(K) -> Option<&'m TriMesh>,
    ) -> Result<WireDent, ReplicationError> {
        let projectile = match self.bodies.iter().find(|b| b.key == d.projectile) {
            Some(b) => ProjectileId::Body(b.id),
            None => {
                let mesh = surface(d.projectile).ok_or_else(|| {
                    ReplicationError::UnknownProjectile(format!(
                        "the surface of projectile {:?} is unknown",
                        d.projectile
                    ))
                })?;
                let hash = content_hash(mesh);
                let shape = self.shapes.iter().find(|(h, _)| *h == hash).map(|&(_, id)| ProjectileId::Shape(id));
                let piece = || self.pieces.iter().find(|(h, ..)| *h == hash).map(|&(_, id, _)| ProjectileId::Piece(id));
                shape.or_else(piece).ok_or_else(|| {
                    ReplicationError::UnknownProjectile(format!(
                        "projectile {:?} dented {:?} with a mesh no id names: register it with \
                         ReplicationServer::add_projectile (and on every client)",
                        d.projectile, d.target
                    ))
                })?
            }
        };
        Ok(WireDent { projectile, distance: d.dent_distance, reach: d.reach, contact: d.local })
    }
}
