//! The damage file on disk: a small JSON object (format, version, scene, one entry per body with
//! its mesh stamps) whose bulk, each body's records, is one base64 string of little-endian
//! binary (see [`encode_records`]). Hashes are 16 hex digits.

use serde::{Deserialize, Serialize};

use super::bytes::{ByteReader, ByteWriter, base64_decode, base64_encode};
use super::records::{decode_records, encode_records};
use super::{BodyDamage, DamageFile, DamageRecord, MeshStamp, RecordError, SceneRef, hex64};

/// The `format` field of every damage file.
const FORMAT: &str = "dentbend-damage";
/// The format version this build writes: dent batches may carry their refinement (record tag
/// 8). It reads this one, version 2 (no refinements recorded) and version 1, whose fractures
/// came out welded from meshes with seams (their records replay that way).
const VERSION: u32 = 3;

/// The version before refinements were recorded.
const NO_REFINEMENTS: u32 = 2;

/// The version whose fractures welded their output.
const WELDED_FRACTURES: u32 = 1;

#[derive(Serialize, Deserialize)]
struct Header {
    format: String,
    version: u32,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct WireFile {
    format: String,
    version: u32,
    /// Dents in all, for people reading the file.
    dents: u64,
    scene: Option<WireScene>,
    bodies: Vec<WireBody>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct WireScene {
    spec: String,
    size: String,
    file_hash: Option<String>,
    frame: u64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct WireStamp {
    vertices: u32,
    faces: u32,
    hash: String,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct WireBody {
    name: String,
    dents: u64,
    base: WireStamp,
    #[serde(rename = "final")]
    final_mesh: WireStamp,
    /// Mesh → world at the end, 12 f32 (columns, then translation), base64.
    pose: Option<String>,
    /// The records, base64.
    records: String,
}

fn stamp_out(s: &MeshStamp) -> WireStamp {
    WireStamp { vertices: s.vertices, faces: s.faces, hash: hex64(s.hash) }
}

fn parse_hex(text: &str, what: &str) -> Result<u64, RecordError> {
    if text.len() != 16 {
        return Err(RecordError::Malformed(format!("{what} {text:?} is not 16 hex digits")));
    }
    u64::from_str_radix(text, 16).map_err(|_| RecordError::Malformed(format!("{what} {text:?} is not hex")))
}

fn stamp_in(s: &WireStamp, what: &str) -> Result<MeshStamp, RecordError> {
    Ok(MeshStamp { vertices: s.vertices, faces: s.faces, hash: parse_hex(&s.hash, what)? })
}

impl DamageFile {
    /// The file's bytes: compact JSON.
    ///
    /// # Errors
    /// [`RecordError::NotRecordable`] for a dent with a custom falloff.
    pub fn to_json(&self) -> Result<Vec<u8>, RecordError> {
        let mut bodies = Vec::with_capacity(self.bodies.len());
        for b in &self.bodies {
            let records = encode_records(&b.records)?;
            let pose = b.pose.map(|p| {
                let mut w = ByteWriter::default();
                w.affine(p);
                base64_encode(&w.bytes)
            });
            bodies.push(WireBody {
                name: b.name.clone(),
                dents: b.dents(),
                base: stamp_out(&b.base),
                final_mesh: stamp_out(&b.final_mesh),
                pose,
                records: base64_encode(&records),
            });
        }
        let scene = self.scene.as_ref().map(|s| WireScene {
            spec: s.spec.clone(),
            size: s.size.clone(),
            file_hash: s.file_hash.map(hex64),
            frame: s.frame,
        });
        let wire = WireFile { format: FORMAT.into(), version: VERSION, dents: self.dents(), scene, bodies };
        serde_json::to_vec(&wire).map_err(|e| RecordError::Malformed(e.to_string()))
    }

    /// Reads a damage file's bytes: format and version first, then every body's records, every
    /// count checked against the bytes that back it before anything is allocated.
    ///
    /// # Errors
    /// [`RecordError::TooLarge`] past [`MAX_FILE_BYTES`](Self::MAX_FILE_BYTES) or [`MAX_BODIES`](Self::MAX_BODIES),
    /// [`RecordError::Truncated`], [`RecordError::Version`], [`RecordError::Malformed`].
    pub fn from_json(bytes: &[u8]) -> Result<Self, RecordError> {
        if bytes.len() as u64 > DamageFile::MAX_FILE_BYTES {
            return Err(RecordError::TooLarge {
                what: "bytes",
                count: bytes.len() as u64,
                limit: DamageFile::MAX_FILE_BYTES,
            });
        }
        let json_error = |e: serde_json::Error| {
            if e.is_eof() {
                RecordError::Truncated { what: "the damage file's JSON", needed: 1, available: 0 }
            } else {
                RecordError::Malformed(e.to_string())
            }
        };
        let header: Header = serde_json::from_slice(bytes).map_err(json_error)?;
        if header.format != FORMAT {
            return Err(RecordError::Malformed(format!("format {:?} is not {FORMAT:?}", header.format)));
        }
        if ![VERSION, NO_REFINEMENTS, WELDED_FRACTURES].contains(&header.version) {
            return Err(RecordError::Version { found: header.version, supported: VERSION });
        }
        let wire: WireFile = serde_json::from_slice(bytes).map_err(json_error)?;
        if wire.bodies.len() > DamageFile::MAX_BODIES {
            return Err(RecordError::TooLarge {
                what: "bodies",
                count: wire.bodies.len() as u64,
                limit: DamageFile::MAX_BODIES as u64,
            });
        }
        let mut bodies = Vec::with_capacity(wire.bodies.len());
        for b in &wire.bodies {
            let mut records = decode_records(&base64_decode(&b.records, "records")?)?;
            if header.version == WELDED_FRACTURES {
                for record in &mut records {
                    if let DamageRecord::Fracture(f) = record {
                        f.fracture.weld_output = true;
                    }
                }
            }
            let pose = match &b.pose {
                None => None,
                Some(text) => {
                    let data = base64_decode(text, "pose")?;
                    let mut r = ByteReader::new(&data);
                    let pose = r.affine("pose")?;
                    if r.remaining() != 0 || !pose.is_finite() {
                        return Err(RecordError::Malformed(format!("body \"{}\": pose is not 12 finite f32", b.name)));
                    }
                    Some(pose)
                }
            };
            let body = BodyDamage {
                name: b.name.clone(),
                base: stamp_in(&b.base, "base hash")?,
                final_mesh: stamp_in(&b.final_mesh, "final hash")?,
                pose,
                records,
            };
            if body.dents() != b.dents {
                return Err(RecordError::Malformed(format!(
                    "body \"{}\" says {} dents, its records hold {}",
                    b.name,
                    b.dents,
                    body.dents()
                )));
            }
            bodies.push(body);
        }
        let scene = match wire.scene {
            None => None,
            Some(s) => Some(SceneRef {
                file_hash: s.file_hash.as_deref().map(|h| parse_hex(h, "scene file hash")).transpose()?,
                spec: s.spec,
                size: s.size,
                frame: s.frame,
            }),
        };
        Ok(Self { scene, bodies })
    }
}
