//! Each step's contacts → hits → dents through the world-free damage API: CPU-path bodies are
//! dented and their mesh assets updated at once, GPU-path dents go to the render world.

use bevy::prelude::*;
use dentbend::dent::{Hit, Impact, Surface};

use crate::backend::SplitBackend;
use crate::link::{MainLink, ToMain, ToRender};
use crate::mesh_data::write_dented;
use crate::world::surface_in;
use crate::{DentApplied, DentContact, DentPath, DentStats, DentWorld, MeshDented};

/// Decides and makes the dents of this step's [`DentContact`]s.
pub(crate) fn decide_dents(
    mut world: ResMut<DentWorld>,
    mut contacts: MessageReader<DentContact>,
    link: Res<MainLink>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut stats: ResMut<DentStats>,
    mut applied: MessageWriter<DentApplied>,
    mut dented: MessageWriter<MeshDented>,
) {
    let contacts: Vec<DentContact> = contacts.read().copied().collect();
    world.step += 1;
    let step = world.step;
    // Sides whose target dents and whose projectile has a surface; poses refreshed.
    let mut sides = Vec::new();
    for c in &contacts {
        for (target, projectile, normal) in [(c.a, c.b, -c.normal), (c.b, c.a, c.normal)] {
            let Some(settings) = world.targets.settings(target.entity) else { continue };
            let progressive = settings.progressive;
            if world.surface(projectile.entity).is_none() || !(c.started || progressive) {
                continue;
            }
            if let Err(e) = world.targets.set_pose(target.entity, target.pose) {
                debug!("bevy_dentbend: a contact on {} has an unusable pose ({e})", target.entity);
                stats.rejected_contacts += 1;
                continue;
            }
            sides.push((target, projectile, c.point, normal));
        }
    }
    let world = &mut *world;
    let mut hits = Vec::with_capacity(sides.len());
    for (target, projectile, point, normal) in sides {
        let impact = match Impact::from_contact(point, normal, &target.state, &projectile.state) {
            Ok(impact) => impact,
            Err(e) => {
                debug!("bevy_dentbend: a contact on {} cannot dent ({e})", target.entity);
                stats.rejected_contacts += 1;
                continue;
            }
        };
        let Some(mesh) = surface_in(&world.targets, &world.surfaces, projectile.entity) else { continue };
        hits.push(Hit {
            target: target.entity,
            projectile: projectile.entity,
            impact,
            target_state: target.state,
            projectile_state: projectile.state,
            projectile_surface: Surface { mesh, to_world: projectile.pose },
        });
    }
    if hits.is_empty() {
        return;
    }
    let mut backend = SplitBackend::new(&world.on_gpu);
    let plan = match world.damage.plan(&world.targets, &hits, step, &mut backend) {
        Ok(plan) => plan,
        Err(e) => {
            warn!("bevy_dentbend: this step's dents were refused ({e}); nothing changed");
            stats.rejected_contacts += hits.len() as u64;
            return;
        }
    };
    for job in backend.queued {
        link.send(ToRender::Dent(job));
    }
    for dent in &plan.dents {
        let path = if world.on_gpu.contains(&dent.target) { DentPath::Gpu } else { DentPath::Cpu };
        if path == DentPath::Cpu {
            stats.dents += 1;
        }
        let (target, projectile, impact, dent_distance) =
            (dent.target, dent.projectile, dent.impact, dent.dent_distance);
        applied.write(DentApplied { target, projectile, impact, dent_distance, path });
    }
    let cpu_targets: Vec<_> = plan.targets.into_iter().filter(|t| !world.on_gpu.contains(&t.key)).collect();
    for t in &cpu_targets {
        let Some(body) = world.bodies.get(&t.key) else { continue };
        if let Some(mut mesh) = meshes.get_mut(&body.mesh)
            && let Err(e) = write_dented(&mut mesh, &t.mesh, &t.refinement)
        {
            error!("bevy_dentbend: {}'s dented mesh could not be written ({e})", t.key);
        }
        dented.write(MeshDented { entity: t.key, moved: t.moved.clone(), topology_changed: t.topology_changed });
    }
    world.targets.apply(cpu_targets);
}

/// Takes what the render world sent: batch counts and the collider read-backs, which update the
/// main world's meshes (and, through [`MeshDented`], the colliders).
pub(crate) fn receive_from_render(
    mut world: ResMut<DentWorld>,
    link: Res<MainLink>,
    mut stats: ResMut<DentStats>,
    mut dented: MessageWriter<MeshDented>,
) {
    for message in link.receive() {
        match message {
            ToMain::Batch { dents } => {
                stats.gpu_batches += 1;
                stats.gpu_dents += dents;
                stats.dents += dents;
            }
            ToMain::Dropped { dents } => stats.rejected_contacts += dents,
            ToMain::Demote(entities) => {
                for entity in entities {
                    world.demote(entity);
                }
            }
            ToMain::Moved { entity, moved, bytes } => {
                stats.collider_readback_bytes += bytes;
                if world.move_vertices(entity, &moved.indices, &moved.positions) {
                    dented.write(MeshDented { entity, moved: moved.indices, topology_changed: false });
                }
            }
        }
    }
}
