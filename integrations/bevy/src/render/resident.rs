//! The dentable meshes resident on Bevy's device and the dents waiting for the next batch: each
//! frame's batch, the writes into Bevy's vertex slabs and the collider read-backs are recorded
//! here.

use bevy::prelude::*;
use bevy::render::mesh::allocator::MeshAllocator;
use dentbend::TriMesh;
use dentbend::gpu::{GpuBatchError, GpuContext, GpuDenter, PendingMoved};

use super::readbacks::{Mirrors, Readbacks};
use super::skinned::SkinnedMeshes;
use super::target::Target;
use crate::link::{GpuJob, RenderLink, ToMain, ToRender};

/// Render-world state of the GPU path.
#[derive(Resource, Default)]
pub(crate) struct ResidentDents {
    context: Option<GpuContext>,
    denter: Option<GpuDenter>,
    targets: Vec<Target>,
    /// The targets changed since the denter was built.
    stale: bool,
    jobs: Vec<GpuJob>,
    reads: Readbacks,
    skinned: SkinnedMeshes,
    /// Bodies the last batch found too large for the device once refined: they leave the GPU
    /// path after the frame is recorded.
    outgrown: Vec<Entity>,
}

/// The resident targets as the read-backs see them.
struct Slots<'a>(&'a mut Vec<Target>);

impl Mirrors for Slots<'_> {
    fn mirror(&mut self, entity: Entity) -> Option<(usize, &mut TriMesh)> {
        let slot = self.0.iter().position(|t| t.entity == entity)?;
        Some((slot, &mut self.0[slot].mirror))
    }
}

/// What one frame recorded.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Recorded {
    pub dents: u64,
    pub copies: u64,
    pub skinned: u64,
}

impl ResidentDents {
    /// Runs on `context` from now on.
    pub fn start(&mut self, context: GpuContext) {
        self.context = Some(context);
    }

    /// Whether the GPU path runs.
    pub fn is_running(&self) -> bool {
        self.context.is_some()
    }

    /// Takes the main world's messages.
    pub fn take(&mut self, messages: Vec<ToRender>) {
        for message in messages {
            match message {
                ToRender::Register { entity, asset, mesh, layout } => {
                    self.forget(entity);
                    let target = Target { entity, asset, mirror: mesh, layout, copy_needed: false, copied_at: None };
                    self.targets.push(target);
                    self.stale = true;
                }
                ToRender::Forget(entity) => {
                    self.forget(entity);
                    self.skinned.forget(entity);
                }
                ToRender::Dent(job) => self.jobs.push(job),
                ToRender::RegisterSkin { entity, asset, positions, normals, influences, bones, layout } => {
                    if let Some(context) = &self.context {
                        self.skinned.register(context, entity, asset, &positions, &normals, &influences, bones, layout);
                    }
                }
                ToRender::Pose { entity, bones } => self.skinned.pose(entity, bones),
            }
        }
    }

    fn forget(&mut self, entity: Entity) {
        if let Some(slot) = self.targets.iter().position(|t| t.entity == entity) {
            self.targets.remove(slot);
            self.stale = true;
        }
    }

    /// Marks the targets whose asset Bevy uploaded again (their dents must be written again).
    pub fn uploaded_again(&mut self, assets: impl Iterator<Item = AssetId<Mesh>>) {
        for asset in assets {
            for t in self.targets.iter_mut().filter(|t| t.asset == asset) {
                t.copy_needed = true;
            }
            self.skinned.uploaded_again(asset);
        }
    }

    /// Advances the collider read-backs; sends each finished one to the main world. While the
    /// targets wait to be uploaded again their slots are not the denter's, so a failed read-back
    /// is not replaced by a whole-mesh one then.
    pub fn poll_reads(&mut self, link: &RenderLink) {
        let Self { reads, targets, denter, stale, .. } = self;
        let denter = if *stale { None } else { denter.as_ref() };
        reads.poll(&mut Slots(targets), denter, link);
    }

    /// Waits for the read-backs under way and applies them, so that a batch run now (whose
    /// results reach the mirrors and the main world at once) lands after them.
    fn settle_reads(&mut self, link: &RenderLink) {
        // A count, then a list, each mapped after a wait.
        for _ in 0..3 {
            if self.reads.is_empty() {
                return;
            }
            if let Some(context) = &self.context
                && let Err(e) = context.wait()
            {
                warn!("bevy_dentbend: waiting for the collider read-backs failed ({e})");
            }
            self.poll_reads(link);
        }
    }

