//! PLY input: `ascii 1.0`, `binary_little_endian 1.0` and `binary_big_endian 1.0`.
//!
//! The `vertex` element must carry scalar `x`, `y`, `z` properties (any numeric type, any order,
//! among others); the `face` element a `vertex_indices` (or `vertex_index`) list with an integer
//! item type. Polygons are fan-triangulated; other elements and properties, lists included, are
//! read past. Every declared count is checked against the data actually present before anything
//! is allocated, so a lying header costs no more memory than the file itself.

use std::path::Path;

use glam::Vec3;

use super::obj::MEMORY;
use super::ply_header::{Format, Header, Kind, Role};
use super::ply_source::{AsciiSource, BinarySource, Source};
use super::{MeshError, TriMesh};

/// Reads a PLY file (see [`parse_ply`] for what is accepted).
///
/// # Errors
/// [`MeshError::Io`] if the file cannot be read, otherwise as [`parse_ply`].
pub fn load_ply(path: impl AsRef<Path>) -> Result<TriMesh, MeshError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io { path: path.to_path_buf(), source })?;
    parse_ply_named(&bytes, path)
}

/// Parses the bytes of a PLY file (ASCII or binary of either endianness; positions in world
/// units).
///
/// # Errors
/// [`MeshError::Parse`] for a bad header (no `ply` magic, unknown format, type or keyword, no
/// `x`/`y`/`z`), truncated data or declared counts that the data does not match, a malformed
/// value, a negative index or a polygon with fewer than three corners; [`MeshError::Empty`],
/// [`MeshError::NonFinite`] or [`MeshError::IndexOutOfRange`] from [`TriMesh::new`].
pub fn parse_ply(bytes: &[u8]) -> Result<TriMesh, MeshError> {
    parse_ply_named(bytes, Path::new(MEMORY))
}

/// [`parse_ply`] with the path to name in errors.
pub(crate) fn parse_ply_named(bytes: &[u8], path: &Path) -> Result<TriMesh, MeshError> {
    let fail = |message: String| MeshError::Parse { path: path.to_path_buf(), format: "PLY", message };
    let header = Header::parse(bytes).map_err(fail)?;
    let body = &bytes[header.data_offset..];
    let (positions, faces) = match header.format {
        Format::Ascii => read_body(&header, AsciiSource::new(body, header.lines)),
        Format::Binary { big_endian } => read_body(&header, BinarySource::new(body, header.data_offset, big_endian)),
    }
    .map_err(fail)?;
    TriMesh::new(positions, faces)
}

/// Reads every element entry, keeping vertex positions and fan-triangulated faces.
fn read_body(header: &Header, mut src: impl Source) -> Result<(Vec<Vec3>, Vec<[u32; 3]>), String> {
    src.check_counts(header)?;
    let (mut positions, mut faces, mut polygon) = (Vec::new(), Vec::new(), Vec::new());
    for element in &header.elements {
        // The counts were checked against the data size, so these reservations are bounded by it.
        match element.role {
            Role::Vertex(_) => positions.reserve(element.count as usize),
            Role::Face(_) => faces.reserve(element.count as usize),
            Role::Skip => {}
        }
        for entry in 0..element.count {
            let context = |e: String| format!("element '{}' entry {entry}: {e}", element.name);
            src.begin().map_err(context)?;
            let mut xyz = [0.0f32; 3];
            polygon.clear();
            for (k, property) in element.properties.iter().enumerate() {
                match property.kind {
                    Kind::Scalar(ty) => {
                        let value = src.value(ty).map_err(context)?;
                        if let Role::Vertex(axes) = element.role {
                            for (axis, coordinate) in axes.iter().zip(&mut xyz) {
                                if *axis == k {
                                    // Doubles beyond f32 become infinite; validation rejects them.
                                    *coordinate = value as f32;
                                }
                            }
                        }
                    }
                    Kind::List { count, item } => {
                        let len = src.list_len(count, item).map_err(context)?;
                        let indices = matches!(element.role, Role::Face(list) if list == k);
                        for _ in 0..len {
                            let value = src.value(item).map_err(context)?;
                            if indices {
                                let index = u32::try_from(value as i64)
                                    .map_err(|_| context(format!("invalid vertex index {value}")))?;
                                polygon.push(index);
                            }
                        }
                        if indices && polygon.len() < 3 {
                            return Err(context(format!("a face needs at least 3 vertices, this one has {len}")));
                        }
                    }
                }
            }
            src.end().map_err(context)?;
            match element.role {
                Role::Vertex(_) => positions.push(Vec3::from_array(xyz)),
                Role::Face(_) => faces.extend((1..polygon.len() - 1).map(|i| [polygon[0], polygon[i], polygon[i + 1]])),
                Role::Skip => {}
            }
        }
    }
    src.finish()?;
    Ok((positions, faces))
}
