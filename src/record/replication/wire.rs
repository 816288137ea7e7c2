//! The bytes of the replication stream.
//!
//! A **message** (one server step): tag `0xD1`, message number (varint), group count (varint),
//! then per changed body: its id (varint), a header (varint: bits 0–1 the change, 0 dents, 1 a
//! mesh edit, 2 the whole mesh; bit 2 a fracture follows; bits 3 and up the number of dents),
//! the low 32 bits of the body's content hash after the change (u32), then the dents, the edit
//! ([`write_edit`]) or the mesh (as in a snapshot), then the fracture if one follows: its
//! number (varint), the break ([`write_break`]) and the low 32 bits of the hash of what it
//! made ([`outcome_check`], u32).
//!
//! A **dent** (54 bytes for a rotation, 78 for a scaled pose): flags (u8: bits 0–1 the
//! rotation's dropped component, bit 2 a whole matrix, bit 3 the projectile is a tracked body,
//! bit 4 a piece of a fracture the stream carried), the projectile's id (varint; a piece's is
//! its fracture number and its index, two varints), dent distance and crop reach (f32, m), contact point (3 × f32),
//! normal and view codes (2 × 2 × u16), rotation (3 × f32, or 9 × f32), translation (3 × f32).
//!
//! A **snapshot** (a late joiner's start): tag `0xD5`, version (u8), the next message number
//! (varint), body count (varint), then per body: id (varint), base mesh stamp (vertex and face
//! counts as varints, content hash u64), settings digest (u64), form (u8: 0 an edit from the
//! base, 1 the whole mesh; plus 2 when every vertex normal follows), the edit or the mesh, the
//! normals (a varint count, 3 × f32 each), content hash of the body's mesh (u64); then the ids
//! of the bodies a fracture took whole (a varint count, varints); then the pieces of carried
//! fractures still in play (a varint count; per piece its fracture number and index as varints
//! and its mesh).

use glam::{Mat3A, Vec3};

use super::super::break_codec::{read_break, write_break};
use super::super::bytes::{ByteReader, ByteWriter};
use super::super::edit_codec::{MAX_EDIT_ITEMS, read_edit, write_edit};
use super::ReplicationError;
use crate::damage::PieceId;
use crate::dent::{LocalContact, OctDirection, PoseRotation};
use crate::fracture::FractureRecord;
use crate::mesh::{MeshEdit, TriMesh, content_hash, fnv1a64, fnv1a64_start};

/// First byte of a message.
pub(crate) const MESSAGE_TAG: u8 = 0xD1;
/// First byte of a snapshot.
pub(crate) const SNAPSHOT_TAG: u8 = 0xD5;
/// Snapshot format version.
pub(crate) const SNAPSHOT_VERSION: u8 = 2;

/// Most bodies or groups one message or snapshot may declare.
pub const MAX_BODIES: u64 = 1 << 20;
/// Most dents one group may declare.
pub const MAX_GROUP_DENTS: u64 = 1 << 20;

/// What dented a body: a tracked body (its mesh before the message's dents) or a registered
/// projectile mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProjectileId {
    /// A body the stream tracks, by id.
    Body(u32),
    /// A projectile mesh both sides registered, by id.
    Shape(u32),
    /// A piece of a fracture the stream carried (both sides have its mesh from the fracture).
    Piece(PieceId),
}

/// One dent as the stream carries it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WireDent {
    /// What dented the body.
    pub projectile: ProjectileId,
    /// Dent distance, m.
    pub distance: f32,
    /// How far from the contact the projectile is cropped, m.
    pub reach: f32,
    /// The contact, target mesh coordinates.
    pub contact: LocalContact,
}

/// One body's change in a message.
#[derive(Debug, Clone, PartialEq)]
pub enum GroupChange {
    /// Dents recomputed on the client, in order, every map from the body's mesh before them.
    Dents(Vec<WireDent>),
    /// An exact edit of the body's mesh (a progressive dent, rebuilt from a pre-dent surface).
    Edit(MeshEdit),
    /// The body's whole mesh (a progressive dent rebuilt with fewer vertices than the mesh it
    /// replaces, which no edit can express).
    Whole(TriMesh),
}

/// A fracture as the stream carries it: the client replays the break on the body's mesh after
/// the group's change.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WireBreak {
    /// The server's fracture number (its pieces' [`PieceId::fracture`](crate::damage::PieceId)).
    pub number: u64,
    /// The break, body mesh coordinates.
    pub record: FractureRecord,
    /// Low 32 bits of [`outcome_check`] of the rest and pieces it made.
    pub check: u32,
}

