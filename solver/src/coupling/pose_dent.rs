//! Denting a bending body in its current pose (paper §4, last paragraph): skin the rest mesh to
//! the pose, dent the skinned mesh like a plain body's, map each vertex's displacement back to
//! the rest pose through the inverse of its blended linear part, and refit the sub-bodies whose
//! vertices moved.
//!
//! What is kept: the skinning weights (per vertex, so they move with the dented material, as a
//! texture would), the level set and the sub-bodies' cells and mass properties. A dent is
//! plastic flow, not loss of material: the mass stays, and the level set (cells of a few
//! centimetres) would change by less than a cell for dents of a few millimetres; recomputing it
//! and the weights (tens of ms) for every dent would buy nothing the next split or skinning could
//! use. What changes: the rest mesh, and the open sub-mesh and convex-hull collider of every
//! bone owning a moved vertex.

use glam::Affine3A;

use super::ArticulatedBody;
use crate::sim::{DecidedDent, DentSettings, RigidBody, SimError, World};
use dentbend::dent::{LocalContact, Refine, Surface, dent_batch};
use dentbend::mesh::TriMesh;

/// A dent of a bending body computed in its current pose, not yet applied
/// ([`ArticulatedBody::apply_pose_dent`]).
#[derive(Debug, Clone)]
pub struct PoseDent {
    /// The rest mesh with the dent mapped back, model frame, m.
    pub rest_mesh: TriMesh,
    /// The rest mesh skinned to the pose before the dent, world, m.
    pub skinned: TriMesh,
    /// The same, dented: skinning [`rest_mesh`](Self::rest_mesh) to the pose gives it back.
    pub dented: TriMesh,
    /// Rest vertices whose position changed (against the body's rest mesh now), ascending.
    pub moved: Vec<usize>,
    /// Bones owning a moved vertex (their sub-bodies change), ascending.
    pub bones: Vec<usize>,
    /// Indices of the dents applied, ascending (a dent whose projectile has nothing near its
    /// impact is left out, as the [`Denter`](crate::sim::Denter) leaves it out).
    pub applied: Vec<usize>,
    /// World body index and new mesh (body coordinates) of each of those bones.
    pub(crate) sub_meshes: SubMeshes,
}

/// New sub-body meshes: (world body index, mesh in its body coordinates).
type SubMeshes = Vec<(usize, TriMesh)>;

impl PoseDent {
    /// Dissolves the clusters holding the sub-bodies this dent refits: a cluster's compound
    /// collider holds its members' old shapes.
    ///
    /// # Errors
    /// As [`World::uncondense`].
    pub(crate) fn uncondense_refitted(&self, world: &mut World) -> Result<(), SimError> {
        for (index, _) in &self.sub_meshes {
            if let Some(cluster) = world.cluster_of(*index) {
                world.uncondense(cluster)?;
            }
        }
        Ok(())
    }
}

impl ArticulatedBody {
    /// How the body dents, `None` when it does not.
    pub fn dent_settings(&self) -> Option<&DentSettings> {
        self.dent.as_ref()
    }

