//! The records of one body's damage, in the order they happened, and their binary form (one
//! tag byte, then the record's fields, little-endian).

use glam::{Affine3A, Quat, Vec3};

use super::RecordError;
use super::break_codec::{read_break, write_break};
use super::bytes::{ByteReader, ByteWriter};
use super::edit_codec::{read_edit, write_edit};
use super::params_codec::{read_params, write_params};
use crate::dent::{DentParams, Impact};
use crate::mesh::{MeshEdit, Refinement, SplitVertex};

/// Most records of one body, and most dents of one batch.
pub(crate) const MAX_RECORDS: u64 = 1 << 24;

/// A projectile as an impact record names it: by its mesh's
/// [`content_hash`](crate::mesh::content_hash) (and built-in name, when it is one) and its pose.
#[derive(Debug, Clone, PartialEq)]
pub struct ProjectileRef {
    /// Content hash of the projectile's whole mesh, its own coordinates.
    pub hash: u64,
    /// Its [`mesh::builtin`](crate::mesh::builtin) name, when it is one.
    pub builtin: Option<String>,
    /// Its mesh → world transform at the contact.
    pub to_world: Affine3A,
}

/// One dent as its impact and parameters: what a multiplayer client receives instead of a mesh.
/// The replay recomputes it on the CPU (deterministic), cropping the projectile exactly as the
/// damage API did.
#[derive(Debug, Clone)]
pub struct ImpactDent {
    /// The contact, world coordinates, normal into the target.
    pub impact: Impact,
    /// The target's mesh → world transform at the contact.
    pub target_to_world: Affine3A,
    /// The projectile.
    pub projectile: ProjectileRef,
    /// The crop radius about the contact the projectile was cut to, m.
    pub reach: f32,
    /// Every dent parameter, `dent_distance` the distance decided.
    pub params: DentParams,
    /// Whether it deepened a progressive dent (rebuilt from a pre-dent surface; not replayable
    /// from the impact alone).
    pub progressive: bool,
}

/// Dents that changed a body together (one batch: maps from the same surface, applied in order).
#[derive(Debug, Clone)]
pub struct DentBatch {
    /// How many dents the batch holds.
    pub dents: u32,
    /// The dents as impacts (empty when recorded as edits only).
    pub impacts: Vec<ImpactDent>,
    /// The batch's result as a mesh edit (`None` when recorded as impacts only).
    pub edit: Option<MeshEdit>,
    /// Content hash of the body's mesh after the batch.
    pub after: u64,
    /// What the batch's refinement appended (each new vertex's edge, each new face's parent),
    /// when recorded: a replay carries per-vertex data (UVs, normals) over exactly with it.
    /// `None` when the batch did not refine, or the recording did not say.
    pub refinement: Option<Refinement>,
}

/// A plastic bend of one joint during a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointBend {
    /// Step (1 = the first).
    pub frame: u64,
    /// Joint index in the world.
    pub joint: u32,
    /// Angle the joint's rest rotation turned by, rad.
    pub angle: f32,
}

/// A joint's rest rotation at the end of the recording.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointRest {
    /// Joint index in the world.
    pub joint: u32,
    /// The rest (target) relative rotation, child in parent.
    pub rest: Quat,
}

/// A bone split where a fast hit landed (dynamic articulation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoneSplit {
    /// Step (1 = the first).
    pub frame: u64,
    /// Index of the new joint in the world.
    pub joint: u32,
    /// Where, world, m.
    pub position: Vec3,
    /// Where in the body's rest frame, m.
    pub rest_position: Vec3,
}

/// Longest body name a record names, bytes.
pub(crate) const MAX_NAME_BYTES: u64 = 4096;

/// A piece of a [`FractureRecord`] that became a body of its own.
#[derive(Debug, Clone, PartialEq)]
pub struct FracturePiece {
    /// The new body's name (its own [`BodyDamage`](super::BodyDamage) in the file).
    pub name: String,
    /// Its index in the fracture's [`pieces`](crate::fracture::FractureOutcome::pieces) (slivers
    /// that could not become bodies are skipped).
    pub index: u32,
    /// The translation that took the piece's mesh to the new body's coordinates (minus its
    /// centre of mass), m; zero: not moved.
    pub shift: Vec3,
    /// Content hash of the piece's mesh, shifted (the new body's base): the rest alone does not
    /// show the pattern's cells.
    pub hash: u64,
}