/// One body's part of a message.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// The body's id.
    pub id: u32,
    /// Low 32 bits of the body's content hash after the change (before a fracture).
    pub check: u32,
    /// The change.
    pub change: GroupChange,
    /// The fracture that followed the change, if the body broke.
    pub fracture: Option<WireBreak>,
}

/// A decoded message.
#[derive(Debug, Clone, PartialEq)]
pub struct Message {
    /// Its number in the stream (0 = the first).
    pub number: u64,
    /// The bodies it changes, each once.
    pub groups: Vec<Group>,
}

/// The form of one body in a snapshot.
#[derive(Debug, Clone, PartialEq)]
pub enum BodyForm {
    /// An edit of the base mesh.
    Edit(MeshEdit),
    /// The whole mesh.
    Whole(TriMesh),
}

/// One body in a snapshot.
#[derive(Debug, Clone, PartialEq)]
pub struct SnapshotBody {
    /// The body's id.
    pub id: u32,
    /// Base mesh: vertex count, face count, content hash.
    pub base: (u32, u32, u64),
    /// Digest of the body's dent settings.
    pub settings: u64,
    /// Its mesh now.
    pub form: BodyForm,
    /// Its vertex normals now, for a body whose dents read them (the rim of
    /// `VolumeMode::Preserve`): a dent refreshes normals only around what it moved, so they are
    /// not always the ones the positions and faces give (authored normals).
    pub normals: Option<Vec<Vec3>>,
    /// Content hash of its mesh now.
    pub hash: u64,
}

/// A decoded snapshot.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// The number of the first message to apply after it.
    pub next: u64,
    /// Every tracked body.
    pub bodies: Vec<SnapshotBody>,
    /// Bodies a fracture took whole: a joiner removes them.
    pub removed: Vec<u32>,
    /// Pieces of carried fractures still in play, with their meshes (projectiles that may dent).
    pub pieces: Vec<(PieceId, TriMesh)>,
}

/// A dent's flag bit: the projectile is a tracked body.
const BODY_FLAG: u8 = 8;
/// A dent's flag bit: the projectile is a piece of a carried fracture.
const PIECE_FLAG: u8 = 16;

/// A snapshot body's form bit: its vertex normals follow its mesh.
const NORMALS_FOLLOW: u8 = 2;

/// A group header's change kinds (bits 0–1).
const DENTS_KIND: u64 = 0;
const EDIT_KIND: u64 = 1;
const WHOLE_KIND: u64 = 2;
/// A group header's bit: a fracture follows the change.
const FRACTURE_FOLLOWS: u64 = 4;
/// Where a group header's dent count starts.
const COUNT_SHIFT: u32 = 3;

/// The low 32 bits of a content hash, as a group's check.
pub fn check_of(hash: u64) -> u32 {
    hash as u32
}

/// The check of what a fracture made: the low 32 bits of an FNV-1a hash over the content
/// hashes of its rest (0 for none) and of its pieces (`piece_hashes`, in order).
pub fn outcome_check(rest: Option<&TriMesh>, piece_hashes: impl IntoIterator<Item = u64>) -> u32 {
    let mut h = fnv1a64(fnv1a64_start(), &rest.map_or(0, content_hash).to_le_bytes());
    for piece in piece_hashes {
        h = fnv1a64(h, &piece.to_le_bytes());
    }
    check_of(h)
}

/// Encodes `message`.
pub fn write_message(message: &Message) -> Vec<u8> {
    let mut out = ByteWriter::default();
    out.u8(MESSAGE_TAG);
    out.varint(message.number);
    out.varint(message.groups.len() as u64);
    for g in &message.groups {
        out.varint(u64::from(g.id));
        let follows = if g.fracture.is_some() { FRACTURE_FOLLOWS } else { 0 };
        match &g.change {
            GroupChange::Dents(dents) => {
                out.varint(((dents.len() as u64) << COUNT_SHIFT) | DENTS_KIND | follows);
                out.u32(g.check);
                dents.iter().for_each(|d| write_dent(&mut out, d));
            }
            GroupChange::Edit(edit) => {
                out.varint(EDIT_KIND | follows);
                out.u32(g.check);
                write_edit(&mut out, edit);
            }
            GroupChange::Whole(mesh) => {
                out.varint(WHOLE_KIND | follows);
                out.u32(g.check);
                write_whole(&mut out, mesh);
            }
        }
        if let Some(f) = &g.fracture {
            out.varint(f.number);
            // A server's fractures are made live: they keep the mesh's seams.
            debug_assert!(!f.record.weld_output, "a replicated fracture has welded output");
            write_break(&mut out, &f.record);
            out.u32(f.check);
        }
    }
    out.bytes
}