    /// Uploads the targets again when they changed and no read-back is under way (so every
    /// mirror holds the dents the GPU made).
    pub fn rebuild_if_stale(&mut self, link: &RenderLink) {
        let Some(context) = &self.context else { return };
        if !self.stale || !self.reads.is_empty() {
            return;
        }
        self.stale = false;
        self.denter = None;
        if self.targets.is_empty() {
            return;
        }
        let meshes: Vec<TriMesh> = self.targets.iter().map(|t| t.mirror.clone()).collect();
        match GpuDenter::new(context, &meshes) {
            Ok(denter) => self.denter = Some(denter),
            Err(e) => {
                error!("bevy_dentbend: the dentable meshes could not be made resident ({e}); they take the CPU path");
                let entities = self.targets.drain(..).map(|t| t.entity).collect();
                link.send(ToMain::Demote(entities));
            }
        }
    }

    /// Records this frame's dents, writes dented targets into Bevy's vertex slabs, records their
    /// collider read-backs and skins the bendable meshes that moved, in one submission on Bevy's
    /// queue (before Bevy's own frame, so this frame draws them).
    pub fn record(&mut self, allocator: &MeshAllocator, link: &RenderLink) -> Recorded {
        let Some(context) = self.context.clone() else { return Recorded::default() };
        if self.jobs.iter().any(|j| !j.params.host_stages().is_empty()) {
            // This frame's batch waits for the GPU and updates the mirrors at once: the older
            // read-backs must land first.
            self.settle_reads(link);
        }
        let mut encoder = context.device.create_command_encoder(&Default::default());
        let Some((dents, copies, reads)) = self.record_dents(&mut encoder, allocator, link) else {
            // A failed batch may have left part of itself in the encoder: drop it.
            return Recorded::default();
        };
        let skinned = self.skinned.record(&context, &mut encoder, allocator);
        context.queue.submit([encoder.finish()]);
        let outgrown = std::mem::take(&mut self.outgrown);
        if !outgrown.is_empty() {
            for &entity in &outgrown {
                warn!(
                    "bevy_dentbend: {entity}'s mesh, refined under a dent, would outgrow what Bevy's device can hold; \
                     it takes the CPU path from now on (its dent this frame was dropped)"
                );
                self.forget(entity);
            }
            link.send(ToMain::Demote(outgrown));
        }
        self.reads.submitted(reads);
        if dents > 0 {
            link.send(ToMain::Batch { dents });
        }
        Recorded { dents, copies, skinned }
    }

