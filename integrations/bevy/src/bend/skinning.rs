//! Each frame's bone matrices: on the GPU path sent to the render world, which skins the mesh
//! into Bevy's vertex slab; on the CPU path skinned here into the mesh asset.

use bevy::camera::primitives::Aabb;
use bevy::prelude::*;
use dentbend::cpu::{SkinBone, SkinParams, skin};
use dentbend::glam::Vec3 as DVec3;

use super::Bends;
use crate::DentPath;
use crate::link::{MainLink, ToRender};
use crate::mesh_data::write_vertices;

/// Skins every bendable body whose bones moved since the last frame, and bounds it for
/// culling: linear blend skinning keeps each vertex in the convex hull of its bones' images of
/// it, so the union of every bone's image of the rest mesh's box bounds the skinned mesh.
pub(crate) fn pose_bendables(
    mut commands: Commands,
    mut bends: ResMut<Bends>,
    link: Res<MainLink>,
    pieces: Query<&GlobalTransform>,
    mut meshes: ResMut<Assets<Mesh>>,
) {
    for (&entity, rig) in bends.rigs.iter_mut() {
        let to_entity = rig.pose.inverse();
        let bones: Option<Vec<SkinBone>> = rig
            .pieces
            .iter()
            .map(|&p| pieces.get(p).ok().map(|t| SkinBone::from_affine(to_entity * t.affine())))
            .collect();
        let Some(bones) = bones else { continue };
        if bones == rig.last {
            continue;
        }
        commands.entity(entity).try_insert(skinned_bounds(rig.core.rest(), &bones));
        match rig.path {
            DentPath::Gpu => link.send(ToRender::Pose { entity, bones: bones.clone() }),
            DentPath::Cpu => {
                let n = rig.core.rest().vertex_count();
                let (mut positions, mut normals) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
                let params = SkinParams::new(n as u32, bones.len() as u32);
                let rest = (rig.core.rest().positions(), rig.core.rest().normals());
                let influences = rig.core.influences();
                if let Err(e) = skin(&params, &bones, rest.0, rest.1, influences, &mut positions, &mut normals) {
                    error!("bevy_dentbend: {entity} could not be skinned ({e})");
                    continue;
                }
                if let Some(mut mesh) = meshes.get_mut(&rig.mesh)
                    && let Err(e) = write_vertices(&mut mesh, &positions, &normals)
                {
                    error!("bevy_dentbend: {entity}'s skinned mesh could not be written ({e})");
                }
            }
        }
        rig.last = bones;
    }
}

/// A box holding `rest` skinned by any blend of `bones` (its own coordinates).
fn skinned_bounds(rest: &dentbend::TriMesh, bones: &[SkinBone]) -> Aabb {
    let (lo, hi) = rest.bounds();
    let (mut min, mut max) = (DVec3::splat(f32::INFINITY), DVec3::splat(f32::NEG_INFINITY));
    for bone in bones {
        for corner in 0..8 {
            let c = DVec3::new(
                if corner & 1 == 0 { lo.x } else { hi.x },
                if corner & 2 == 0 { lo.y } else { hi.y },
                if corner & 4 == 0 { lo.z } else { hi.z },
            );
            let p = DVec3::from_array(bone.rows.map(|r| r[0] * c.x + r[1] * c.y + r[2] * c.z + r[3]));
            (min, max) = (min.min(p), max.max(p));
        }
    }
    Aabb::from_min_max(Vec3::from(min.to_array()), Vec3::from(max.to_array()))
}