/// Decodes a message, checking every length before it reads.
///
/// # Errors
/// [`ReplicationError::Truncated`], [`ReplicationError::Malformed`].
pub fn read_message(bytes: &[u8]) -> Result<Message, ReplicationError> {
    let mut r = ByteReader::new(bytes);
    let tag = r.u8("message tag")?;
    if tag != MESSAGE_TAG {
        return Err(ReplicationError::Malformed(format!("tag {tag:#04x} is no replication message's")));
    }
    let number = r.varint("message number")?;
    // A group takes at least an id, a header and a check: 6 bytes.
    let n = r.count("message groups", 6, MAX_BODIES)?;
    let mut groups = Vec::with_capacity(n);
    let mut ids = std::collections::HashSet::with_capacity(n);
    for _ in 0..n {
        let id = r.varint32("body id")?;
        let header = r.varint("group header")?;
        let check = r.u32("group check")?;
        let follows = header & FRACTURE_FOLLOWS != 0;
        let count = header >> COUNT_SHIFT;
        let bad_header = || ReplicationError::Malformed(format!("body {id}: group header {header}"));
        let change = match header & 3 {
            DENTS_KIND => {
                if (count == 0 && !follows) || count > MAX_GROUP_DENTS {
                    return Err(ReplicationError::Malformed(format!("body {id}: a group of {count} dents")));
                }
                let mut dents = Vec::with_capacity((count as usize).min(r.remaining() / 54));
                for _ in 0..count {
                    dents.push(read_dent(&mut r)?);
                }
                GroupChange::Dents(dents)
            }
            EDIT_KIND if count == 0 => GroupChange::Edit(read_edit(&mut r)?),
            WHOLE_KIND if count == 0 => GroupChange::Whole(read_whole(&mut r)?),
            _ => return Err(bad_header()),
        };
        let fracture = if follows {
            let number = r.varint("fracture number")?;
            let record = read_break(&mut r)?;
            Some(WireBreak { number, record, check: r.u32("fracture check")? })
        } else {
            None
        };
        if !ids.insert(id) {
            return Err(ReplicationError::Malformed(format!("body {id} appears twice in message {number}")));
        }
        groups.push(Group { id, check, change, fracture });
    }
    if r.remaining() != 0 {
        return Err(ReplicationError::Malformed(format!("{} bytes after the message's end", r.remaining())));
    }
    Ok(Message { number, groups })
}

fn write_dent(out: &mut ByteWriter, d: &WireDent) {
    let (rotation_bits, matrix) = match d.contact.rotation {
        PoseRotation::Quaternion { largest, .. } => (largest & 3, false),
        PoseRotation::Matrix(_) => (0, true),
    };
    let kind = match d.projectile {
        ProjectileId::Body(_) => BODY_FLAG,
        ProjectileId::Shape(_) => 0,
        ProjectileId::Piece(_) => PIECE_FLAG,
    };
    out.u8(rotation_bits | (u8::from(matrix) << 2) | kind);
    match d.projectile {
        ProjectileId::Body(id) | ProjectileId::Shape(id) => out.varint(u64::from(id)),
        ProjectileId::Piece(piece) => write_piece_id(out, piece),
    }
    out.f32(d.distance);
    out.f32(d.reach);
    out.vec3(d.contact.point);
    d.contact.normal.0.iter().chain(&d.contact.view.0).for_each(|&c| out.u16(c));
    match d.contact.rotation {
        PoseRotation::Quaternion { rest, .. } => rest.iter().for_each(|&c| out.f32(c)),
        PoseRotation::Matrix(m) => m.to_cols_array().iter().for_each(|&c| out.f32(c)),
    }
    out.vec3(d.contact.translation);
}