    /// Records the dents waiting (unless the targets are being uploaded again), the writes of
    /// dented targets into Bevy's vertex slabs and their collider read-backs into `encoder`:
    /// dents, copies and the read-backs to start once it is submitted. `None` when the GPU failed
    /// while recording.
    #[allow(clippy::type_complexity)]
    fn record_dents(
        &mut self,
        encoder: &mut dentbend::wgpu::CommandEncoder,
        allocator: &MeshAllocator,
        link: &RenderLink,
    ) -> Option<(u64, u64, Vec<(Entity, PendingMoved)>)> {
        if self.stale {
            // The targets are uploaded again once the read-backs under way are in: dents wait.
            return Some((0, 0, Vec::new()));
        }
        let Some(denter) = &mut self.denter else {
            // No resident target (all despawned, or demoted to the CPU path): drop and count.
            let dropped: Vec<u64> = std::mem::take(&mut self.jobs).iter().map(|j| j.id).collect();
            if !dropped.is_empty() {
                link.send(ToMain::Dropped { ids: dropped });
            }
            return Some((0, 0, Vec::new()));
        };
        let jobs = std::mem::take(&mut self.jobs);
        let slots: Vec<Option<usize>> =
            jobs.iter().map(|j| self.targets.iter().position(|t| t.entity == j.target)).collect();
        let gone: Vec<u64> = slots.iter().zip(&jobs).filter(|(s, _)| s.is_none()).map(|(_, j)| j.id).collect();
        if !gone.is_empty() {
            debug!("bevy_dentbend: {} dent(s) on despawned bodies skipped", gone.len());
            link.send(ToMain::Dropped { ids: gone });
        }
        let mut kept: Vec<(usize, GpuJob)> = slots.into_iter().zip(jobs).filter_map(|(s, j)| Some((s?, j))).collect();
        // Dents with host stages run them now (waiting for the GPU) and every dent of the frame
        // with them, in order; the paper's dents are recorded into the frame.
        let staged = kept.iter().any(|(_, j)| !j.params.host_stages().is_empty());
        let recorded = if staged { Kernels::NeedStages } else { record_kernels(denter, encoder, &mut kept, link) };
        let stages_ran = matches!(recorded, Kernels::NeedStages);
        let dents = match recorded {
            Kernels::Recorded(dents) => dents,
            Kernels::NeedStages => {
                let made = super::staged::make(denter, &mut self.targets, &mut kept, link)?;
                self.outgrown = made.outgrown;
                made.dents
            }
            Kernels::Failed => return None,
        };
        let mut dented: Vec<usize> = kept.iter().map(|(slot, _)| *slot).collect();
        dented.sort_unstable();
        dented.dedup();
        for &slot in &dented {
            self.targets[slot].copy_needed = true;
        }
        let mut copies = 0;
        for (slot, t) in self.targets.iter_mut().enumerate() {
            let Some(slice) = allocator.mesh_vertex_slice(&t.asset) else { continue };
            if slice.range.len() != t.mirror.vertex_count() {
                // Refined: its slot in the slab is the old size until the main world's mesh
                // asset, grown with it, is uploaded again (which marks it for a copy).
                continue;
            }
            let at = (slice.buffer.id(), slice.range.start);
            if !t.copy_needed && t.copied_at.is_none_or(|c| c == at) {
                t.copied_at.get_or_insert(at);
                continue;
            }
            let offset = u64::from(slice.range.start) * t.layout.stride;
            match denter.copy_target_into(encoder, slot, slice.buffer, offset, t.layout.stride, t.layout.fields) {
                Ok(()) => {
                    (t.copy_needed, t.copied_at) = (false, Some(at));
                    copies += 1;
                }
                Err(e) => error!(
                    "bevy_dentbend: the dents of {} could not be written into Bevy's vertex buffer ({e})",
                    t.entity
                ),
            }
        }
        if stages_ran {
            // The batch read back what it moved already (sent with its reports).
            return Some((dents, copies, Vec::new()));
        }
        let mut reads = Vec::with_capacity(dented.len());
        for &slot in &dented {
            match denter.record_moved(encoder, slot) {
                Ok(read) => reads.push((self.targets[slot].entity, read)),
                Err(e) => {
                    // It may have left part of itself in the encoder: drop the frame's batch.
                    error!("bevy_dentbend: a collider read-back could not be recorded ({e}); {dents} dent(s) dropped");
                    link.send(ToMain::Dropped { ids: kept.iter().map(|(_, j)| j.id).collect() });
                    return None;
                }
            }
        }
        Some((dents, copies, reads))
    }
}

/// What recording a frame's paper dents came to.
enum Kernels {
    /// Recorded, this many.
    Recorded(u64),
    /// A dent needs a host stage (a falloff fitted to a wall): the frame's dents run with them.
    NeedStages,
    /// The GPU failed; the frame's dents are dropped.
    Failed,
}

/// Records `kept`'s dents (the paper's) into `encoder`; an invalid dent is found before anything
/// is recorded, dropped (logged and counted) and the rest recorded.
fn record_kernels(
    denter: &mut GpuDenter,
    encoder: &mut dentbend::wgpu::CommandEncoder,
    kept: &mut Vec<(usize, GpuJob)>,
    link: &RenderLink,
) -> Kernels {
    loop {
        let batch = super::staged::jobs(kept);
        match denter.record_batch(encoder, &batch) {
            Ok(_) => return Kernels::Recorded(kept.len() as u64),
            Err(GpuBatchError::Job(bad)) => super::staged::drop_refused(kept, &bad, link),
            Err(GpuBatchError::HostStages { .. }) => return Kernels::NeedStages,
            Err(e) => {
                super::staged::drop_all(kept, &e, link);
                return Kernels::Failed;
            }
        }
    }
}
