//! A client's side: the bodies' base meshes and settings and the projectile meshes, given up
//! front; a snapshot to join; then every message in order, each recomputed on the CPU and
//! checked against the server's result.

use std::collections::BTreeMap;

use super::wire::{
    BodyForm, Group, GroupChange, ProjectileId, WireBreak, check_of, outcome_check, read_message, read_snapshot,
};
use super::{ReplicationError, settings_digest};
use crate::damage::PieceId;
use crate::dent::{DentJob, DentParams, DentSettings, changed_vertices, dent_batch_tracked};
use crate::fracture::{Piece, VertexOrigin, replay};
use crate::mesh::{Refinement, TriMesh, content_hash};
use crate::record::hex64;

/// One body a message or snapshot changed on the client.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplicaChange {
    /// The body's wire id.
    pub id: u32,
    /// Vertices whose position changed, ascending (new vertices included): refit over these.
    pub moved: Vec<u32>,
    /// Whether the faces changed too (a refined dent, a fracture's rest): rebuild the collider
    /// and the render mesh.
    pub topology_changed: bool,
    /// The fracture the body went through, when it broke.
    pub fracture: Option<ReplicaFracture>,
    /// Whether the body is gone (a fracture took it whole): remove it. The client no longer
    /// has it.
    pub removed: bool,
    /// What refinement appended to the body's mesh (up to the mesh that broke, when it broke),
    /// when this client computed the message's dents itself: each new vertex's edge and each
    /// new face's parent, to carry per-vertex data over exactly ([`Asset::follow_dent`]).
    /// `None` for a change that came as a mesh (a snapshot, a progressive body's or a
    /// mesh-edit server's message), which does not tell them.
    ///
    /// [`Asset::follow_dent`]: crate::mesh::Asset::follow_dent
    pub refinement: Option<Refinement>,
}

/// A fracture replayed on the client: the server's pieces, bit for bit, for the caller to make
/// bodies of (their velocities are the game's own state to replicate).
#[derive(Debug, Clone, PartialEq)]
pub struct ReplicaFracture {
    /// The server's fracture number.
    pub number: u64,
    /// The pieces, each with its id (the server's [`PieceId`]) and its closed mesh and mass
    /// properties in the body's mesh coordinates.
    pub pieces: Vec<(PieceId, Piece)>,
    /// The mesh that broke (the message's dents included), which the pieces' and the rest's
    /// [`VertexOrigin`]s point into: for carrying attributes over
    /// ([`carry_asset`](crate::fracture::carry_asset)).
    pub broken: TriMesh,
    /// Where each vertex of the rest lies on `broken` (empty with no rest).
    pub rest_origins: Vec<VertexOrigin>,
}

/// A body's new state, staged before anything is committed.
struct Staged {
    id: u32,
    /// Its mesh after the message; `None` when it is gone.
    mesh: Option<TriMesh>,
    fracture: Option<ReplicaFracture>,
    /// What the client's own dents refined, when it computed them.
    refinement: Option<Refinement>,
}

#[derive(Debug, Clone)]
struct ClientBody {
    base: TriMesh,
    base_hash: u64,
    params: DentParams,
    /// The deepest dent its settings allow, m: a message's deeper dent is refused before it
    /// is computed.
    cap: f32,
    settings: u64,
    mesh: TriMesh,
}

/// A client's replica of the server's damage.
#[derive(Debug, Clone, Default)]
pub struct ReplicationClient {
    bodies: BTreeMap<u32, ClientBody>,
    shapes: BTreeMap<u32, TriMesh>,
    /// Pieces of the stream's fractures, projectiles that may dent.
    pieces: BTreeMap<PieceId, TriMesh>,
    /// The next message's number; `None` before the snapshot.
    next: Option<u64>,
}

impl ReplicationClient {
    /// No body yet, not joined.
    pub fn new() -> Self {
        Self::default()
    }

