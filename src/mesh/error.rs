//! Errors raised while building, loading, saving or validating meshes.

use std::path::PathBuf;

/// Everything that can go wrong with a [`TriMesh`](super::TriMesh).
///
/// A failed operation never leaves a partially modified mesh behind.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The mesh has no vertices or no faces.
    #[error("mesh is empty: it has {vertices} vertices and {faces} faces (at least one face is needed)")]
    Empty {
        /// Number of vertices found.
        vertices: usize,
        /// Number of faces found.
        faces: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {index} has a non-finite coordinate {position:?}")]
    NonFinite {
        /// Index of the offending vertex.
        index: usize,
        /// Its coordinates as read.
        position: [f32; 3],
    },
    /// A vertex coordinate lies beyond [`MAX_COORDINATE`](super::MAX_COORDINATE).
    #[error(
        "vertex {index} at {position:?} lies beyond ±{limit:e}, the supported coordinate range (areas and volumes of \
         larger coordinates overflow f32)"
    )]
    OutOfRange {
        /// Index of the offending vertex.
        index: usize,
        /// Its coordinates.
        position: [f32; 3],
        /// The limit, mesh units.
        limit: f32,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {index}, but the mesh has only {vertex_count} vertices")]
    IndexOutOfRange {
        /// Index of the offending face.
        face: usize,
        /// The out-of-range vertex index.
        index: u32,
        /// Number of vertices in the mesh.
        vertex_count: usize,
    },
    /// A replacement position array has the wrong length.
    #[error("expected {expected} vertex positions, got {actual}")]
    LengthMismatch {
        /// Number of vertices in the mesh.
        expected: usize,
        /// Number of positions supplied.
        actual: usize,
    },
    /// A per-vertex or per-face attribute array of an [`Asset`](super::Asset) has the wrong
    /// length.
    #[error("attribute {attribute} has {actual} entries, expected {expected}")]
    AttributeLength {
        /// Which attribute (`"uv set 0"`, `"normals"`, `"face groups"`, ...).
        attribute: String,
        /// Entries needed (the vertex or face count).
        expected: usize,
        /// Entries supplied.
        actual: usize,
    },
    /// An attribute value of an [`Asset`](super::Asset) is NaN or infinite, or out of its range.
    #[error("attribute {attribute} entry {index} is invalid: {reason}")]
    AttributeValue {
        /// Which attribute.
        attribute: String,
        /// Index of the offending entry.
        index: usize,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A dented mesh, its refinement and its moved list do not describe the same dent of an
    /// [`Asset`](super::Asset)'s mesh.
    #[error("the dent does not follow this asset: {what} is {actual}, expected {expected}")]
    DentMismatch {
        /// What disagrees.
        what: &'static str,
        /// What the asset implies.
        expected: usize,
        /// What was given.
        actual: usize,
    },
    /// A generator parameter is out of range (negative size, zero segments, ...).
    #[error("invalid mesh parameter: {0}")]
    InvalidParameter(String),
    /// A file could not be read or written.
    #[error("cannot access {path}: {source}")]
    Io {
        /// The file involved.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A file was read but its contents are malformed.
    #[error("malformed {format} file {path}: {message}")]
    Parse {
        /// The file involved.
        path: PathBuf,
        /// `"OBJ"`, `"PLY"` or `"glTF"`.
        format: &'static str,
        /// What is wrong, with a line number, byte offset or glTF object index where known.
        message: String,
    },
    /// The file extension names a format this crate does not read or write.
    #[error("unsupported mesh format for {path} (expected .obj, .ply, .gltf or .glb, or a built-in name: {builtins})")]
    UnsupportedFormat {
        /// The file involved.
        path: PathBuf,
        /// The built-in mesh names, comma separated.
        builtins: String,
    },
    /// The file extension names no format this crate writes.
    #[error("cannot save {path}: unsupported extension (expected .obj or .glb)")]
    UnsupportedSaveFormat {
        /// The file that was to be written.
        path: PathBuf,
    },
}
