//! A damage file in memory: which scene and base meshes it belongs to, and each body's records.

use glam::Affine3A;

use super::records::{DamageRecord, DentBatch};
use crate::mesh::{TriMesh, content_hash};

/// A mesh named by its counts and [`content_hash`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshStamp {
    /// Vertex count.
    pub vertices: u32,
    /// Face count.
    pub faces: u32,
    /// [`content_hash`] of positions and faces.
    pub hash: u64,
}

impl MeshStamp {
    /// The stamp of `mesh`.
    pub fn of(mesh: &TriMesh) -> Self {
        Self { vertices: mesh.vertex_count() as u32, faces: mesh.face_count() as u32, hash: content_hash(mesh) }
    }
}

/// Which scene a simulation's damage belongs to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SceneRef {
    /// A built-in scene's name or the scene file's path as given to `dentbend run`.
    pub spec: String,
    /// The built-in scene's size (`full` or `demo`).
    pub size: String,
    /// The hash of the scene file's bytes ([`SceneRef::file_hash_of`]); `None` for a built-in
    /// scene.
    pub file_hash: Option<u64>,
    /// The frame whose meshes the bodies' final stamps are (the run's last).
    pub frame: u64,
}

impl SceneRef {
    /// The hash a damage file keeps of a scene file's `bytes` (FNV-1a 64), so that a replay can
    /// tell the file changed since the run.
    pub fn file_hash_of(bytes: &[u8]) -> u64 {
        crate::mesh::fnv1a64(crate::mesh::fnv1a64_start(), bytes)
    }
}

/// One body's damage: the mesh it starts from, its records in order, the mesh they end at.
#[derive(Debug, Clone)]
pub struct BodyDamage {
    /// The body's name (the caller's, or the scene's).
    pub name: String,
    /// The mesh the records apply to (the body's own coordinates).
    pub base: MeshStamp,
    /// The mesh after every record.
    pub final_mesh: MeshStamp,
    /// The body's mesh → world transform at the end, when the file places bodies in a world
    /// (a replay that writes world meshes applies it to the final mesh).
    pub pose: Option<Affine3A>,
    /// Its records, oldest first.
    pub records: Vec<DamageRecord>,
}

impl BodyDamage {
    /// An undamaged body on `base`.
    pub fn new(name: impl Into<String>, base: &TriMesh) -> Self {
        let stamp = MeshStamp::of(base);
        Self { name: name.into(), base: stamp, final_mesh: stamp, pose: None, records: Vec::new() }
    }

    /// How many dents its records hold.
    pub fn dents(&self) -> u64 {
        self.records
            .iter()
            .map(|r| match r {
                DamageRecord::Dents(DentBatch { dents, .. }) => u64::from(*dents),
                _ => 0,
            })
            .sum()
    }
}

/// A whole damage file.
#[derive(Debug, Clone, Default)]
pub struct DamageFile {
    /// The scene, for a simulation's damage; `None` for bodies of the caller's own.
    pub scene: Option<SceneRef>,
    /// Every body, in the order the recorder listed them.
    pub bodies: Vec<BodyDamage>,
}

impl DamageFile {
    /// Largest damage file read, bytes (256 MiB), checked before reading it.
    pub const MAX_FILE_BYTES: u64 = 256 << 20;
    /// Most bodies a damage file may list.
    pub const MAX_BODIES: usize = 1 << 20;

    /// The body named `name`.
    pub fn body(&self, name: &str) -> Option<&BodyDamage> {
        self.bodies.iter().find(|b| b.name == name)
    }

    /// Dents over all bodies.
    pub fn dents(&self) -> u64 {
        self.bodies.iter().map(BodyDamage::dents).sum()
    }
}
