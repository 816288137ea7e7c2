//! Dents on the GPU for the world-free damage API: a [`DentBackend`] keyed by the caller's ids
//! whose targets stay resident on the device ([`GpuDenter`]) between steps. A target whose mesh the GPU has not seen (a new dentable
//! collider, or a mesh changed outside the backend) makes it upload every known target again;
//! otherwise a batch uploads nothing but its jobs and reads back the dented targets. The refine
//! stage runs on the host first ([`refine_targets`]); a target it refines is uploaded again
//! (with every other, as for a changed mesh).

use std::collections::HashMap;
use std::hash::Hash;

use super::{GpuBatchError, GpuContext, GpuDenter};
use crate::dent::{
    BatchError, BatchOutcome, DentBackend, DentError, DentJob, DentReport, VolumeMode, moved_vertices, refine_targets,
};
use crate::mesh::TriMesh;

/// Batches on a GPU, targets resident there, keyed by the caller's ids.
pub struct GpuBackend<K> {
    context: GpuContext,
    denter: Option<GpuDenter>,
    slots: HashMap<K, usize>,
    meshes: Vec<TriMesh>,
}

impl<K> std::fmt::Debug for GpuBackend<K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuBackend").field("resident", &self.meshes.len()).finish()
    }
}

impl<K: Copy + Eq + Hash> GpuBackend<K> {
    /// A backend on `context` (e.g. [`shared_context`](super::shared_context), or an
    /// application's device through [`GpuContext::from_device`]); nothing resident yet.
    pub fn new(context: &GpuContext) -> Self {
        Self { context: context.clone(), denter: None, slots: HashMap::new(), meshes: Vec::new() }
    }

    /// Forgets `key` (its mesh leaves the device at the next upload).
    pub fn forget(&mut self, key: K) {
        if let Some(slot) = self.slots.remove(&key) {
            self.meshes.remove(slot);
            self.slots.values_mut().filter(|s| **s > slot).for_each(|s| *s -= 1);
            self.denter = None;
        }
    }

    /// Makes `meshes` (current meshes; `keys[i]` the id of `meshes[i]`) resident now, uploading once, so that their
    /// first batch uploads nothing but its jobs.
    ///
    /// # Errors
    /// [`DentError::Backend`] when the upload fails.
    pub fn make_resident(&mut self, keys: &[K], meshes: &[TriMesh]) -> Result<(), DentError> {
        self.resident(keys, &meshes.iter().collect::<Vec<_>>()).map(|_| ())
    }

    /// Makes every target of the batch resident with its current mesh; the slot of each.
    fn resident(&mut self, keys: &[K], meshes: &[&TriMesh]) -> Result<Vec<usize>, DentError> {
        // A mesh whose faces changed (refined) is resident again even if its positions match.
        let same = |old: &TriMesh, new: &TriMesh| old.positions() == new.positions() && old.faces() == new.faces();
        let mut stale = self.denter.is_none();
        for (key, &mesh) in keys.iter().zip(meshes) {
            match self.slots.get(key) {
                Some(&slot) if same(&self.meshes[slot], mesh) => {}
                Some(&slot) => {
                    self.meshes[slot] = mesh.clone();
                    stale = true;
                }
                None => {
                    self.slots.insert(*key, self.meshes.len());
                    self.meshes.push(mesh.clone());
                    stale = true;
                }
            }
        }
        if stale {
            self.denter = None;
            let denter = GpuDenter::new(&self.context, &self.meshes).map_err(|e| DentError::Backend(e.to_string()))?;
            self.denter = Some(denter);
        }
        Ok(keys.iter().map(|k| self.slots[k]).collect())
    }
}

impl<K: Copy + Eq + Hash> DentBackend<K> for GpuBackend<K> {
    fn dent_batch(
        &mut self,
        keys: &[K],
        targets: &mut [TriMesh],
        jobs: &[DentJob<'_>],
    ) -> Result<BatchOutcome, BatchError> {
        // Stage 1 on the host: refine copies of the targets where their dents need it.
        let refined = refine_targets(targets, jobs)?;
        let current: Vec<&TriMesh> =
            targets.iter().zip(&refined.meshes).map(|(old, new)| new.as_ref().unwrap_or(old)).collect();
        let slots = self.resident(keys, &current).map_err(|error| BatchError { job: 0, error })?;
        let mut gpu_jobs = jobs.to_vec();
        for job in &mut gpu_jobs {
            job.target = slots[job.target];
        }
        let failed = |error: String| BatchError { job: 0, error: DentError::Backend(error) };
        let Some(denter) = self.denter.as_mut() else { return Err(failed("no resident targets".into())) };
        let infos = denter.dent_batch(&gpu_jobs).map_err(|e| match e {
            GpuBatchError::Job(job) => job,
            GpuBatchError::Gpu(e) => failed(e.to_string()),
        });
        let infos = match infos {
            Ok(infos) => infos,
            Err(e) => {
                // The device may hold a half-applied batch: upload again next time.
                self.denter = None;
                return Err(e);
            }
        };
        let reports = infos
            .iter()
            .zip(refined.reports)
            .zip(jobs)
            .map(|((i, refine), job)| DentReport {
                theta_deg: i.theta_deg,
                resolution: i.resolution,
                map_resolution: i.map_resolution,
                cell_size: i.cell_size,
                warnings: [refine.warnings.clone(), volume_warning(job)].concat(),
                ..refine
            })
            .collect();
        let mut dented = Vec::with_capacity(targets.len());
        for &slot in &slots {
            match denter.read_mesh(slot) {
                Ok(mesh) => dented.push(mesh),
                Err(e) => {
                    self.denter = None;
                    return Err(failed(e.to_string()));
                }
            }
        }
        let mut moved = Vec::with_capacity(targets.len());
        for ((mesh, new), &slot) in targets.iter_mut().zip(dented).zip(&slots) {
            // New vertices count as moved, as on the CPU.
            let mut list = moved_vertices(mesh.positions(), new.positions());
            list.extend(mesh.vertex_count() as u32..new.vertex_count() as u32);
            moved.push(list);
            self.meshes[slot] = new.clone();
            *mesh = new;
        }
        Ok(BatchOutcome { reports, moved, refined: refined.refinements })
    }
}

/// The GPU kernels do not restore volume ([`VolumeMode::Preserve`] is a CPU stage): say so.
fn volume_warning(job: &DentJob<'_>) -> Vec<String> {
    if job.params.volume == VolumeMode::Preserve {
        let message = "volume preservation runs on the CPU backend only: this GPU dent does not restore volume";
        log::warn!("{message}");
        return vec![message.to_owned()];
    }
    Vec::new()
}
