//! Which rest data a bending body's skin was built from: a revision number that changes whenever
//! its rest mesh (a dent) or its skinning influences (a split) change, so that a skinner holding
//! a copy of them (the GPU's resident meshes, [`GpuSkinner`](super::GpuSkinner)) knows when to
//! upload them again without comparing them.

use super::ArticulatedBody;
use super::articulated::next_rest_revision;
use crate::sim::SimError;
use dentbend::cpu::SkinInfluence;
use dentbend::mesh::TriMesh;

impl ArticulatedBody {
    /// The revision of the rest data the skin reads (rest mesh and influences): a new number
    /// after every change to either, equal for copies of one body made while their rest data
    /// agreed ([`Bending::add`](super::Bending::add) of the same body twice).
    pub fn rest_revision(&self) -> u64 {
        self.rest_revision
    }

    /// Replaces the rest mesh (a dent's: the same faces) and takes a new
    /// [`rest_revision`](Self::rest_revision).
    ///
    /// # Errors
    /// [`SimError::BadShape`] for a mesh with other faces; nothing changes then.
    pub(crate) fn set_rest_mesh(&mut self, mesh: TriMesh) -> Result<(), SimError> {
        self.rig.set_rest(mesh).map_err(|e| super::bendable::bend_error(&self.name, e))?;
        self.rest_revision = next_rest_revision();
        Ok(())
    }

    /// The four bone influences of every rest vertex, as the skinning kernel reads them.
    pub fn influences(&self) -> &[SkinInfluence] {
        self.rig.influences()
    }
}
