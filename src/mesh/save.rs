//! Saving a mesh in the format its file extension names.

use std::path::Path;

use super::{MeshError, TriMesh, save_obj};

/// Writes `mesh` in the format named by the extension of `path` (case-insensitive): `.obj` or,
/// with the `io` feature, `.glb` (one node, default colour; `save_glb_scene` writes several).
/// The file is replaced atomically: a failed save leaves what was there.
///
/// # Errors
/// [`MeshError::UnsupportedSaveFormat`] for any other extension (nothing is written); otherwise
/// as the format's writer.
///
/// # Example
/// ```no_run
/// let bunny = dentbend::mesh::builtin("bunny").unwrap();
/// dentbend::mesh::save("bunny.glb", &bunny).unwrap();
/// ```
pub fn save(path: impl AsRef<Path>, mesh: &TriMesh) -> Result<(), MeshError> {
    let path = path.as_ref();
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("obj") => save_obj(mesh, path),
        #[cfg(feature = "io")]
        Some("glb") => super::save_glb(path, mesh),
        _ => Err(MeshError::UnsupportedSaveFormat { path: path.to_path_buf() }),
    }
}
