//! A frame's dents with host stages (refinement, the intersection guard, the volume rim, a
//! falloff fitted to a wall) on the GPU path: `GpuDenter::dent_batch` runs them around the
//! kernels on its copy of each mesh, waiting for the GPU and reading back only the vertices the
//! kernels moved. Each dent's report goes to the main world by its job's id; a target that kept
//! its triangles sends its moved vertices (for the collider), one that was refined sends its
//! new mesh, which the main world writes into the entity's mesh asset for Bevy to upload again.

use bevy::prelude::*;
use dentbend::dent::{BatchError, DentJob};
use dentbend::gpu::{GpuBatchError, GpuDenter, GpuError, MovedVertices};

use super::target::Target;
use crate::link::{GpuJob, RenderLink, ToMain};

/// `kept`'s dents (each with its target's slot) as the denter takes them.
pub(super) fn jobs(kept: &[(usize, GpuJob)]) -> Vec<DentJob<'_>> {
    kept.iter()
        .map(|(slot, j)| DentJob {
            target: *slot,
            projectile: &j.projectile,
            impact: j.impact,
            params: j.params.clone(),
        })
        .collect()
}

/// What [`make`] did: the dents made, and the bodies whose refined mesh outgrew what Bevy's
/// device can hold (their dents dropped and counted; they are to take the CPU path).
pub(super) struct Made {
    pub(super) dents: u64,
    pub(super) outgrown: Vec<Entity>,
}

/// Makes `kept`'s dents with every stage they ask for, in order; an invalid dent is dropped
/// (logged and counted) and the rest made. When a refined mesh would outgrow the device's
/// buffers, each body's dents run on their own to find the bodies that do; those are left out
/// of `kept`. `None` when the GPU failed otherwise (the frame's dents dropped; the denter put
/// every target back).
pub(super) fn make(
    denter: &mut GpuDenter,
    targets: &mut [Target],
    kept: &mut Vec<(usize, GpuJob)>,
    link: &RenderLink,
) -> Option<Made> {
    match batch(denter, kept, link) {
        Batch::Made(outcome) => {
            deliver(denter, targets, kept, &outcome, link);
            Some(Made { dents: kept.len() as u64, outgrown: Vec::new() })
        }
        Batch::Failed => None,
        Batch::Outgrown => {
            let mut slots: Vec<usize> = kept.iter().map(|(slot, _)| *slot).collect();
            slots.sort_unstable();
            slots.dedup();
            let (mut made, mut outgrown) = (Vec::new(), Vec::new());
            let mut failed = false;
            for slot in slots {
                let mut mine: Vec<(usize, GpuJob)> = kept.iter().filter(|(s, _)| *s == slot).cloned().collect();
                if failed {
                    // The GPU failed for an earlier body: the rest are dropped and counted.
                    link.send(ToMain::Dropped { ids: mine.iter().map(|(_, j)| j.id).collect() });
                    continue;
                }
                match batch(denter, &mut mine, link) {
                    Batch::Made(outcome) => {
                        deliver(denter, targets, &mine, &outcome, link);
                        made.extend(mine);
                    }
                    Batch::Outgrown => {
                        link.send(ToMain::Dropped { ids: mine.iter().map(|(_, j)| j.id).collect() });
                        outgrown.push(targets[slot].entity);
                    }
                    Batch::Failed => failed = true,
                }
            }
            *kept = made;
            Some(Made { dents: kept.len() as u64, outgrown })
        }
    }
}

/// How one `dent_batch` call ended.
enum Batch {
    Made(dentbend::dent::BatchOutcome),
    /// A refined mesh would not fit the device's buffers; nothing changed.
    Outgrown,
    /// The GPU failed otherwise (logged, the dents dropped and counted).
    Failed,
}

/// `dent_batch` over `kept`, dropping (logged and counted) each invalid dent until the rest
/// can run.
fn batch(denter: &mut GpuDenter, kept: &mut Vec<(usize, GpuJob)>, link: &RenderLink) -> Batch {
    loop {
        if kept.is_empty() {
            return Batch::Made(Default::default());
        }
        match denter.dent_batch(&jobs(kept)) {
            Ok(outcome) => return Batch::Made(outcome),
            Err(GpuBatchError::Job(bad)) => drop_refused(kept, &bad, link),
            Err(GpuBatchError::Gpu(GpuError::OverLimit { .. })) => return Batch::Outgrown,
            Err(e) => {
                drop_all(kept, &e, link);
                return Batch::Failed;
            }
        }
    }
}

/// Drops the dent of `kept` that a batch refused as `bad` (logged, counted by the main world).
pub(super) fn drop_refused(kept: &mut Vec<(usize, GpuJob)>, bad: &BatchError, link: &RenderLink) {
    let (_, job) = kept.remove(bad.job);
    warn!("bevy_dentbend: a dent on {} was refused ({}); the others go on", job.target, bad.error);
    link.send(ToMain::Dropped { ids: vec![job.id] });
}

/// Drops every dent of `kept` after the GPU failed with `error` (logged, counted by the main
/// world).
pub(super) fn drop_all(kept: &[(usize, GpuJob)], error: &GpuBatchError, link: &RenderLink) {
    error!("bevy_dentbend: a dent batch failed on the GPU ({error}); {} dent(s) dropped", kept.len());
    link.send(ToMain::Dropped { ids: kept.iter().map(|(_, j)| j.id).collect() });
}

/// Sends what `outcome` (of `kept`'s dents) did to the main world and updates the targets'
/// mirrors: each dent's report, then per dented target its moved vertices, or its refined mesh.
fn deliver(
    denter: &mut GpuDenter,
    targets: &mut [Target],
    kept: &[(usize, GpuJob)],
    outcome: &dentbend::dent::BatchOutcome,
    link: &RenderLink,
) {
    if kept.is_empty() {
        return;
    }
    let reports = kept.iter().zip(&outcome.reports).map(|((_, j), r)| (j.id, r.clone())).collect();
    link.send(ToMain::Made { reports, bytes: denter.bytes_read_back() });
    let mut dented: Vec<usize> = kept.iter().map(|(slot, _)| *slot).collect();
    dented.sort_unstable();
    dented.dedup();
    for slot in dented {
        let target = &mut targets[slot];
        let mesh = match denter.mesh(slot) {
            Ok(mesh) => mesh.clone(),
            Err(e) => {
                error!("bevy_dentbend: {}'s dented mesh is unavailable ({e})", target.entity);
                continue;
            }
        };
        let moved = outcome.moved.get(slot).cloned().unwrap_or_default();
        if outcome.topology_changed(slot) {
            let refinement = outcome.refined[slot].clone();
            link.send(ToMain::Refined { entity: target.entity, mesh: mesh.clone(), refinement, moved });
        } else {
            let positions = moved.iter().map(|&v| mesh.positions()[v as usize]).collect();
            let moved = MovedVertices { indices: moved, positions };
            link.send(ToMain::Moved { entity: target.entity, moved, bytes: 0 });
        }
        target.mirror = mesh;
        target.copy_needed = true;
    }
}