/// A prescored fracture: the body broke along a pattern into its rest (the body's new mesh) and
/// pieces that became bodies. [`replay_body`](super::replay_body) moves the mesh by
/// [`to_model`](Self::to_model), rebuilds the fracture with [`crate::fracture::replay`], and
/// moves the rest by [`rest_shift`](Self::rest_shift) and each piece by its own shift.
#[derive(Debug, Clone, PartialEq)]
pub struct FractureRecord {
    /// Step (1 = the first).
    pub frame: u64,
    /// The fracture as the fracture module rebuilds it (pattern, placement, density, welded
    /// output or not), in the coordinates [`to_model`](Self::to_model) takes the mesh to.
    pub fracture: crate::fracture::FractureRecord,
    /// The translation from the body's mesh coordinates to those it broke in, m.
    pub to_model: Vec3,
    /// The translation that took the rest to the body's new coordinates, m; zero: not moved.
    pub rest_shift: Vec3,
    /// The pieces that became bodies, in the order they were added.
    pub pieces: Vec<FracturePiece>,
    /// Content hash of the body's mesh after the fracture (the rest, shifted).
    pub after: u64,
}

/// One entry of a body's damage.
#[derive(Debug, Clone)]
pub enum DamageRecord {
    /// Dents (tag 1).
    Dents(DentBatch),
    /// A plastic bend (tag 2).
    Bend(JointBend),
    /// A joint's final rest rotation (tag 3).
    Rest(JointRest),
    /// A bone split (tag 4).
    Split(BoneSplit),
    /// A fracture (tag 5; tag 7 when its output is welded, as version 1 files broke meshes with
    /// seams).
    Fracture(FractureRecord),
    /// The final skinned (bent) surface as an edit of the mesh so far, with the hash after it
    /// (tag 6): a bending body's mesh is rebuilt from this, not from its joints.
    Skinned {
        /// The edit.
        edit: MeshEdit,
        /// Content hash after it.
        after: u64,
    },
}

/// `records` as little-endian binary (the bytes a damage file carries in base64 per body; on
/// their own, a compact network message: an impact dent is about 180 bytes).
///
/// # Errors
/// [`RecordError::NotRecordable`] for a dent with a custom falloff.
pub fn encode_records(records: &[DamageRecord]) -> Result<Vec<u8>, RecordError> {
    let mut out = ByteWriter::default();
    write_records(&mut out, records)?;
    Ok(out.bytes)
}

/// Reads [`encode_records`]' bytes, every count checked against the bytes left before anything
/// is allocated.
///
/// # Errors
/// [`RecordError::Truncated`], [`RecordError::TooLarge`], [`RecordError::Malformed`] (also for
/// bytes left over after the records).
pub fn decode_records(bytes: &[u8]) -> Result<Vec<DamageRecord>, RecordError> {
    let mut reader = ByteReader::new(bytes);
    let records = read_records(&mut reader)?;
    match reader.remaining() {
        0 => Ok(records),
        n => Err(RecordError::Malformed(format!("{n} bytes after the records"))),
    }
}