    /// Gives body `id` its base mesh (the one the server tracks it from, its own coordinates)
    /// and dent settings (the server's); its mesh is the base until the snapshot says otherwise.
    ///
    /// # Errors
    /// [`ReplicationError::DuplicateId`], [`ReplicationError::NotReplicable`].
    pub fn add_body(&mut self, id: u32, base: TriMesh, settings: &DentSettings) -> Result<(), ReplicationError> {
        if self.bodies.contains_key(&id) {
            return Err(ReplicationError::DuplicateId { what: "body", id });
        }
        let body = ClientBody {
            base_hash: content_hash(&base),
            params: settings.params.clone(),
            cap: settings.material.cap,
            settings: settings_digest(settings)?,
            mesh: base.clone(),
            base,
        };
        self.bodies.insert(id, body);
        Ok(())
    }

    /// Registers projectile mesh `id` (its own coordinates), as the server did.
    ///
    /// # Errors
    /// [`ReplicationError::DuplicateId`] when `id` names another mesh.
    pub fn add_projectile(&mut self, id: u32, mesh: TriMesh) -> Result<(), ReplicationError> {
        if self.shapes.get(&id).is_some_and(|m| content_hash(m) != content_hash(&mesh)) {
            return Err(ReplicationError::DuplicateId { what: "projectile", id });
        }
        self.shapes.insert(id, mesh);
        Ok(())
    }

    /// Stops keeping piece `id` (the game removed it; the server calls
    /// [`ReplicationServer::forget_piece`](super::ReplicationServer::forget_piece)).
    pub fn forget_piece(&mut self, id: PieceId) {
        self.pieces.remove(&id);
    }

    /// Piece `id`'s mesh, body mesh coordinates of the body it broke from, while the client
    /// keeps it.
    pub fn piece(&self, id: PieceId) -> Option<&TriMesh> {
        self.pieces.get(&id)
    }

    /// Body `id`'s mesh now.
    pub fn mesh(&self, id: u32) -> Option<&TriMesh> {
        self.bodies.get(&id).map(|b| &b.mesh)
    }

    /// The number of the next message to apply; `None` before [`join`](Self::join).
    pub fn next_message(&self) -> Option<u64> {
        self.next
    }

    /// Joins the stream at `snapshot` ([`ReplicationServer::snapshot`](super::ReplicationServer::snapshot)):
    /// every body the snapshot names takes the mesh it gives.
    ///
    /// # Errors
    /// [`ReplicationError::MissingBase`] for a body not added, [`ReplicationError::OtherMesh`]
    /// for a base mesh or settings other than the server's or a mesh that does not hash as the
    /// snapshot says, [`ReplicationError::Truncated`] / [`ReplicationError::Malformed`]; nothing
    /// changes then.
    pub fn join(&mut self, snapshot: &[u8]) -> Result<Vec<ReplicaChange>, ReplicationError> {
        let snapshot = read_snapshot(snapshot)?;
        let mut staged = Vec::with_capacity(snapshot.bodies.len());
        for s in &snapshot.bodies {
            let body = self.bodies.get(&s.id).ok_or(ReplicationError::MissingBase { id: s.id })?;
            let found = (body.base.vertex_count() as u32, body.base.face_count() as u32, body.base_hash);
            if found != s.base {
                let show = |b: (u32, u32, u64)| format!("{} vertices, {} faces, hash {}", b.0, b.1, hex64(b.2));
                return Err(other(s.id, "the base mesh", show(s.base), show(found)));
            }
            if body.settings != s.settings {
                return Err(other(s.id, "the dent settings' digest", hex64(s.settings), hex64(body.settings)));
            }
            let mesh = match &s.form {
                BodyForm::Edit(edit) => {
                    edit.apply(&body.base).map_err(|error| ReplicationError::Mesh { id: s.id, error })?
                }
                BodyForm::Whole(mesh) => mesh.clone(),
            };
            // The server's normals where the dents read them (a rebuilt mesh has the ones its
            // positions and faces give).
            let mesh = match &s.normals {
                Some(normals) => {
                    TriMesh::with_normals(mesh.positions().to_vec(), mesh.faces().to_vec(), normals.clone())
                        .map_err(|error| ReplicationError::Mesh { id: s.id, error })?
                }
                None => mesh,
            };
            let hash = content_hash(&mesh);
            if hash != s.hash {
                return Err(other(s.id, "the joined mesh's hash", hex64(s.hash), hex64(hash)));
            }
            staged.push(Staged { id: s.id, mesh: Some(mesh), fracture: None, refinement: None });
        }
        // Removed bodies this client does not have are passed over by the commit.
        staged.extend(snapshot.removed.iter().map(|&id| Staged { id, mesh: None, fracture: None, refinement: None }));
        let changes = self.commit(staged);
        self.pieces = snapshot.pieces.into_iter().collect();
        self.next = Some(snapshot.next);
        Ok(changes)
    }

