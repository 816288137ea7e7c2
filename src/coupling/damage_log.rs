//! Recording a [`Simulation`]'s damage as data: every body shown (the world's bodies but
//! sub-bodies and cluster stand-ins, then the bending bodies), each dentable body's dents per
//! step as mesh edits (exact on the CPU and the GPU alike), and each bending body's dents on
//! its rest mesh, bends, rest rotations, splits and final skinned surface.
//!
//! A bending body's final surface is recorded as a mesh edit of its rest mesh (every vertex,
//! about 13 bytes each), not rebuilt from its joints: rebuilding it would need the skinning
//! influences that splits recompute (32 bytes a vertex, more than the edit) or the whole
//! geodesic weight solve, and a GPU-skinned surface need not match the CPU twin bit for bit.

use super::Simulation;
use crate::mesh::{MeshEdit, TriMesh, content_hash};
use crate::record::{
    BodyDamage, BoneSplit, DamageFile, DamageRecord, DentBatch, JointBend, JointRest, MeshStamp, RecordError, SceneRef,
};
use crate::sim::SimError;

/// One body being recorded.
#[derive(Debug, Clone)]
struct Logged {
    /// World index of a shown world body; `None` for a bending body (by its index in
    /// [`Bending::bodies`](super::Bending::bodies), the entry's position among them).
    index: Option<usize>,
    damage: BodyDamage,
    /// The mesh as last recorded, for bodies that dent.
    last: Option<TriMesh>,
}

/// A simulation's damage so far; call [`after_step`](Self::after_step) after every step and
/// [`finish`](Self::finish) at the end.
#[derive(Debug, Clone)]
pub struct DamageLog {
    bodies: Vec<Logged>,
    /// Dent records of the simulation already seen.
    seen: usize,
}

impl DamageLog {
    /// Starts recording `sim` as it is now (its meshes are the bases).
    pub fn new(sim: &Simulation) -> Self {
        let world = sim.world();
        let owners = sim.bending().owners(world.bodies().len());
        let mut bodies: Vec<Logged> = (world.bodies().iter().enumerate())
            .filter(|(k, b)| owners[*k].is_none() && !b.is_cluster_proxy())
            .map(|(k, b)| Logged {
                index: Some(k),
                damage: BodyDamage::new(b.name.clone(), b.mesh()),
                last: b.dent.is_some().then(|| b.mesh().clone()),
            })
            .collect();
        bodies.extend(sim.bending().bodies().iter().map(|b| Logged {
            index: None,
            damage: BodyDamage::new(b.name(), b.rest_mesh()),
            last: Some(b.rest_mesh().clone()),
        }));
        Self { bodies, seen: sim.dents().len() }
    }

    /// Records the dents of the steps since the last call: one batch per body and step that
    /// dented it (the step's dents on a body are one batch).
    ///
    /// # Errors
    /// [`RecordError::Mesh`] if a dented mesh lost vertices or faces (a bug).
    pub fn after_step(&mut self, sim: &Simulation) -> Result<(), RecordError> {
        let fresh = &sim.dents()[self.seen..];
        self.seen = sim.dents().len();
        if fresh.is_empty() {
            return Ok(());
        }
        let mut bending = sim.bending().bodies().iter();
        for logged in &mut self.bodies {
            let now = match logged.index {
                Some(k) => sim.world().bodies()[k].mesh(),
                None => bending.next().expect("one entry per bending body").rest_mesh(),
            };
            let Some(last) = logged.last.as_mut() else { continue };
            let dents = fresh.iter().filter(|d| d.target == logged.damage.name).count() as u32;
            if dents == 0 {
                continue;
            }
            let edit = MeshEdit::between(last, now)?;
            let after = content_hash(now);
            logged.damage.records.push(DamageRecord::Dents(DentBatch {
                dents,
                impacts: Vec::new(),
                edit: Some(edit),
                after,
            }));
            logged.damage.final_mesh = MeshStamp::of(now);
            *last = now.clone();
        }
        Ok(())
    }

    /// The damage file: every body's records, its final pose (world bodies) or final skinned
    /// surface (bending bodies, skinned now unless the step did), under `scene`.
    ///
    /// # Errors
    /// As [`Simulation::skinned_meshes`]; [`RecordError`] as [`SimError::Invalid`].
    pub fn finish(&self, sim: &mut Simulation, scene: SceneRef) -> Result<DamageFile, SimError> {
        let skinned = sim.skinned_meshes()?;
        let world = sim.world();
        let owners = sim.bending().owners(world.bodies().len());
        let mut bending = sim.bending().bodies().iter().enumerate().zip(skinned);
        let mut out = Vec::with_capacity(self.bodies.len());
        for logged in &self.bodies {
            let mut damage = logged.damage.clone();
            if let Some(k) = logged.index {
                damage.pose = Some(world.bodies()[k].transform());
                out.push(damage);
                continue;
            }
            let ((which, body), (_, surface, _)) = bending.next().expect("one entry per bending body");
            let mine = |index: usize| owners.get(index).copied().flatten().is_some_and(|(b, _)| b == which);
            for bend in sim.bending().bends() {
                let joint = &world.joints()[bend.joint];
                if mine(joint.a()) || mine(joint.b()) {
                    let record = JointBend { frame: bend.frame, joint: bend.joint as u32, angle: bend.angle };
                    damage.records.push(DamageRecord::Bend(record));
                }
            }
            for split in sim.bending().joints().iter().filter(|j| j.body == damage.name) {
                damage.records.push(DamageRecord::Split(BoneSplit {
                    frame: split.frame,
                    joint: split.joint as u32,
                    position: split.position,
                    rest_position: split.rest_position,
                }));
            }
            for (k, joint) in world.joints().iter().enumerate().filter(|(_, j)| mine(j.a()) && mine(j.b())) {
                damage.records.push(DamageRecord::Rest(JointRest { joint: k as u32, rest: joint.target() }));
            }
            let invalid = |e: RecordError| SimError::Invalid {
                what: format!("damage record of \"{}\"", damage.name),
                value: e.to_string(),
                reason: "could not be made",
            };
            let edit = MeshEdit::between(body.rest_mesh(), &surface).map_err(|e| invalid(e.into()))?;
            damage.records.push(DamageRecord::Skinned { edit, after: content_hash(&surface) });
            damage.final_mesh = MeshStamp::of(&surface);
            out.push(damage);
        }
        Ok(DamageFile { scene: Some(scene), bodies: out })
    }
}
