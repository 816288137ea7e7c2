//! Wavefront OBJ input and output: positions and faces only (texture coordinates, normals,
//! groups and materials are read past), polygons fan-triangulated, all objects merged.

use std::io::Write;
use std::path::Path;

use glam::Vec3;

use super::atomic_write::write_atomically;
use super::{MeshError, TriMesh};

/// Path reported in errors from the in-memory parsers.
pub(crate) const MEMORY: &str = "<memory>";

/// Reads an OBJ file (see [`parse_obj`] for what is accepted).
///
/// # Errors
/// [`MeshError::Io`] if the file cannot be read, otherwise as [`parse_obj`].
pub fn load_obj(path: impl AsRef<Path>) -> Result<TriMesh, MeshError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io { path: path.to_path_buf(), source })?;
    parse_obj_named(&String::from_utf8_lossy(&bytes), path)
}

/// Parses OBJ text: `v x y z [more]` vertices (world units) and `f` faces whose corners are
/// `v`, `v/vt`, `v//vn` or `v/vt/vn` with 1-based or negative (relative) vertex indices.
/// Polygons are fan-triangulated; every other statement and `#` comments are ignored.
///
/// # Errors
/// [`MeshError::Parse`] (with the line number) for a malformed `v` or `f` statement, index 0, a
/// relative index before the first vertex or a face with fewer than three corners;
/// [`MeshError::Empty`], [`MeshError::NonFinite`] (NaN or infinite coordinates) or
/// [`MeshError::IndexOutOfRange`] (a face index past the last vertex) from [`TriMesh::new`].
///
/// # Example
/// ```
/// let quad = dentbend::mesh::parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
/// assert_eq!(quad.face_count(), 2);
/// ```
pub fn parse_obj(text: &str) -> Result<TriMesh, MeshError> {
    parse_obj_named(text, Path::new(MEMORY))
}

/// [`parse_obj`] with the path to name in errors.
pub(crate) fn parse_obj_named(text: &str, path: &Path) -> Result<TriMesh, MeshError> {
    let fail = |line: usize, message: String| MeshError::Parse {
        path: path.to_path_buf(),
        format: "OBJ",
        message: format!("line {line}: {message}"),
    };
    let mut positions: Vec<Vec3> = Vec::new();
    let mut faces: Vec<[u32; 3]> = Vec::new();
    let mut polygon: Vec<u32> = Vec::new();
    for (number, raw) in text.lines().enumerate() {
        let line = number + 1;
        let content = raw.split('#').next().unwrap_or_default();
        let mut tokens = content.split_ascii_whitespace();
        match tokens.next() {
            Some("v") => {
                let mut xyz = [0.0f32; 3];
                for (axis, value) in xyz.iter_mut().enumerate() {
                    let token = tokens
                        .next()
                        .ok_or_else(|| fail(line, format!("vertex has {axis} coordinates, expected at least 3")))?;
                    *value = token
                        .parse()
                        .map_err(|_| fail(line, format!("vertex coordinate '{token}' is not a number")))?;
                }
                positions.push(Vec3::from_array(xyz));
            }
            Some("f" | "fo") => {
                polygon.clear();
                for corner in tokens {
                    polygon.push(corner_index(corner, positions.len()).map_err(|m| fail(line, m))?);
                }
                if polygon.len() < 3 {
                    return Err(fail(line, format!("face has {} corners, at least 3 are needed", polygon.len())));
                }
                faces.extend((1..polygon.len() - 1).map(|i| [polygon[0], polygon[i], polygon[i + 1]]));
            }
            _ => {}
        }
    }
    TriMesh::new(positions, faces)
}

/// Zero-based vertex index of one face corner `v[/vt][/vn]`, given the vertices read so far.
fn corner_index(corner: &str, vertices_so_far: usize) -> Result<u32, String> {
    let token = corner.split('/').next().unwrap_or_default();
    let index: i64 = token.parse().map_err(|_| format!("face corner '{corner}' is not a vertex index"))?;
    let zero_based = match index {
        0 => return Err("vertex index 0 is invalid (OBJ indices start at 1)".to_owned()),
        i if i > 0 => i - 1,
        i => {
            let resolved = vertices_so_far as i64 + i;
            if resolved < 0 {
                return Err(format!(
                    "relative vertex index {i} points before the first vertex ({vertices_so_far} read so far)"
                ));
            }
            resolved
        }
    };
    u32::try_from(zero_based).map_err(|_| format!("vertex index {index} is too large"))
}

/// Writes `mesh` as OBJ: a `v` line per position (shortest text that reads back to the same
/// f32), a `vn` line per normal, and an `f a//a b//b c//c` line per triangle (1-based). The
/// file is written to a temporary sibling and renamed into place, so a failed save leaves no
/// partial file.
///
/// # Errors
/// [`MeshError::Io`] naming `path` if the file cannot be created or written.
pub fn save_obj(mesh: &TriMesh, path: impl AsRef<Path>) -> Result<(), MeshError> {
    write_atomically(path.as_ref(), |out| write_obj(mesh, out))
}

fn write_obj(mesh: &TriMesh, out: &mut impl Write) -> std::io::Result<()> {
    writeln!(out, "# dentbend mesh: {} vertices, {} triangles", mesh.vertex_count(), mesh.face_count())?;
    for p in mesh.positions() {
        writeln!(out, "v {} {} {}", p.x, p.y, p.z)?;
    }
    for n in mesh.normals() {
        writeln!(out, "vn {} {} {}", n.x, n.y, n.z)?;
    }
    for f in mesh.faces() {
        let [a, b, c] = f.map(|v| u64::from(v) + 1);
        writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}")?;
    }
    Ok(())
}