    /// Applies the next message: each body's dents recomputed on the CPU (every map from the
    /// meshes before the message), or its edit applied, and checked against the server's
    /// result. Returns what changed, for the caller's colliders and render meshes.
    ///
    /// # Errors
    /// [`ReplicationError::NotJoined`], [`ReplicationError::OutOfOrder`],
    /// [`ReplicationError::Repeated`], [`ReplicationError::Truncated`],
    /// [`ReplicationError::Malformed`], [`ReplicationError::MissingBase`],
    /// [`ReplicationError::UnknownProjectile`], [`ReplicationError::OtherMesh`] (a result that
    /// differs from the server's: the message was made for another mesh), or a dent or edit that
    /// fails; nothing changes then.
    pub fn apply(&mut self, message: &[u8]) -> Result<Vec<ReplicaChange>, ReplicationError> {
        let expected = self.next.ok_or(ReplicationError::NotJoined)?;
        let message = read_message(message)?;
        if message.number < expected {
            return Err(ReplicationError::Repeated { expected, found: message.number });
        }
        if message.number > expected {
            return Err(ReplicationError::OutOfOrder { expected, found: message.number });
        }
        let staged: Vec<Staged> = message.groups.iter().map(|g| self.changed(g)).collect::<Result<_, _>>()?;
        let next = expected
            .checked_add(1)
            .ok_or_else(|| ReplicationError::Malformed("the stream's message numbers are used up".into()))?;
        let changes = self.commit(staged);
        self.next = Some(next);
        Ok(changes)
    }

    /// Gives each staged body its new mesh, or removes it; returns what changed.
    fn commit(&mut self, staged: Vec<Staged>) -> Vec<ReplicaChange> {
        let mut changes = Vec::with_capacity(staged.len());
        for Staged { id, mesh, fracture, refinement } in staged {
            let made = fracture.iter().flat_map(|f| &f.pieces);
            self.pieces.extend(made.map(|(piece_id, piece)| (*piece_id, piece.mesh.clone())));
            let Some(body) = self.bodies.get_mut(&id) else { continue };
            match mesh {
                Some(mesh) => {
                    let moved = changed_vertices(&body.mesh, &mesh);
                    let topology_changed = body.mesh.faces() != mesh.faces();
                    changes.push(ReplicaChange { id, moved, topology_changed, fracture, removed: false, refinement });
                    body.mesh = mesh;
                }
                None => {
                    self.bodies.remove(&id);
                    changes.push(ReplicaChange {
                        id,
                        moved: Vec::new(),
                        topology_changed: true,
                        fracture,
                        removed: true,
                        refinement,
                    });
                }
            }
        }
        changes
    }

    /// Body `g.id` after its group: its change checked against the group's hash, then its
    /// fracture replayed and checked.
    fn changed(&self, g: &Group) -> Result<Staged, ReplicationError> {
        let (mesh, refinement) = self.changed_mesh(g)?;
        let Some(wire) = &g.fracture else {
            return Ok(Staged { id: g.id, mesh: Some(mesh), fracture: None, refinement });
        };
        let (rest, fracture) = replay_break(g.id, &mesh, wire)?;
        Ok(Staged { id: g.id, mesh: rest, fracture: Some(fracture), refinement })
    }

