//! Recording a [`Simulation`]'s damage as data: every body shown (the world's bodies but
//! sub-bodies and cluster stand-ins, then the bending bodies), each dentable body's dents per
//! step as mesh edits (exact on the CPU and the GPU alike), and each bending body's dents on
//! its rest mesh, bends, rest rotations, splits and final skinned surface.
//!
//! A fracture is recorded on the body that broke (the dents of its step first, on the mesh it
//! broke with), and each piece that became a body is listed as a body of its own, after the
//! world bodies before it, its base the piece's mesh as the fracture made it.
//!
//! A bending body's final surface is recorded as a mesh edit of its rest mesh (every vertex,
//! about 13 bytes each), not rebuilt from its joints: rebuilding it would need the skinning
//! influences that splits recompute (32 bytes a vertex, more than the edit) or the whole
//! geodesic weight solve, and a GPU-skinned surface need not match the CPU twin bit for bit.

use super::Simulation;
use crate::sim::SimError;
use dentbend::mesh::{MeshEdit, TriMesh, content_hash};
use dentbend::record::{
    BodyDamage, BoneSplit, DamageFile, DamageRecord, DentBatch, JointBend, JointRest, MeshStamp, RecordError, SceneRef,
};

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
    /// Fractures of the simulation already seen.
    fractures_seen: usize,
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
        Self { bodies, seen: sim.dents().len(), fractures_seen: sim.fractures().len() }
    }

    /// Records the dents and fractures of the steps since the last call: one batch per body and
    /// step that dented it (the step's dents on a body are one batch), each fracture after the
    /// dents of its step, and the pieces of each fracture as new bodies. Call it after every
    /// step: a body's dents and fracture of one step are told apart by the fracture's
    /// [`mesh_before`](super::FractureEvent::mesh_before).
    ///
    /// # Errors
    /// [`RecordError::Mesh`] if a dented mesh lost vertices or faces (a bug);
    /// [`RecordError::UnknownBody`] for a piece the world does not hold.
    pub fn after_step(&mut self, sim: &Simulation) -> Result<(), RecordError> {
        let fresh = &sim.dents()[self.seen..];
        self.seen = sim.dents().len();
        let fractures = &sim.fractures()[self.fractures_seen..];
        self.fractures_seen = sim.fractures().len();
        if fresh.is_empty() && fractures.is_empty() {
            return Ok(());
        }
        let mut bending = sim.bending().bodies().iter();
        let mut pieces = Vec::new();
        for logged in &mut self.bodies {
            let now = match logged.index {
                Some(k) => sim.world().bodies()[k].mesh(),
                None => bending.next().expect("one entry per bending body").rest_mesh(),
            };
            let broke: Vec<_> = fractures.iter().filter(|f| f.body == logged.damage.name).collect();
            let dents = fresh.iter().filter(|d| d.target == logged.damage.name).count() as u32;
            if let Some(last) = logged.last.as_mut()
                && dents > 0
            {
                // The step's dents came before its fracture: they end on the mesh it broke with.
                let dented = broke.first().map_or(now, |f| &*f.mesh_before);
                let edit = MeshEdit::between(last, dented)?;
                let after = content_hash(dented);
                logged.damage.records.push(DamageRecord::Dents(DentBatch {
                    dents,
                    impacts: Vec::new(),
                    edit: Some(edit),
                    after,
                    refinement: None,
                }));
                logged.damage.final_mesh = MeshStamp::of(dented);
                *last = dented.clone();
            }
            for fracture in broke {
                logged.damage.records.push(DamageRecord::Fracture(fracture.damage.clone()));
                pieces.extend(fracture.damage.pieces.iter().map(|p| p.name.clone()));
            }
            if fractures.iter().any(|f| f.body == logged.damage.name) {
                logged.damage.final_mesh = MeshStamp::of(now);
                if let Some(last) = logged.last.as_mut() {
                    *last = now.clone();
                }
            }
        }
        // Pieces are world bodies added last: listed after the world bodies, before the
        // bending bodies.
        let at = self.bodies.iter().position(|b| b.index.is_none()).unwrap_or(self.bodies.len());
        let world = sim.world();
        let added: Vec<Logged> = pieces
            .into_iter()
            .map(|name| {
                let k = world.find(&name).ok_or_else(|| RecordError::UnknownBody(name.clone()))?;
                let body = &world.bodies()[k];
                Ok(Logged {
                    index: Some(k),
                    damage: BodyDamage::new(name, body.mesh()),
                    last: body.dent.is_some().then(|| body.mesh().clone()),
                })
            })
            .collect::<Result<_, RecordError>>()?;
        self.bodies.splice(at..at, added);
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
