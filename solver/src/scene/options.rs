//! How a scene is loaded: its size (built-in scenes), where a scene file may read meshes from,
//! and how many bodies and bytes a file may hold before it is refused as too large.

use super::SceneSize;

/// Where the mesh paths of a scene file may lead.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MeshPaths {
    /// Only files in the scene file's folder or below: no absolute paths, no `..`, no symbolic
    /// link out (files from others: downloads, mods, a build farm's inputs).
    #[default]
    Confined,
    /// Any path, relative to the scene file's folder or absolute (files you wrote yourself).
    Trusted,
}

/// Bodies a scene file may declare by default.
pub(crate) const DEFAULT_MAX_BODIES: usize = 10_000;
/// Largest scene file read by default, bytes (16 MiB: about 100,000 bodies of TOML).
pub(crate) const DEFAULT_MAX_FILE_BYTES: u64 = 16 << 20;

/// Options of [`load_with`](super::load_with) and `parse_scene_with`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LoadOptions {
    /// Size of a built-in scene (scene files have one size).
    pub size: SceneSize,
    /// Where a scene file's mesh paths may lead.
    pub mesh_paths: MeshPaths,
    /// Most bodies a scene file may declare.
    pub max_bodies: usize,
    /// Largest scene file read, bytes.
    pub max_file_bytes: u64,
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self {
            size: SceneSize::Full,
            mesh_paths: MeshPaths::Confined,
            max_bodies: DEFAULT_MAX_BODIES,
            max_file_bytes: DEFAULT_MAX_FILE_BYTES,
        }
    }
}

impl LoadOptions {
    /// The defaults at `size`.
    pub fn sized(size: SceneSize) -> Self {
        Self { size, ..Self::default() }
    }

    /// No limit on bodies or file size (for inputs you know to be large).
    pub fn unlimited(self) -> Self {
        Self { max_bodies: usize::MAX, max_file_bytes: u64::MAX, ..self }
    }
}
