//! Each step's contacts → hits → dents through the world-free damage API: CPU-path bodies are
//! dented and their mesh assets updated at once, GPU-path dents go to the render world.

use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use std::collections::HashSet;

use dentbend::damage::{AppliedDent, Hit};
use dentbend::dent::{Impact, Surface};

use crate::backend::SplitBackend;
use crate::fracture::{Breaking, break_bodies};
use crate::link::{MainLink, ToMain, ToRender};
use crate::mesh_data::write_dented;
use crate::scale::{for_asset, rigid_pose};
use crate::world::surface_in;
use crate::{DentApplied, DentContact, DentPath, DentStats, DentWorld, MeshDented};

/// What [`decide_dents`] reports: its messages, and the names it logs bodies by.
#[derive(SystemParam)]
pub(crate) struct DentReports<'w, 's> {
    applied: MessageWriter<'w, DentApplied>,
    dented: MessageWriter<'w, MeshDented>,
    names: Query<'w, 's, &'static Name>,
}

/// Decides and makes the dents of this step's [`DentContact`]s.
pub(crate) fn decide_dents(
    mut world: ResMut<DentWorld>,
    mut contacts: MessageReader<DentContact>,
    link: Res<MainLink>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut stats: ResMut<DentStats>,
    mut reports: DentReports,
    mut breaking: Breaking,
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
            // Poses are rigid (a body's scale is in the mesh the plug-in keeps).
            if let Err(e) = world.targets.set_pose(target.entity, rigid_pose(target.pose)) {
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
    let mut backend = SplitBackend::new(&world.on_gpu, world.next_job);
    let plan = match world.damage.plan(&world.targets, &hits, step, &mut backend) {
        Ok(plan) => plan,
        Err(e) => {
            warn!("bevy_dentbend: this step's dents were refused ({e}); nothing changed");
            stats.rejected_contacts += hits.len() as u64;
            return;
        }
    };
    world.next_job += backend.queued.len() as u64;
    // The GPU-path dents, in the order they were queued (the plan's order): a dent with host
    // stages reports how deep it really is once the render world has made it.
    let mut queued = backend.queued.into_iter();
    for dent in &plan.dents {
        let path = if world.on_gpu.contains(&dent.target) { DentPath::Gpu } else { DentPath::Cpu };
        let (target, projectile, impact, dent_distance) =
            (dent.target, dent.projectile, dent.impact, dent.dent_distance);
        let mut applied =
            DentApplied { target, projectile, impact, dent_distance, depth_made: None, limited_to: None, path };
        match path {
            DentPath::Gpu => {
                let Some(job) = queued.next() else { continue };
                let staged = !job.params.host_stages().is_empty();
                let id = job.id;
                world.records.queued(dent.target);
                link.send(ToRender::Dent(job));
                if staged {
                    world.awaiting_report.insert(id, applied);
                    continue;
                }
            }
            DentPath::Cpu => {
                count_cpu_dent(&mut stats, dent);
                if dent.moved_vertices == 0 {
                    warn_empty_once(
                        &mut world.warned_empty,
                        (dent.target, dent.dent_distance, dent.limited_to),
                        &reports.names,
                    );
                }
                (applied.depth_made, applied.limited_to) = (Some(dent.depth_made), dent.limited_to);
            }
        }
        reports.applied.write(applied);
    }
    stats.refined_triangles += plan
        .targets
        .iter()
        .filter(|t| !world.on_gpu.contains(&t.key))
        .map(|t| t.refinement.added_faces() as u64)
        .sum::<u64>();
    let cpu_targets: Vec<_> = plan.targets.into_iter().filter(|t| !world.on_gpu.contains(&t.key)).collect();
    for t in &cpu_targets {
        let Some(body) = world.bodies.get(&t.key) else { continue };
        let written = match for_asset(&t.mesh, body.scale) {
            Ok(mesh) => mesh,
            Err(e) => {
                error!("bevy_dentbend: {}'s dented mesh could not be unscaled ({e})", t.key);
                continue;
            }
        };
        if let Some(mut mesh) = meshes.get_mut(&body.mesh)
            && let Err(e) = write_dented(&mut mesh, &written, &t.refinement)
        {
            error!("bevy_dentbend: {}'s dented mesh could not be written ({e})", t.key);
        }
        reports.dented.write(MeshDented {
            entity: t.key,
            moved: t.moved.clone(),
            topology_changed: t.topology_changed,
        });
    }
    for t in &cpu_targets {
        let dents = plan.dents.iter().filter(|d| d.target == t.key).count() as u32;
        world.records.changed(t.key, &t.mesh, dents);
    }
    world.targets.apply(cpu_targets);
    break_bodies(world, plan.fractures, &mut breaking, (&mut meshes, &mut reports.dented, &mut stats));
}

/// Counts a dent made on the CPU path.
fn count_cpu_dent(stats: &mut DentStats, dent: &AppliedDent<Entity>) {
    stats.dents += 1;
    stats.cpu_dents += 1;
    stats.limited_dents += u64::from(dent.limited_to.is_some());
    stats.empty_dents += u64::from(dent.moved_vertices == 0);
}

/// Logs, once per body, that a dent on it (target, decided distance in m, the guard's limit)
/// moved nothing, naming it and what fixes it.
fn warn_empty_once(
    warned: &mut HashSet<Entity>,
    (target, dent_distance, limited_to): (Entity, f32, Option<f32>),
    names: &Query<&Name>,
) {
    if !warned.insert(target) {
        return;
    }
    let name = names.get(target).map_or_else(|_| format!("{target}"), |n| format!("{n} ({target})"));
    let why = match limited_to {
        Some(_) => "the intersection guard limited it to nothing (any deeper, faces would cross or turn over)",
        None => "no vertex lies under its map (the mesh is too coarse there)",
    };
    warn!(
        "bevy_dentbend: a {:.3} m dent on {name} moved no vertex: {why}; give the body a finer mesh, or settings with \
         refinement (`Refine::Auto`, the default of `DentSettings`), so that dents take their shape",
        dent_distance
    );
}

/// Takes what the render world sent: batch counts, the reports of dents made with host stages,
/// the collider read-backs and refined meshes, which update the main world's meshes (and,
/// through [`MeshDented`], the colliders; a refined mesh also its asset, which Bevy uploads
/// again with its new vertices and triangles).
pub(crate) fn receive_from_render(
    mut world: ResMut<DentWorld>,
    link: Res<MainLink>,
    mut stats: ResMut<DentStats>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut reports: DentReports,
) {
    for message in link.receive() {
        match message {
            ToMain::Batch { dents } => {
                stats.gpu_batches += 1;
                stats.gpu_dents += dents;
                stats.dents += dents;
            }
            ToMain::Dropped { ids } => {
                stats.rejected_contacts += ids.len() as u64;
                for id in &ids {
                    world.awaiting_report.remove(id);
                }
            }
            ToMain::Demote(entities) => {
                for entity in entities {
                    world.demote(entity);
                }
            }
            ToMain::Moved { entity, moved, bytes } => {
                stats.collider_readback_bytes += bytes;
                if world.move_vertices(entity, &moved.indices, &moved.positions) {
                    reports.dented.write(MeshDented { entity, moved: moved.indices, topology_changed: false });
                }
            }
            ToMain::Made { reports: made, bytes } => {
                stats.collider_readback_bytes += bytes;
                for (id, report) in made {
                    stats.limited_dents += u64::from(report.limited_to.is_some());
                    stats.empty_dents += u64::from(report.moved_vertices == 0);
                    stats.refined_triangles += report.refined_triangles as u64;
                    let Some(mut applied) = world.awaiting_report.remove(&id) else { continue };
                    if report.moved_vertices == 0 {
                        let dent = (applied.target, applied.dent_distance, report.limited_to);
                        warn_empty_once(&mut world.warned_empty, dent, &reports.names);
                    }
                    (applied.depth_made, applied.limited_to) = (Some(report.max_displacement), report.limited_to);
                    reports.applied.write(applied);
                }
            }
            ToMain::Refined { entity, mesh, refinement, moved } => {
                if let Some(body) = world.bodies.get(&entity)
                    && let Some(mut asset) = meshes.get_mut(&body.mesh)
                    && let Err(e) = write_dented(&mut asset, &mesh, &refinement)
                {
                    error!("bevy_dentbend: {entity}'s refined mesh could not be written ({e})");
                }
                if world.take_refined(entity, mesh, refinement, moved.clone()) {
                    reports.dented.write(MeshDented { entity, moved, topology_changed: true });
                }
            }
        }
    }
}
