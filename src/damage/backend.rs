//! Where a batch of dents runs: the [`DentBackend`] trait and the all-cores [`CpuBackend`]
//! (the GPU's is `gpu::GpuBackend`).

use crate::dent::{BatchError, BatchOutcome, DentJob, dent_batch_tracked};
use crate::mesh::TriMesh;

/// Where a batch of dents runs: dents `meshes` (copies of the targets' meshes; `keys[i]` is the
/// caller's id of `meshes[i]`) by `jobs` (whose `target` indexes `meshes`) in place.
pub trait DentBackend<K> {
    /// Runs the batch.
    ///
    /// # Errors
    /// [`BatchError`] naming the first bad job; the meshes are unchanged then.
    fn dent_batch(
        &mut self,
        keys: &[K],
        meshes: &mut [TriMesh],
        jobs: &[DentJob<'_>],
    ) -> Result<BatchOutcome, BatchError>;
}

/// Batches on all CPU cores ([`dent_batch_tracked`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct CpuBackend;

impl<K> DentBackend<K> for CpuBackend {
    fn dent_batch(
        &mut self,
        _: &[K],
        meshes: &mut [TriMesh],
        jobs: &[DentJob<'_>],
    ) -> Result<BatchOutcome, BatchError> {
        dent_batch_tracked(meshes, jobs)
    }
}