fn read_dent(r: &mut ByteReader<'_>) -> Result<WireDent, ReplicationError> {
    let flags = r.u8("dent flags")?;
    if flags >> 5 != 0 || flags & (BODY_FLAG | PIECE_FLAG) == BODY_FLAG | PIECE_FLAG {
        return Err(ReplicationError::Malformed(format!("dent flags {flags:#04x}")));
    }
    let projectile = if flags & PIECE_FLAG != 0 {
        ProjectileId::Piece(read_piece_id(r)?)
    } else if flags & BODY_FLAG != 0 {
        ProjectileId::Body(r.varint32("projectile id")?)
    } else {
        ProjectileId::Shape(r.varint32("projectile id")?)
    };
    let distance = r.f32("dent distance")?;
    let reach = r.f32("crop reach")?;
    let point = r.vec3("contact point")?;
    let normal = OctDirection([r.u16("normal")?, r.u16("normal")?]);
    let view = OctDirection([r.u16("view")?, r.u16("view")?]);
    let rotation = if flags & 4 != 0 {
        let mut cols = [0.0f32; 9];
        for c in &mut cols {
            *c = r.f32("rotation matrix")?;
        }
        PoseRotation::Matrix(Mat3A::from_cols_array(&cols))
    } else {
        let rest = [r.f32("rotation")?, r.f32("rotation")?, r.f32("rotation")?];
        PoseRotation::Quaternion { largest: flags & 3, rest }
    };
    let translation = r.vec3("translation")?;
    let finite = [distance, reach].iter().all(|v| v.is_finite())
        && point.is_finite()
        && translation.is_finite()
        && match rotation {
            PoseRotation::Matrix(m) => m.is_finite(),
            PoseRotation::Quaternion { rest, .. } => rest.iter().all(|c| c.is_finite() && c.abs() <= 1.0),
        };
    if !finite || distance < 0.0 || reach <= 0.0 {
        return Err(ReplicationError::Malformed(format!(
            "a dent with distance {distance}, reach {reach}, point {point}, translation {translation}"
        )));
    }
    let contact = LocalContact { point, normal, view, rotation, translation };
    Ok(WireDent { projectile, distance, reach, contact })
}

/// Encodes `snapshot`.
pub fn write_snapshot(snapshot: &Snapshot) -> Vec<u8> {
    let mut out = ByteWriter::default();
    out.u8(SNAPSHOT_TAG);
    out.u8(SNAPSHOT_VERSION);
    out.varint(snapshot.next);
    out.varint(snapshot.bodies.len() as u64);
    for b in &snapshot.bodies {
        out.varint(u64::from(b.id));
        out.varint(u64::from(b.base.0));
        out.varint(u64::from(b.base.1));
        out.u64(b.base.2);
        out.u64(b.settings);
        let with_normals = if b.normals.is_some() { NORMALS_FOLLOW } else { 0 };
        match &b.form {
            BodyForm::Edit(edit) => {
                out.u8(with_normals);
                write_edit(&mut out, edit);
            }
            BodyForm::Whole(mesh) => {
                out.u8(1 | with_normals);
                write_whole(&mut out, mesh);
            }
        }
        if let Some(normals) = &b.normals {
            out.varint(normals.len() as u64);
            normals.iter().for_each(|&n| out.vec3(n));
        }
        out.u64(b.hash);
    }
    out.varint(snapshot.removed.len() as u64);
    snapshot.removed.iter().for_each(|&id| out.varint(u64::from(id)));
    out.varint(snapshot.pieces.len() as u64);
    for (id, mesh) in &snapshot.pieces {
        write_piece_id(&mut out, *id);
        write_whole(&mut out, mesh);
    }
    out.bytes
}

fn write_piece_id(out: &mut ByteWriter, id: PieceId) {
    out.varint(id.fracture);
    out.varint(u64::from(id.index));
}

fn read_piece_id(r: &mut ByteReader<'_>) -> Result<PieceId, ReplicationError> {
    Ok(PieceId { fracture: r.varint("piece's fracture number")?, index: r.varint32("piece index")? })
}