/// Appends `records`.
///
/// # Errors
/// [`RecordError::NotRecordable`] for a dent with a custom falloff.
fn write_records(out: &mut ByteWriter, records: &[DamageRecord]) -> Result<(), RecordError> {
    // A batch's refinement is an item of its own after it.
    let refinements = records.iter().filter(|r| matches!(r, DamageRecord::Dents(b) if b.refinement.is_some()));
    out.varint((records.len() + refinements.count()) as u64);
    for record in records {
        match record {
            DamageRecord::Dents(b) => {
                out.u8(1);
                out.varint(u64::from(b.dents));
                out.varint(b.impacts.len() as u64);
                for d in &b.impacts {
                    write_impact(out, d)?;
                }
                match &b.edit {
                    None => out.u8(0),
                    Some(edit) => {
                        out.u8(1);
                        write_edit(out, edit);
                    }
                }
                out.u64(b.after);
                if let Some(refinement) = &b.refinement {
                    // Tag 8 follows the batch it belongs to.
                    out.u8(REFINEMENT);
                    write_refinement(out, refinement);
                }
            }
            DamageRecord::Bend(b) => {
                out.u8(2);
                out.varint(b.frame);
                out.varint(u64::from(b.joint));
                out.f32(b.angle);
            }
            DamageRecord::Rest(r) => {
                out.u8(3);
                out.varint(u64::from(r.joint));
                out.quat(r.rest);
            }
            DamageRecord::Split(s) => {
                out.u8(4);
                out.varint(s.frame);
                out.varint(u64::from(s.joint));
                out.vec3(s.position);
                out.vec3(s.rest_position);
            }
            DamageRecord::Fracture(f) => {
                out.u8(if f.fracture.weld_output { WELDED_FRACTURE } else { 5 });
                out.varint(f.frame);
                write_break(out, &f.fracture);
                out.vec3(f.to_model);
                out.vec3(f.rest_shift);
                out.varint(f.pieces.len() as u64);
                for piece in &f.pieces {
                    out.text(&piece.name);
                    out.varint(u64::from(piece.index));
                    out.vec3(piece.shift);
                    out.u64(piece.hash);
                }
                out.u64(f.after);
            }
            DamageRecord::Skinned { edit, after } => {
                out.u8(6);
                write_edit(out, edit);
                out.u64(*after);
            }
        }
    }
    Ok(())
}

/// The tag of a fracture whose output is welded ([`crate::fracture::FractureRecord::weld_output`]).
const WELDED_FRACTURE: u8 = 7;
/// The tag of the refinement of the dent batch before it (not a record of its own).
const REFINEMENT: u8 = 8;

/// Appends a batch's refinement: base counts, new vertices (parents and fraction), new faces'
/// parents, split and held-back base faces.
fn write_refinement(out: &mut ByteWriter, r: &Refinement) {
    out.varint(r.base_vertex_count as u64);
    out.varint(r.base_face_count as u64);
    out.varint(r.vertices.len() as u64);
    for v in &r.vertices {
        out.u32(v.parents[0]);
        out.u32(v.parents[1]);
        out.f32(v.fraction);
    }
    for list in [&r.face_parents, &r.split_faces, &r.held_back] {
        out.varint(list.len() as u64);
        list.iter().for_each(|&f| out.u32(f));
    }
}

/// Reads [`write_refinement`]'s bytes, every count checked against the bytes left.
fn read_refinement(r: &mut ByteReader<'_>) -> Result<Refinement, RecordError> {
    let base_vertex_count = r.varint("refinement base vertex count")? as usize;
    let base_face_count = r.varint("refinement base face count")? as usize;
    let n = r.count("refinement vertices", 12, MAX_RECORDS)?;
    let mut vertices = Vec::with_capacity(n);
    for _ in 0..n {
        let parents = [r.u32("split parent")?, r.u32("split parent")?];
        vertices.push(SplitVertex { parents, fraction: r.f32("split fraction")? });
    }
    let mut list = |what| -> Result<Vec<u32>, RecordError> {
        let n = r.count(what, 4, MAX_RECORDS)?;
        (0..n).map(|_| r.u32(what)).collect()
    };
    let (face_parents, split_faces, held_back) =
        (list("refinement face parents")?, list("refinement split faces")?, list("refinement held-back faces")?);
    Ok(Refinement { base_vertex_count, base_face_count, vertices, face_parents, split_faces, held_back })
}

