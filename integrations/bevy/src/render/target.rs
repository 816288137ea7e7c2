//! One dentable mesh resident on Bevy's device: its entity and asset, the host's copy of what
//! the GPU holds, and where its dents go in Bevy's vertex slab.

use bevy::prelude::*;
use bevy::render::render_resource::BufferId;
use dentbend::TriMesh;

use crate::mesh_data::SlabLayout;

/// One resident target, in slot order.
pub(super) struct Target {
    pub(super) entity: Entity,
    pub(super) asset: AssetId<Mesh>,
    /// The target as the GPU holds it (updated from the read-backs), to upload it again when
    /// the set of targets changes.
    pub(super) mirror: TriMesh,
    pub(super) layout: SlabLayout,
    /// Its dents must be written into Bevy's vertex buffer (dented, or Bevy uploaded the asset
    /// again).
    pub(super) copy_needed: bool,
    /// Where they were last written (slab buffer, first vertex).
    pub(super) copied_at: Option<(BufferId, u32)>,
}