/// Decodes a snapshot.
///
/// # Errors
/// [`ReplicationError::Truncated`], [`ReplicationError::Malformed`] (a mesh in it that is no
/// valid mesh included).
pub fn read_snapshot(bytes: &[u8]) -> Result<Snapshot, ReplicationError> {
    let mut r = ByteReader::new(bytes);
    let tag = r.u8("snapshot tag")?;
    if tag != SNAPSHOT_TAG {
        return Err(ReplicationError::Malformed(format!("tag {tag:#04x} is no replication snapshot's")));
    }
    let version = r.u8("snapshot version")?;
    if version != SNAPSHOT_VERSION {
        return Err(ReplicationError::Malformed(format!(
            "snapshot version {version}; this build reads version {SNAPSHOT_VERSION}"
        )));
    }
    let next = r.varint("next message number")?;
    // A body takes at least 1 + 1 + 1 + 8 + 8 + 1 + 2 + 8 bytes.
    let n = r.count("snapshot bodies", 30, MAX_BODIES)?;
    let mut bodies = Vec::with_capacity(n);
    let mut ids = std::collections::HashSet::with_capacity(n);
    for _ in 0..n {
        let id = r.varint32("body id")?;
        let base = (r.varint32("base vertex count")?, r.varint32("base face count")?, r.u64("base hash")?);
        let settings = r.u64("settings digest")?;
        let form_byte = r.u8("body form")?;
        let form = match form_byte & !NORMALS_FOLLOW {
            0 => BodyForm::Edit(read_edit(&mut r)?),
            1 => BodyForm::Whole(read_whole(&mut r)?),
            other => return Err(ReplicationError::Malformed(format!("body {id}: form {other}"))),
        };
        let normals = if form_byte & NORMALS_FOLLOW != 0 {
            let n = r.count("body normals", 12, MAX_EDIT_ITEMS)?;
            Some((0..n).map(|_| r.vec3("body normal")).collect::<Result<Vec<_>, _>>()?)
        } else {
            None
        };
        let hash = r.u64("body hash")?;
        if !ids.insert(id) {
            return Err(ReplicationError::Malformed(format!("body {id} appears twice in the snapshot")));
        }
        bodies.push(SnapshotBody { id, base, settings, form, normals, hash });
    }
    let n = r.count("removed bodies", 1, MAX_BODIES)?;
    let removed = (0..n).map(|_| r.varint32("removed body id")).collect::<Result<Vec<_>, _>>()?;
    for id in &removed {
        if !ids.insert(*id) {
            return Err(ReplicationError::Malformed(format!("body {id} is named twice in the snapshot")));
        }
    }
    // A piece takes at least two ids and two counts.
    let n = r.count("snapshot pieces", 4, MAX_BODIES)?;
    let mut pieces = Vec::with_capacity(n);
    let mut seen = std::collections::HashSet::with_capacity(n);
    for _ in 0..n {
        let id = read_piece_id(&mut r)?;
        if !seen.insert(id) {
            return Err(ReplicationError::Malformed(format!("piece {id:?} appears twice in the snapshot")));
        }
        pieces.push((id, read_whole(&mut r)?));
    }
    if r.remaining() != 0 {
        return Err(ReplicationError::Malformed(format!("{} bytes after the snapshot's end", r.remaining())));
    }
    Ok(Snapshot { next, bodies, removed, pieces })
}

fn write_whole(out: &mut ByteWriter, mesh: &TriMesh) {
    out.varint(mesh.vertex_count() as u64);
    out.varint(mesh.face_count() as u64);
    mesh.positions().iter().for_each(|&p| out.vec3(p));
    mesh.faces().iter().flatten().for_each(|&v| out.u32(v));
}

fn read_whole(r: &mut ByteReader<'_>) -> Result<TriMesh, ReplicationError> {
    let nv = r.count("mesh vertices", 12, MAX_EDIT_ITEMS)?;
    let nf = r.count("mesh faces", 12, MAX_EDIT_ITEMS)?;
    let positions: Vec<Vec3> = (0..nv).map(|_| r.vec3("mesh vertex")).collect::<Result<_, _>>()?;
    let mut faces = Vec::with_capacity(nf);
    for _ in 0..nf {
        faces.push([r.u32("mesh face")?, r.u32("mesh face")?, r.u32("mesh face")?]);
    }
    TriMesh::new(positions, faces).map_err(|e| ReplicationError::Malformed(format!("a whole mesh: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_whole_mesh_group_round_trips_and_a_bad_header_is_refused() {
        let mesh = crate::mesh::icosphere(0.5, 1).expect("a sphere");
        let message = Message {
            number: 7,
            groups: vec![Group { id: 3, check: 0xdead_beef, change: GroupChange::Whole(mesh.clone()), fracture: None }],
        };
        let bytes = write_message(&message);
        let back = read_message(&bytes).expect("read back");
        assert_eq!(back.number, 7);
        match &back.groups[0].change {
            GroupChange::Whole(m) => {
                assert_eq!(m.positions(), mesh.positions());
                assert_eq!(m.faces(), mesh.faces());
            }
            other => panic!("{other:?}"),
        }
        // Tag, number, group count, id, then the header: 3 is no change kind a writer makes.
        let mut bad = bytes.clone();
        bad[4] = 3;
        assert!(matches!(read_message(&bad), Err(ReplicationError::Malformed(_))));
    }
}
