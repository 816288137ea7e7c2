//! The resident targets of a [`GpuDenter`] as a set: the host's copy of each, and adding,
//! replacing and removing targets after the denter is built.

use super::GpuDenter;
use super::resident::{Resident, ResidentBuffers};
use crate::gpu::GpuError;
use crate::mesh::TriMesh;

impl GpuDenter {
    /// The host's copy of target `target`: positions bit for bit the device's, its triangles, and
    /// normals as the CPU pipeline keeps them. After [`record_batch`](Self::record_batch) dented
    /// it, the copy is first read back from the device (once).
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] for an unknown target; device errors of the read-back.
    pub fn mesh(&mut self, target: usize) -> Result<&TriMesh, GpuError> {
        self.check_target(target)?;
        self.catch_up()?;
        Ok(&self.targets[target].mesh)
    }

    /// Makes `mesh` resident as a new target (the last index), laying every target out afresh
    /// (so [`vertex_buffer`](Self::vertex_buffer) is a new buffer afterwards).
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] when the targets would no longer fit the device's buffers (nothing
    /// changes then); device errors.
    pub fn add_target(&mut self, mesh: TriMesh) -> Result<usize, GpuError> {
        self.catch_up()?;
        self.targets.push(Resident::new(mesh));
        if let Err(error) = self.lay_out() {
            self.targets.pop();
            return Err(error);
        }
        Ok(self.targets.len() - 1)
    }

    /// Replaces target `target` by `mesh` (a mesh changed outside the denter, any number of
    /// vertices and triangles): written into its slice when it fits, else every target is laid
    /// out afresh.
    ///
    /// # Errors
    /// As [`add_target`](Self::add_target), and [`GpuError::OverLimit`] for an unknown target.
    pub fn replace_target(&mut self, target: usize, mesh: TriMesh) -> Result<(), GpuError> {
        self.check_target(target)?;
        self.catch_up()?;
        let resident = &self.targets[target];
        if resident.fits(&mesh) {
            let placed = resident.placed_as(mesh);
            self.buffers.upload(&self.context, &placed)?;
            self.targets[target] = placed;
            return Ok(());
        }
        let old = std::mem::replace(&mut self.targets[target], Resident::new(mesh));
        self.lay_out().inspect_err(|_| self.targets[target] = old)
    }

    /// Removes target `target` (later targets move down one index), laying the others out
    /// afresh; returns the host's copy of it.
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] for an unknown target; device errors (nothing changes then).
    pub fn remove_target(&mut self, target: usize) -> Result<TriMesh, GpuError> {
        self.check_target(target)?;
        self.catch_up()?;
        let removed = self.targets.remove(target);
        if let Err(error) = self.lay_out() {
            // The old layout still holds every target where its offsets say.
            self.targets.insert(target, removed);
            return Err(error);
        }
        Ok(removed.mesh)
    }

    /// Lays every target out afresh in new buffers (each target's offsets set, its host copy
    /// uploaded).
    ///
    /// # Errors
    /// As [`ResidentBuffers::lay_out`]; the old buffers stay then, and the targets' offsets
    /// with them.
    pub(super) fn lay_out(&mut self) -> Result<(), GpuError> {
        self.buffers = ResidentBuffers::lay_out(&self.context, &mut self.targets, self.usage)?;
        Ok(())
    }

    /// Fails for a target index past the last.
    pub(super) fn check_target(&self, target: usize) -> Result<(), GpuError> {
        if target >= self.targets.len() {
            let limit = self.targets.len() as u64;
            return Err(GpuError::OverLimit { what: "target index".into(), needed: target as u64, limit });
        }
        Ok(())
    }
}