    /// Body `g.id`'s mesh after its group's change, checked against the group's hash, with
    /// what refinement appended to it when the client computed the dents itself.
    fn changed_mesh(&self, g: &Group) -> Result<(TriMesh, Option<Refinement>), ReplicationError> {
        let body = self.bodies.get(&g.id).ok_or(ReplicationError::MissingBase { id: g.id })?;
        let mut refinement = None;
        let mesh = match &g.change {
            GroupChange::Edit(edit) => {
                edit.apply(&body.mesh).map_err(|error| ReplicationError::Mesh { id: g.id, error })?
            }
            GroupChange::Whole(mesh) => mesh.clone(),
            GroupChange::Dents(dents) => {
                let mut cropped = Vec::with_capacity(dents.len());
                for d in dents {
                    if d.distance > body.cap {
                        return Err(ReplicationError::Malformed(format!(
                            "body {}: a dent of {} m, deeper than its settings' cap of {} m",
                            g.id, d.distance, body.cap
                        )));
                    }
                    let projectile = match d.projectile {
                        ProjectileId::Body(id) => {
                            &self.bodies.get(&id).ok_or(ReplicationError::MissingBase { id })?.mesh
                        }
                        ProjectileId::Shape(id) => self.shapes.get(&id).ok_or_else(|| {
                            ReplicationError::UnknownProjectile(format!(
                                "projectile mesh {id} is not registered on this client \
                                 (ReplicationClient::add_projectile with the server's mesh)"
                            ))
                        })?,
                        ProjectileId::Piece(id) => self.pieces.get(&id).ok_or_else(|| {
                            ReplicationError::UnknownProjectile(format!(
                                "piece {} of fracture {} is not on this client: it was forgotten \
                                 (forget_piece) while the server still names it",
                                id.index, id.fracture
                            ))
                        })?,
                    };
                    cropped.push(d.contact.crop(projectile, d.reach));
                }
                let jobs: Vec<DentJob<'_>> = dents
                    .iter()
                    .zip(&cropped)
                    .filter_map(|(d, c)| {
                        Some(DentJob {
                            target: 0,
                            projectile: c.as_ref()?,
                            impact: d.contact.impact(),
                            params: DentParams { dent_distance: d.distance, ..body.params.clone() },
                        })
                    })
                    .collect();
                let mut meshes = vec![body.mesh.clone()];
                if jobs.is_empty() {
                    return Ok((self.checked(g, meshes.swap_remove(0))?, Some(Refinement::default())));
                }
                let outcome = dent_batch_tracked(&mut meshes, &jobs).map_err(|e| ReplicationError::Dent {
                    id: g.id,
                    dent: e.job,
                    error: e.error,
                })?;
                refinement = Some(outcome.refined.into_iter().next().unwrap_or_default());
                meshes.pop().unwrap_or_else(|| body.mesh.clone())
            }
        };
        Ok((self.checked(g, mesh)?, refinement))
    }

    /// `mesh` when its hash is the one group `g` carries.
    fn checked(&self, g: &Group, mesh: TriMesh) -> Result<TriMesh, ReplicationError> {
        let found = check_of(content_hash(&mesh));
        if found != g.check {
            return Err(other(
                g.id,
                "the result's hash (low 32 bits)",
                format!("{:08x}", g.check),
                format!("{found:08x}"),
            ));
        }
        Ok(mesh)
    }
}

/// Body `id`'s fracture `wire` replayed on `mesh` (its mesh when it broke): its rest (`None`:
/// the pattern took it whole) and the pieces, checked against the server's.
fn replay_break(
    id: u32,
    mesh: &TriMesh,
    wire: &WireBreak,
) -> Result<(Option<TriMesh>, ReplicaFracture), ReplicationError> {
    let outcome = replay(mesh, &wire.record)
        .map_err(|error| ReplicationError::Fracture { id, error })?
        .ok_or_else(|| other(id, "the fracture", "pieces".into(), "a pattern that misses the body".into()))?;
    let found = outcome_check(outcome.rest.as_ref(), outcome.pieces.iter().map(|p| content_hash(&p.mesh)));
    if found != wire.check {
        return Err(other(
            id,
            "the fracture's hash (low 32 bits)",
            format!("{:08x}", wire.check),
            format!("{found:08x}"),
        ));
    }
    let pieces = outcome
        .pieces
        .into_iter()
        .enumerate()
        .map(|(index, piece)| (PieceId { fracture: wire.number, index: index as u32 }, piece))
        .collect();
    let fracture =
        ReplicaFracture { number: wire.number, pieces, broken: mesh.clone(), rest_origins: outcome.rest_origins };
    Ok((outcome.rest, fracture))
}

fn other(id: u32, what: &'static str, expected: String, found: String) -> ReplicationError {
    ReplicationError::OtherMesh { id, what, expected, found }
}
