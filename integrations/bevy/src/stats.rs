//! What the plug-in has done, for games, tests and benchmarks.

use bevy::prelude::*;

/// Running totals since the app started.
#[derive(Resource, Debug, Clone, Default, PartialEq, Eq)]
pub struct DentStats {
    /// Dents made (both paths).
    pub dents: u64,
    /// Dents made on the GPU path.
    pub gpu_dents: u64,
    /// Bytes read back from the GPU to draw dented or bent meshes. The plug-in never does: the
    /// GPU path writes into Bevy's vertex slab in place and the CPU path computes on the CPU, so
    /// this stays 0 (reported in `summary.json` for comparison with engines that round-trip).
    pub render_readback_bytes: u64,
    /// Bytes read back for the physics colliders (4 per dented target and batch, 16 per moved
    /// vertex), asynchronously.
    pub collider_readback_bytes: u64,
    /// Dent batches recorded on the GPU.
    pub gpu_batches: u64,
    /// Contacts that could not dent (unknown or despawned bodies, bad values), logged.
    pub rejected_contacts: u64,
    /// Dents made on the CPU path.
    pub cpu_dents: u64,
    /// Triangles refinement added under CPU-path dents.
    pub refined_triangles: u64,
    /// CPU-path dents the intersection guard scaled back.
    pub limited_dents: u64,
    /// CPU-path dents that moved no vertex (the mesh too coarse under them, or the guard
    /// limited them to nothing); each body's first is logged with its fix.
    pub empty_dents: u64,
    /// Bones split where a fast hit landed (dynamic articulation of bendable bodies).
    pub splits: u64,
    /// Dents made on bendable bodies (counted in `dents` and `cpu_dents` too).
    pub bendable_dents: u64,
    /// Breakable bodies that broke.
    pub fractures: u64,
    /// Pieces their fractures made (each an entity with a [`DentPiece`](crate::DentPiece)).
    pub pieces: u64,
}

/// Which path a dentable body's dents take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DentPath {
    /// Dented on Bevy's GPU device, written into Bevy's vertex buffer.
    Gpu,
    /// Dented on the CPU, written into the mesh asset (Bevy uploads it again).
    Cpu,
}
