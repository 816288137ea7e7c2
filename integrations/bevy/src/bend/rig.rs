//! Builds a bendable body's rig when its mesh is available: skinning weights, one dynamic body
//! of the engine per bone (convex hull of its sub-body), spherical joints at the skeleton's
//! joints.

use bevy::prelude::*;
use dentbend::TriMesh;
use dentbend::bend::{self, JointState};
use dentbend::damage::Damage;
use dentbend::glam::Quat;

use super::{BendPiece, Bendable, Bends, Joint, Rig};
use crate::engine::Engine;
use crate::link::{GpuStatus, MainLink, ToRender};
use crate::register::{Unregistered, prepare_mesh, refuse};
use crate::scale::scale_refusal;
use crate::{DentPath, DentRegistered};

/// The rig of a bendable body, before anything is spawned.
struct Built {
    core: bend::Rig,
    /// Each bone's sub-body vertices (rest frame, m), its collider's hull.
    parts: Vec<Vec<Vec3>>,
    rules: Vec<(usize, usize, Vec3, JointState)>,
}

/// Registers each new bendable body once its mesh is loaded and the GPU's status is known.
pub(crate) fn register_bendables<E: Engine>(
    mut commands: Commands,
    mut bends: ResMut<Bends>,
    mut meshes: ResMut<Assets<Mesh>>,
    link: Res<MainLink>,
    new: Query<(Entity, &Bendable, &Mesh3d, &GlobalTransform), Unregistered>,
) {
    let status = link.status();
    if status == GpuStatus::Pending {
        return;
    }
    for (entity, bendable, mesh3d, transform) in &new {
        if let Some(reason) = scale_refusal(transform) {
            refuse(&mut commands, entity, reason);
            continue;
        }
        let Some(mesh) = meshes.get(&mesh3d.0) else { continue };
        let prepared = prepare_mesh(entity, mesh, "bend")
            .and_then(|(copy, tri, layout)| Ok((copy, build(tri, bendable)?, layout)));
        let (copy, built, layout) = match prepared {
            Ok(done) => done,
            Err(reason) => {
                refuse(&mut commands, entity, reason);
                continue;
            }
        };
        let pose = transform.affine();
        let at = Transform::from_matrix(Mat4::from(pose));
        let material = (bendable.settings.density, bendable.settings.friction);
        let bodies: Option<Vec<_>> =
            built.parts.iter().map(|hull| E::bone_body(hull, material, at, (Vec3::ZERO, Vec3::ZERO))).collect();
        let Some(bodies) = bodies else {
            refuse(&mut commands, entity, "a bone's sub-body has no convex hull".into());
            continue;
        };
        let pieces: Vec<Entity> = bodies
            .into_iter()
            .enumerate()
            .map(|(bone, body)| commands.spawn((BendPiece { owner: entity, bone }, body)).id())
            .collect();
        let mut joints = Vec::new();
        for (parent, child, point, rule) in built.rules {
            let link = E::join(&mut commands, pieces[parent], pieces[child], point);
            joints.push(Joint { parent, child, point, rule, link });
        }
        let handle = meshes.add(copy);
        let path = match status {
            GpuStatus::Ready(_) => {
                register_skin(&link, entity, handle.id(), &built.core, layout);
                DentPath::Gpu
            }
            _ => DentPath::Cpu,
        };
        commands.entity(entity).insert((Mesh3d(handle.clone()), DentRegistered));
        let rig = Rig {
            pose,
            pieces,
            joints,
            core: built.core,
            dent: bendable.dent.clone().map(|settings| (settings, Damage::new(), 0)),
            settings: bendable.settings,
            path,
            mesh: handle,
            last: Vec::new(),
        };
        bends.rigs.insert(entity, rig);
    }
}

/// Puts `core`'s rest mesh and influences on the render world's skinner for `entity`'s mesh
/// `asset` (laid out as `layout`), replacing what it had.
pub(crate) fn register_skin(
    link: &MainLink,
    entity: Entity,
    asset: AssetId<Mesh>,
    core: &bend::Rig,
    layout: crate::SlabLayout,
) {
    let rest = core.rest();
    link.send(ToRender::RegisterSkin {
        entity,
        asset,
        positions: rest.positions().to_vec(),
        normals: rest.normals().to_vec(),
        influences: core.influences().to_vec(),
        bones: core.skeleton().len() as u32,
        layout,
    });
}

/// Weights, sub-bodies and joint rules of `bendable` over `rest`.
fn build(rest: TriMesh, bendable: &Bendable) -> Result<Built, String> {
    let (skeleton, settings) = (bendable.skeleton.clone(), &bendable.settings);
    let error = |e: dentbend::bend::BendError| format!("its rig cannot be built: {e}");
    let rig = bend::Rig::new(rest, skeleton, settings.weights, settings.density).map_err(error)?;
    let parts = (0..rig.skeleton().len())
        .map(|bone| rig.part(bone).map(|part| part.positions().to_vec()))
        .collect::<Result<_, _>>()
        .map_err(error)?;
    let mut rules = Vec::new();
    for j in rig.skeleton().joints() {
        let rule = JointState::new(settings.joint, Quat::IDENTITY).map_err(|e| e.to_string())?;
        rules.push((j.parent, j.child, j.point, rule));
    }
    Ok(Built { core: rig, parts, rules })
}

/// Despawns the bones of bendable bodies that were despawned or lost their component.
pub(crate) fn forget_removed(
    mut commands: Commands,
    mut bends: ResMut<Bends>,
    link: Res<MainLink>,
    mut removed: RemovedComponents<Bendable>,
) {
    for entity in removed.read() {
        if let Some(rig) = bends.rigs.remove(&entity) {
            for piece in rig.pieces.into_iter().chain(rig.joints.iter().filter_map(|j| j.link)) {
                commands.entity(piece).try_despawn();
            }
            link.send(ToRender::Forget(entity));
        }
    }
}
