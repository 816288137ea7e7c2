//! The dent backend the plug-in plans with: dents of CPU-path bodies are made at once on all
//! cores; dents of GPU-path bodies are kept, owned, for the render world's next batch.

use std::collections::{HashMap, HashSet};

use bevy::prelude::Entity;
use dentbend::TriMesh;
use dentbend::damage::DentBackend;
use dentbend::dent::{BatchError, BatchOutcome, DentJob, dent_batch_tracked};

use crate::link::GpuJob;

/// Splits each batch between the CPU (now) and the GPU (queued).
pub(crate) struct SplitBackend<'a> {
    gpu: &'a HashSet<Entity>,
    /// Id of the first queued dent (the others follow in order).
    first_id: u64,
    /// The GPU-path dents of the batch, in order.
    pub queued: Vec<GpuJob>,
}

impl<'a> SplitBackend<'a> {
    /// Bodies in `gpu` are dented on the GPU, the others on the CPU; the queued dents are
    /// numbered from `first_id`.
    pub fn new(gpu: &'a HashSet<Entity>, first_id: u64) -> Self {
        Self { gpu, first_id, queued: Vec::new() }
    }
}

impl DentBackend<Entity> for SplitBackend<'_> {
    fn dent_batch(
        &mut self,
        keys: &[Entity],
        meshes: &mut [TriMesh],
        jobs: &[DentJob<'_>],
    ) -> Result<BatchOutcome, BatchError> {
        let on_cpu: Vec<usize> = (0..keys.len()).filter(|&t| !self.gpu.contains(&keys[t])).collect();
        let cpu_slot: HashMap<usize, usize> = on_cpu.iter().enumerate().map(|(k, &t)| (t, k)).collect();
        let cpu_jobs: Vec<usize> = (0..jobs.len()).filter(|&j| cpu_slot.contains_key(&jobs[j].target)).collect();
        let mut outcome = BatchOutcome {
            reports: vec![Default::default(); jobs.len()],
            moved: vec![Vec::new(); keys.len()],
            refined: vec![Default::default(); keys.len()],
        };
        if !cpu_jobs.is_empty() {
            let mut cpu_meshes: Vec<TriMesh> = on_cpu.iter().map(|&t| meshes[t].clone()).collect();
            let batch: Vec<DentJob<'_>> =
                cpu_jobs.iter().map(|&j| DentJob { target: cpu_slot[&jobs[j].target], ..jobs[j].clone() }).collect();
            let done = dent_batch_tracked(&mut cpu_meshes, &batch)
                .map_err(|e| BatchError { job: cpu_jobs[e.job], error: e.error })?;
            for (k, report) in done.reports.into_iter().enumerate() {
                outcome.reports[cpu_jobs[k]] = report;
            }
            let mut refined = done.refined.into_iter();
            for ((mesh, moved), &t) in cpu_meshes.into_iter().zip(done.moved).zip(&on_cpu) {
                meshes[t] = mesh;
                outcome.moved[t] = moved;
                outcome.refined[t] = refined.next().unwrap_or_default();
            }
        }
        self.queued = jobs
            .iter()
            .filter(|j| !cpu_slot.contains_key(&j.target))
            .zip(self.first_id..)
            .map(|(j, id)| GpuJob {
                id,
                target: keys[j.target],
                projectile: j.projectile.clone(),
                impact: j.impact,
                params: j.params.clone(),
            })
            .collect();
        Ok(outcome)
    }
}
