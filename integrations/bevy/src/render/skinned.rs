//! Bendable meshes skinned on Bevy's device each frame their bones moved: dentbend's `skin`
//! kernel into resident buffers, then the `interleave` kernel into the mesh's slot of Bevy's
//! vertex slab (no read-back).

use std::collections::HashMap;

use bevy::prelude::*;
use bevy::render::mesh::allocator::MeshAllocator;
use dentbend::cpu::SkinBone;
use dentbend::gpu::GpuContext;
use dentbend::gpu::interleave::{Interleave, plan};
use dentbend::gpu::skin::{Skin, SkinMesh};

use crate::mesh_data::SlabLayout;

/// One skinned mesh.
struct Skinned {
    asset: AssetId<Mesh>,
    layout: SlabLayout,
    mesh: SkinMesh,
    /// The bones to skin with at the next frame, if they changed.
    pending: Option<Vec<SkinBone>>,
    /// The last bones skinned with (again when Bevy uploads the asset again).
    last: Option<Vec<SkinBone>>,
}

/// The kernels and the skinned meshes.
#[derive(Default)]
pub(crate) struct SkinnedMeshes {
    kernels: Option<(Skin, Interleave)>,
    meshes: HashMap<Entity, Skinned>,
}

impl SkinnedMeshes {
    /// Uploads `entity`'s rest mesh (compiling the kernels the first time).
    #[allow(clippy::too_many_arguments)]
    pub fn register(
        &mut self,
        context: &GpuContext,
        entity: Entity,
        asset: AssetId<Mesh>,
        positions: &[Vec3],
        normals: &[Vec3],
        influences: &[dentbend::cpu::SkinInfluence],
        bones: u32,
        layout: SlabLayout,
    ) {
        if self.kernels.is_none() {
            match (Skin::new(context), Interleave::new(context)) {
                (Ok(skin), Ok(interleave)) => self.kernels = Some((skin, interleave)),
                (Err(e), _) | (_, Err(e)) => {
                    error!("bevy_dentbend: the skinning kernels do not compile here ({e}); {entity} stays at rest");
                    return;
                }
            }
        }
        let Some((skin, _)) = &self.kernels else { return };
        match skin.upload(context, positions, normals, influences, bones) {
            Ok(mesh) => {
                self.meshes.insert(entity, Skinned { asset, layout, mesh, pending: None, last: None });
            }
            Err(e) => error!("bevy_dentbend: {entity}'s mesh cannot be skinned on the GPU ({e}); it stays at rest"),
        }
    }

    /// Forgets `entity`.
    pub fn forget(&mut self, entity: Entity) {
        self.meshes.remove(&entity);
    }

    /// Sets `entity`'s bones for the next frame.
    pub fn pose(&mut self, entity: Entity, bones: Vec<SkinBone>) {
        if let Some(s) = self.meshes.get_mut(&entity) {
            s.pending = Some(bones);
        }
    }

    /// Skins again the meshes whose asset Bevy uploaded again.
    pub fn uploaded_again(&mut self, asset: AssetId<Mesh>) {
        for s in self.meshes.values_mut().filter(|s| s.asset == asset) {
            s.pending = s.pending.take().or_else(|| s.last.clone());
        }
    }

    /// Records every pending skinning and its write into Bevy's slab into `encoder`; how many.
    pub fn record(
        &mut self,
        context: &GpuContext,
        encoder: &mut dentbend::wgpu::CommandEncoder,
        allocator: &MeshAllocator,
    ) -> u64 {
        let Some((skin, interleave)) = &self.kernels else { return 0 };
        let mut count = 0;
        for (entity, s) in &mut self.meshes {
            let Some(bones) = s.pending.as_ref() else { continue };
            // Not uploaded by Bevy yet: try again next frame.
            let Some(slice) = allocator.mesh_vertex_slice(&s.asset) else { continue };
            let offset = u64::from(slice.range.start) * s.layout.stride;
            let n = s.mesh.vertex_count() as u32;
            let copy = match plan(context, 0, n, slice.buffer.size(), offset, s.layout.stride, s.layout.fields) {
                Ok(copy) => copy,
                Err(e) => {
                    error!("bevy_dentbend: {entity}'s skinned mesh does not fit its slab ({e})");
                    s.pending = None;
                    continue;
                }
            };
            let done = skin.encode(context, encoder, &s.mesh, bones).map_err(|e| e.to_string()).and_then(|()| {
                interleave
                    .encode(context, encoder, &copy, s.mesh.positions(), s.mesh.normals(), slice.buffer)
                    .map_err(|e| e.to_string())
            });
            match done {
                Ok(()) => count += 1,
                Err(e) => error!("bevy_dentbend: {entity} could not be skinned ({e})"),
            }
            s.last = s.pending.take();
        }
        count
    }
}
