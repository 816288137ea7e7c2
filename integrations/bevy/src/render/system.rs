//! The render-world system that makes each frame's GPU dents.

use bevy::prelude::*;
use bevy::render::mesh::RenderMesh;
use bevy::render::mesh::allocator::MeshAllocator;
use bevy::render::render_asset::ExtractedAssets;

use super::ResidentDents;
use crate::link::RenderLink;

/// `Render`, after Bevy has uploaded this frame's meshes: takes the main world's messages,
/// finishes read-backs, uploads the targets again if they changed, then records the dents and
/// the writes into Bevy's vertex slabs (submitted before Bevy's own frame, so this frame draws
/// the dents).
pub(crate) fn make_dents(
    mut resident: ResMut<ResidentDents>,
    link: Res<RenderLink>,
    allocator: Res<MeshAllocator>,
    extracted: Res<ExtractedAssets<RenderMesh>>,
) {
    let messages = link.receive();
    if !resident.is_running() {
        return;
    }
    resident.take(messages);
    // Bevy uploads these assets this frame (before this system): their dents must be written again.
    resident.uploaded_again(extracted.added.iter().chain(&extracted.modified).copied());
    resident.poll_reads(&link);
    resident.rebuild_if_stale(&link);
    resident.record(&allocator, &link);
}
