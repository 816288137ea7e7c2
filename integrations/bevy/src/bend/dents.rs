//! Dents on bendable bodies: each step's contacts on a dentable bendable body's bones dent its
//! rest mesh skinned to the bones' poses (on all cores), the dent is mapped back to the rest
//! mesh ([`Rig::rest_after_pose_dent`](dentbend::bend::Rig::rest_after_pose_dent)), the bones
//! owning a moved vertex get new hulls, and the mesh is skinned again from the new rest mesh.

use std::collections::HashMap;

use bevy::prelude::*;
use dentbend::damage::{CpuBackend, Hit, TargetSet};
use dentbend::dent::{Impact, Surface};
use dentbend::glam::Affine3A;

use super::rig::register_skin;
use super::{BendPiece, Bends, Rig};
use crate::engine::Engine;
use crate::link::MainLink;
use crate::mesh_data::slab_layout;
use crate::{DentApplied, DentBody, DentContact, DentPath, DentStats, DentWorld};

/// One contact on a bone: the bone's side and the other's, the point and the normal into the
/// bone.
#[derive(Clone, Copy)]
struct BoneHit {
    bone: DentBody,
    other: DentBody,
    point: Vec3,
    normal: Vec3,
}

/// Dents every dentable bendable body hit by this step's [`DentContact`]s.
#[allow(clippy::too_many_arguments)]
pub(crate) fn dent_bendables<E: Engine>(
    mut contacts: MessageReader<DentContact>,
    mut bends: ResMut<Bends>,
    world: Res<DentWorld>,
    pieces: Query<&BendPiece>,
    transforms: Query<&GlobalTransform>,
    mut colliders: Query<&mut E::Collider>,
    (mut stats, mut applied): (ResMut<DentStats>, MessageWriter<DentApplied>),
    (link, meshes): (Res<MainLink>, Res<Assets<Mesh>>),
) {
    let mut by_body: HashMap<Entity, Vec<BoneHit>> = HashMap::new();
    for c in contacts.read() {
        for (bone, other, normal) in [(c.a, c.b, -c.normal), (c.b, c.a, c.normal)] {
            let Ok(piece) = pieces.get(bone.entity) else { continue };
            let dents = bends.rigs.get(&piece.owner).and_then(|r| r.dent.as_ref());
            let Some((settings, _, _)) = dents else { continue };
            if world.surface(other.entity).is_none() || !(c.started || settings.progressive) {
                continue;
            }
            by_body.entry(piece.owner).or_default().push(BoneHit { bone, other, point: c.point, normal });
        }
    }
    for (owner, hits) in by_body {
        let Some(rig) = bends.rigs.get_mut(&owner) else { continue };
        match dent_body::<E>(rig, owner, &hits, &world, &pieces, &transforms) {
            Ok(made) => {
                for (bone, hull) in made.hulls {
                    if let Some(&piece) = rig.pieces.get(bone)
                        && let Ok(mut collider) = colliders.get_mut(piece)
                    {
                        *collider = hull;
                    }
                }
                let n = made.applied.len() as u64;
                (stats.dents, stats.cpu_dents, stats.bendable_dents) =
                    (stats.dents + n, stats.cpu_dents + n, stats.bendable_dents + n);
                for a in made.applied {
                    applied.write(a);
                }
                // Skinned again from the new rest mesh: on the GPU by the render world's skinner.
                rig.last.clear();
                if rig.path == DentPath::Gpu
                    && let Some(layout) = meshes.get(&rig.mesh).and_then(|m| slab_layout(m).ok())
                {
                    register_skin(&link, owner, rig.mesh.id(), &rig.core, layout);
                }
            }
            Err(e) => warn!("bevy_dentbend: bendable {owner} keeps its mesh: {e}"),
        }
    }
}

/// What denting one bendable body made.
struct Made<C> {
    /// New hulls of the bones owning a moved vertex.
    hulls: Vec<(usize, C)>,
    applied: Vec<DentApplied>,
}

/// Dents `rig` (bendable `owner`) by `hits`, updating its rest mesh and progressive state.
fn dent_body<E: Engine>(
    rig: &mut Rig,
    owner: Entity,
    hits: &[BoneHit],
    world: &DentWorld,
    pieces: &Query<&BendPiece>,
    transforms: &Query<&GlobalTransform>,
) -> Result<Made<E::Collider>, String> {
    // Each bone's rest → world transform: the contact's pose for a hit bone (the step's start),
    // the bone's transform now for the others.
    let mut bones: Vec<Affine3A> = rig
        .pieces
        .iter()
        .map(|&p| transforms.get(p).map(GlobalTransform::affine).map_err(|_| format!("bone {p} is gone")))
        .collect::<Result<_, _>>()?;
    for hit in hits {
        if let Ok(piece) = pieces.get(hit.bone.entity)
            && let Some(slot) = bones.get_mut(piece.bone)
        {
            *slot = hit.bone.pose;
        }
    }
    let skinned = rig.core.skinned(&bones).map_err(|e| e.to_string())?;
    let Some((settings, damage, step)) = &mut rig.dent else { return Err("it does not dent".into()) };
    let mut targets = TargetSet::new();
    targets.insert(owner, skinned.clone(), Affine3A::IDENTITY, settings.clone()).map_err(|e| e.to_string())?;
    let mut planned = Vec::with_capacity(hits.len());
    for hit in hits {
        let Some(mesh) = world.surface(hit.other.entity) else { continue };
        let Ok(impact) = Impact::from_contact(hit.point, hit.normal, &hit.bone.state, &hit.other.state) else {
            continue;
        };
        targets.insert_rigid(hit.other.entity);
        planned.push(Hit {
            target: owner,
            projectile: hit.other.entity,
            impact,
            target_state: hit.bone.state,
            projectile_state: hit.other.state,
            projectile_surface: Surface { mesh, to_world: hit.other.pose },
        });
    }
    let mut next = damage.clone();
    let plan = next.plan(&targets, &planned, *step + 1, &mut CpuBackend).map_err(|e| e.to_string())?;
    (*damage, *step) = (next, *step + 1);
    let Some(dented) = plan.targets.into_iter().find(|t| t.key == owner) else {
        return Ok(Made { hulls: Vec::new(), applied: Vec::new() });
    };
    let core = &mut rig.core;
    let rest = core.rest_after_pose_dent(core.rest(), &skinned, &dented.mesh, &dented.moved, &bones);
    core.set_rest(rest.map_err(|e| e.to_string())?).map_err(|e| e.to_string())?;
    let mut hulls = Vec::new();
    for bone in core.bones_owning(&dented.moved) {
        let part = core.part(bone).map_err(|e| e.to_string())?;
        let hull = E::hull(part.positions()).ok_or(format!("bone {bone}'s dented part has no hull"))?;
        hulls.push((bone, hull));
    }
    let applied = plan
        .dents
        .iter()
        .map(|d| DentApplied {
            target: owner,
            projectile: d.projectile,
            impact: d.impact,
            dent_distance: d.dent_distance,
            depth_made: Some(d.depth_made),
            limited_to: d.limited_to,
            path: DentPath::Cpu,
        })
        .collect();
    Ok(Made { hulls, applied })
}