    /// Dents `base` (a mesh with the rest mesh's vertices and faces: the rest mesh itself, or a
    /// progressive dent's pre-dent rest mesh) in the pose of `world` by `dents`: impacts in world
    /// coordinates on this body's sub-bodies, each with the surface of its projectile.
    ///
    /// The skinned mesh is dented in the model frame of the first dent's bone, a rigid change of
    /// coordinates of the world (this bone's vertices keep their rest coordinates there, as a
    /// plain body's do in body coordinates). All dent maps come from the undented projectiles;
    /// the dents are applied in order, as [`dent_batch`] does for one target. A vertex's
    /// displacement Δ maps back as (Σₖ wₖ Rₖ)⁻¹ Δ, Rₖ the bones' rotations and wₖ the weights
    /// the skinning uses, so skinning the result gives the dented mesh back (linear blend
    /// skinning is linear in the rest position).
    ///
    /// The mesh is never refined here ([`Refine::Off`] whatever the settings say): skin weights,
    /// bones and sub-bodies belong to the rest mesh's vertices, so a bending body keeps its
    /// vertices and faces and takes the dent at its own resolution.
    ///
    /// # Errors
    /// [`SimError::Invalid`] when the body is not dentable, `dents` is empty or hits another
    /// body, or `base` does not match the rest mesh; [`SimError::Dent`] from the dent pipeline;
    /// [`SimError::BadShape`] if skinning or a sub-mesh fails. Nothing changes here.
    pub fn dent_in_pose(
        &self,
        world: &World,
        base: &TriMesh,
        dents: &[(DecidedDent, Surface<'_>)],
    ) -> Result<PoseDent, SimError> {
        let invalid = |what: &str, value: String, reason| SimError::Invalid {
            what: format!("bendable body \"{}\": {what}", self.name),
            value,
            reason,
        };
        let settings = self.dent.as_ref().ok_or_else(|| invalid("dent", "none".into(), "is not dentable"))?;
        let Some((first, _)) = dents.first() else { return Err(invalid("dents", "[]".into(), "must not be empty")) };
        if let Some((d, _)) = dents.iter().find(|(d, _)| self.bone_of(d.target).is_none()) {
            return Err(invalid("dent target", d.target.to_string(), "is not one of its sub-bodies"));
        }
        let rest_now = self.rig.rest();
        if base.vertex_count() != rest_now.vertex_count() || base.faces() != rest_now.faces() {
            return Err(invalid("dent base mesh", base.vertex_count().to_string(), "does not match the rest mesh"));
        }
        let transforms = self.bone_transforms(world)?;
        let reference = self.bone_of(first.target).unwrap_or(0);
        let to_world = transforms[reference];
        let to_reference = to_world.inverse();
        // The reference bone exactly the identity: its vertices keep their rest coordinates.
        let relative: Vec<Affine3A> = (0..transforms.len())
            .map(|k| if k == reference { Affine3A::IDENTITY } else { to_reference * transforms[k] })
            .collect();
        let skinned = self.skin_rest(base, &relative)?;
        let (lo, hi) = skinned.bounds();
        // Bounds how far from each impact the projectile can matter.
        let radius = 0.5 * lo.distance(hi);
        let locals: Vec<LocalContact> =
            dents.iter().map(|(d, surface)| LocalContact::new(&d.impact, to_world, surface.to_world)).collect();
        let projectiles: Vec<(usize, TriMesh)> = dents
            .iter()
            .enumerate()
            .filter_map(|(k, (d, surface))| {
                let reach = settings.projectile_reach(radius, d.dent_distance);
                Some((k, locals[k].crop(surface.mesh, reach)?))
            })
            .collect();
        let jobs: Vec<_> = projectiles
            .iter()
            .map(|(k, mesh)| {
                let d = &dents[*k].0;
                let mut job = locals[*k].job(mesh, &settings.params, d.dent_distance, 0);
                // Never refined: weights, bones and sub-bodies are per rest-mesh vertex.
                job.params.refine = Refine::Off;
                job
            })
            .collect();
        let mut dented = vec![skinned.clone()];
        if !jobs.is_empty() {
            dent_batch(&mut dented, &jobs).map_err(|e| SimError::Dent { body: self.name.clone(), error: e.error })?;
        }
        let dented = dented.pop().unwrap_or_else(|| skinned.clone());

        let bad = |e: dentbend::mesh::MeshError| SimError::BadShape { body: self.name.clone(), reason: e.to_string() };
        let displaced: Vec<u32> = (0..skinned.vertex_count() as u32)
            .filter(|&v| dented.positions()[v as usize] != skinned.positions()[v as usize])
            .collect();
        let rest_mesh = self
            .rig
            .rest_after_pose_dent(base, &skinned, &dented, &displaced, &relative)
            .map_err(|e| super::bendable::bend_error(&self.name, e))?;
        let moved: Vec<usize> =
            (0..rest_mesh.vertex_count()).filter(|&v| rest_mesh.positions()[v] != rest_now.positions()[v]).collect();
        let (bones, sub_meshes) = self.changed_sub_meshes(world, &rest_mesh, &moved)?;
        let to_world_mesh = |mut mesh: TriMesh| mesh.transform(to_world).map(|_| mesh).map_err(bad);
        Ok(PoseDent {
            rest_mesh,
            skinned: to_world_mesh(skinned)?,
            dented: to_world_mesh(dented)?,
            moved,
            bones,
            applied: projectiles.iter().map(|(k, _)| *k).collect(),
            sub_meshes,
        })
    }

    /// Applies `dent`: the new rest mesh, and the new meshes (and convex hulls) of the sub-bodies
    /// of the bones it lists. The sub-bodies keep their poses, velocities, sleep state, masses
    /// and joints.
    ///
    /// # Errors
    /// [`SimError::BadShape`] when a hull cannot be built, [`SimError::Invalid`] when `dent` was
    /// made for another body; the body and the world are unchanged then.
    pub fn apply_pose_dent(&mut self, world: &mut World, dent: PoseDent) -> Result<(), SimError> {
        dent.uncondense_refitted(world)?;
        let refitted = self.refit_sub_bodies(world, &dent)?;
        for (index, body) in refitted {
            world.bodies_mut()[index] = body;
        }
        self.set_rest_mesh(dent.rest_mesh)
    }

    /// Copies of the sub-bodies of `dent` with their new meshes and hulls (the world unchanged).
    pub(crate) fn refit_sub_bodies(&self, world: &World, dent: &PoseDent) -> Result<Vec<(usize, RigidBody)>, SimError> {
        if dent.rest_mesh.vertex_count() != self.rig.rest().vertex_count()
            || dent.sub_meshes.iter().any(|(index, _)| self.bone_of(*index).is_none())
        {
            return Err(SimError::Invalid {
                what: format!("bendable body \"{}\": pose dent", self.name),
                value: format!("{} vertices", dent.rest_mesh.vertex_count()),
                reason: "was made for another body",
            });
        }
        dent.sub_meshes
            .iter()
            .map(|(index, mesh)| {
                let mut body = world.bodies()[*index].clone();
                body.set_mesh(mesh.clone())?;
                Ok((*index, body))
            })
            .collect()
    }

    /// The bones owning a vertex of `moved` (ascending) and each one's world body index and
    /// sub-mesh of `rest` in that body's coordinates.
    fn changed_sub_meshes(
        &self,
        world: &World,
        rest: &TriMesh,
        moved: &[usize],
    ) -> Result<(Vec<usize>, SubMeshes), SimError> {
        let moved: Vec<u32> = moved.iter().map(|&v| v as u32).collect();
        let bones = self.rig.bones_owning(&moved);
        let fail = |e| super::bendable::bend_error(&self.name, e);
        let meshes = bones
            .iter()
            .map(|&bone| {
                let (mut mesh, _) = self.rig.sub_bodies().sub_mesh(rest, bone).map_err(fail)?;
                let index = self.bodies[bone];
                let offset = world.bodies()[index].model_offset;
                mesh.transform(Affine3A::from_translation(offset))
                    .map_err(|e| SimError::BadShape { body: self.name.clone(), reason: e.to_string() })?;
                Ok((index, mesh))
            })
            .collect::<Result<_, SimError>>()?;
        Ok((bones, meshes))
    }
}
