//! Dents on the GPU for the world-free damage API: a [`DentBackend`] keyed by the caller's ids,
//! a thin view of one [`GpuDenter`] whose targets stay resident on the device between steps.
//!
//! The denter runs every stage of [`DentParams`](crate::DentParams) (see
//! [`GpuDenter::dent_batch`]), so the same params give the same dent as on the CPU
//! ([`dent_batch_tracked`](crate::dent::dent_batch_tracked)). The backend only maps ids to
//! targets: a mesh the device has not seen (a new dentable collider) is added, one changed
//! outside the backend (compared with the denter's host copy) replaces its target, and after a
//! batch the caller's meshes take the denter's host copies of what it dented. Nothing is read
//! back but the vertices the kernels moved.

use std::collections::HashMap;
use std::hash::Hash;

use super::{GpuBatchError, GpuContext, GpuDenter};
use crate::damage::DentBackend;
use crate::dent::{BatchError, BatchOutcome, DentError, DentJob};
use crate::mesh::TriMesh;

/// Batches on a GPU, targets resident there, keyed by the caller's ids.
pub struct GpuBackend<K> {
    context: GpuContext,
    denter: Option<GpuDenter>,
    slots: HashMap<K, usize>,
}

impl<K> std::fmt::Debug for GpuBackend<K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuBackend").field("resident", &self.slots.len()).finish()
    }
}

impl<K: Copy + Eq + Hash> GpuBackend<K> {
    /// A backend on `context` (e.g. [`shared_context`](super::shared_context), or an
    /// application's device through [`GpuContext::from_device`]); nothing resident yet.
    pub fn new(context: &GpuContext) -> Self {
        Self { context: context.clone(), denter: None, slots: HashMap::new() }
    }

    /// Forgets `key` (its mesh leaves the device).
    pub fn forget(&mut self, key: K) {
        let Some(slot) = self.slots.remove(&key) else { return };
        if let Some(denter) = self.denter.as_mut()
            && denter.remove_target(slot).is_err()
        {
            // The device failed: start afresh at the next batch.
            self.denter = None;
            self.slots.clear();
            return;
        }
        self.slots.values_mut().filter(|s| **s > slot).for_each(|s| *s -= 1);
    }

    /// Makes `meshes` (current meshes; `keys[i]` the id of `meshes[i]`) resident now, uploading
    /// once, so that their first batch uploads nothing but its jobs.
    ///
    /// # Errors
    /// [`DentError::Backend`] when the upload fails.
    pub fn make_resident(&mut self, keys: &[K], meshes: &[TriMesh]) -> Result<(), DentError> {
        self.resident(keys, &meshes.iter().collect::<Vec<_>>()).map(|_| ())
    }

    /// Makes every target of the batch resident with its current mesh; the slot of each.
    fn resident(&mut self, keys: &[K], meshes: &[&TriMesh]) -> Result<Vec<usize>, DentError> {
        let backend = |e: super::GpuError| DentError::Backend(e.to_string());
        if self.denter.is_none() {
            let fresh: Vec<TriMesh> = meshes.iter().map(|&m| m.clone()).collect();
            self.denter = Some(GpuDenter::new(&self.context, &fresh).map_err(backend)?);
            self.slots = keys.iter().enumerate().map(|(slot, &key)| (key, slot)).collect();
        }
        let denter = self.denter.as_mut().expect("a denter was just made");
        for (key, &mesh) in keys.iter().zip(meshes) {
            match self.slots.get(key) {
                Some(&slot) => {
                    // A mesh changed outside the backend (its faces or positions) replaces its target.
                    let known = denter.mesh(slot).map_err(backend)?;
                    if known.positions() != mesh.positions() || known.faces() != mesh.faces() {
                        denter.replace_target(slot, mesh.clone()).map_err(backend)?;
                    }
                }
                None => {
                    let slot = denter.add_target(mesh.clone()).map_err(backend)?;
                    self.slots.insert(*key, slot);
                }
            }
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
        if keys.len() != targets.len() {
            let error = crate::dent::invalid("keys", keys.len(), "must hold one id per target mesh");
            return Err(BatchError { job: 0, error });
        }
        if let Some((job, bad)) = jobs.iter().enumerate().find(|(_, j)| j.target >= targets.len()) {
            let error = crate::dent::invalid("target", bad.target, "must index the batch's target list");
            return Err(BatchError { job, error });
        }
        let current: Vec<&TriMesh> = targets.iter().collect();
        let slots = self.resident(keys, &current).map_err(|error| BatchError { job: 0, error })?;
        let denter = self.denter.as_mut().expect("targets are resident");
        let resident_jobs: Vec<DentJob<'_>> =
            jobs.iter().map(|j| DentJob { target: slots[j.target], ..j.clone() }).collect();
        let outcome = match denter.dent_batch(&resident_jobs) {
            Ok(outcome) => outcome,
            Err(GpuBatchError::Job(error)) => return Err(error),
            Err(other) => {
                // The denter put every target back, unless the device failed under it: then
                // start afresh at the next batch.
                if matches!(other, GpuBatchError::Gpu(_)) {
                    self.denter = None;
                    self.slots.clear();
                }
                return Err(BatchError { job: 0, error: DentError::Backend(other.to_string()) });
            }
        };
        // Back in the caller's order: per target, its moved vertices, its refinement and its mesh.
        let mut moved = vec![Vec::new(); targets.len()];
        let mut refined = vec![Default::default(); targets.len()];
        let (mut all_moved, mut all_refined) = (outcome.moved, outcome.refined);
        for (t, &slot) in slots.iter().enumerate() {
            if !jobs.iter().any(|j| j.target == t) {
                continue;
            }
            moved[t] = std::mem::take(&mut all_moved[slot]);
            if let Some(r) = all_refined.get_mut(slot) {
                refined[t] = std::mem::take(r);
            }
            targets[t] =
                denter.mesh(slot).map_err(|e| BatchError { job: 0, error: DentError::Backend(e.to_string()) })?.clone();
        }
        Ok(BatchOutcome { reports: outcome.reports, moved, refined })
    }
}