/// Reads [`write_records`]' bytes; every count is checked against the bytes left first.
fn read_records(r: &mut ByteReader<'_>) -> Result<Vec<DamageRecord>, RecordError> {
    let n = r.count("records", 2, MAX_RECORDS)?;
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        let record = match r.u8("record tag")? {
            1 => {
                let dents = r.varint32("batch dent count")?;
                // An impact dent takes at least 150 bytes.
                let k = r.count("impact dents", 150, MAX_RECORDS)?;
                let mut impacts = Vec::with_capacity(k);
                for _ in 0..k {
                    impacts.push(read_impact(r)?);
                }
                let edit = match r.u8("edit flag")? {
                    0 => None,
                    1 => Some(read_edit(r)?),
                    t => return Err(RecordError::Malformed(format!("edit flag {t}"))),
                };
                let after = r.u64("hash after the batch")?;
                DamageRecord::Dents(DentBatch { dents, impacts, edit, after, refinement: None })
            }
            REFINEMENT => {
                let refinement = read_refinement(r)?;
                match out.last_mut() {
                    Some(DamageRecord::Dents(batch)) if batch.refinement.is_none() => {
                        batch.refinement = Some(refinement);
                        continue;
                    }
                    _ => return Err(RecordError::Malformed("a refinement not after a dent batch".into())),
                }
            }
            2 => DamageRecord::Bend(JointBend {
                frame: r.varint("bend frame")?,
                joint: r.varint32("bend joint")?,
                angle: r.f32("bend angle")?,
            }),
            3 => DamageRecord::Rest(JointRest { joint: r.varint32("rest joint")?, rest: r.quat("rest rotation")? }),
            4 => DamageRecord::Split(BoneSplit {
                frame: r.varint("split frame")?,
                joint: r.varint32("split joint")?,
                position: r.vec3("split position")?,
                rest_position: r.vec3("split rest position")?,
            }),
            5 => DamageRecord::Fracture(read_fracture(r)?),
            WELDED_FRACTURE => {
                let mut f = read_fracture(r)?;
                f.fracture.weld_output = true;
                DamageRecord::Fracture(f)
            }
            6 => DamageRecord::Skinned { edit: read_edit(r)?, after: r.u64("hash after skinning")? },
            t => return Err(RecordError::Malformed(format!("unknown record tag {t}"))),
        };
        out.push(record);
    }
    Ok(out)
}

fn read_fracture(r: &mut ByteReader<'_>) -> Result<FractureRecord, RecordError> {
    let frame = r.varint("fracture frame")?;
    let fracture = read_break(r)?;
    let (to_model, rest_shift) = (r.vec3("to model")?, r.vec3("rest shift")?);
    // A piece takes at least 22 bytes (an empty name, an index, a shift, a hash).
    let k = r.count("fracture pieces", 22, MAX_RECORDS)?;
    let mut pieces = Vec::with_capacity(k);
    for _ in 0..k {
        let name = r.text("piece name", MAX_NAME_BYTES)?;
        let (index, shift) = (r.varint32("piece index")?, r.vec3("piece shift")?);
        pieces.push(FracturePiece { name, index, shift, hash: r.u64("piece hash")? });
    }
    Ok(FractureRecord { frame, fracture, to_model, rest_shift, pieces, after: r.u64("hash after the fracture")? })
}

fn write_impact(out: &mut ByteWriter, d: &ImpactDent) -> Result<(), RecordError> {
    out.vec3(d.impact.point);
    out.vec3(d.impact.normal);
    out.vec3(d.impact.relative_velocity);
    out.affine(d.target_to_world);
    out.u64(d.projectile.hash);
    out.short_str(d.projectile.builtin.as_deref().unwrap_or(""));
    out.affine(d.projectile.to_world);
    out.f32(d.reach);
    out.u8(u8::from(d.progressive));
    write_params(out, &d.params)
}

fn read_impact(r: &mut ByteReader<'_>) -> Result<ImpactDent, RecordError> {
    let impact = Impact {
        point: r.vec3("impact point")?,
        normal: r.vec3("impact normal")?,
        relative_velocity: r.vec3("impact velocity")?,
    };
    let target_to_world = r.affine("target pose")?;
    let hash = r.u64("projectile hash")?;
    let builtin = Some(r.short_str("projectile name")?).filter(|s| !s.is_empty());
    let to_world = r.affine("projectile pose")?;
    let reach = r.f32("reach")?;
    let progressive = match r.u8("progressive flag")? {
        0 => false,
        1 => true,
        t => return Err(RecordError::Malformed(format!("progressive flag {t}"))),
    };
    let params = read_params(r)?;
    Ok(ImpactDent {
        impact,
        target_to_world,
        projectile: ProjectileRef { hash, builtin, to_world },
        reach,
        params,
        progressive,
    })
}
