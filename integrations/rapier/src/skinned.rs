//! The skinned parent mesh of a bendable body from the Rapier poses: every piece's body frame
//! is the rest frame, so a piece's pose is its bone's skinning transform (rest → world); linear
//! blend skinning over the body's weights on the CPU (dentbend's `skin` twin of the GPU
//! kernel).

use dentbend::mesh::TriMesh;
use glam::Affine3A;

use crate::{AdapterError, Bendable, PhysicsWorld};

impl Bendable {
    /// Each bone's skinning transform (rest frame → world): its piece's Rapier pose.
    ///
    /// # Errors
    /// [`AdapterError::UnknownBody`] when a piece's body was removed.
    pub fn bone_transforms(&self, world: &PhysicsWorld) -> Result<Vec<Affine3A>, AdapterError> {
        let mut out = vec![Affine3A::IDENTITY; self.rig.skeleton().len()];
        for p in &self.pieces {
            let rb = world.bodies.get(p.body).ok_or(AdapterError::UnknownBody(p.body))?;
            out[p.bone] = crate::to_affine(rb.position());
        }
        Ok(out)
    }

    /// The parent mesh skinned to the pieces' current poses (world, m), linear blend over the
    /// skinning weights on the CPU.
    ///
    /// # Errors
    /// As [`bone_transforms`](Self::bone_transforms), or a skinning failure.
    pub fn skinned_mesh(&self, world: &PhysicsWorld) -> Result<TriMesh, AdapterError> {
        self.skin_with(&self.bone_transforms(world)?)
    }

    /// The rest mesh skinned by `transforms` (one per bone, rest frame → world), m.
    pub(crate) fn skin_with(&self, transforms: &[Affine3A]) -> Result<TriMesh, AdapterError> {
        self.rig.skinned(transforms).map_err(crate::bendable::rig_error)
    }
}
