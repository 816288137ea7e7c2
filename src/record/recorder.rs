//! Recording the dents a user of the engine-neutral damage API applies: after each
//! [`Damage::plan`](crate::damage::Damage::plan), before the plan's meshes replace the targets',
//! [`DamageRecorder::record`] notes every tracked body's new dents (as a mesh edit, as impacts,
//! or both), and [`DamageRecorder::file`] gives the damage file.

use std::hash::Hash;

use glam::Vec3;

use super::records::{DamageRecord, DentBatch, FracturePiece, FractureRecord, ImpactDent, ProjectileRef};
use super::{BodyDamage, DamageFile, MeshStamp, RecordError, hex64};
use crate::damage::{AppliedDent, DamagePlan, DentTargets, Hit};
use crate::dent::{Attenuation, DentParams};
use crate::mesh::{MeshEdit, TriMesh, content_hash};

/// Which forms of each dent batch the recorder keeps (at least one).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RecordForms {
    /// The batch's result as a mesh edit: exact whatever computed it (a GPU too), about 13
    /// bytes per moved vertex.
    pub edits: bool,
    /// Each dent as its impact, parameters and projectile reference: about 200 bytes a dent,
    /// recomputed on replay (bit-identical when it was computed on the CPU).
    pub impacts: bool,
}

impl RecordForms {
    /// Edits only.
    pub const EDITS: Self = Self { edits: true, impacts: false };
    /// Impacts only (what a multiplayer client is sent).
    pub const IMPACTS: Self = Self { edits: false, impacts: true };
    /// Both (a replay can check one against the other).
    pub const BOTH: Self = Self { edits: true, impacts: true };
}

/// Tracked bodies' damage, keyed by the caller's ids.
#[derive(Debug, Clone)]
pub struct DamageRecorder<K> {
    forms: RecordForms,
    bodies: Vec<(K, BodyDamage)>,
    /// Built-in names of projectile meshes, by content hash.
    builtins: Vec<(u64, String)>,
}

impl<K: Copy + Eq + Hash + std::fmt::Debug> DamageRecorder<K> {
    /// No body tracked yet; `forms` with neither form set records edits.
    pub fn new(forms: RecordForms) -> Self {
        let forms = if forms.edits || forms.impacts { forms } else { RecordForms::EDITS };
        Self { forms, bodies: Vec::new(), builtins: Vec::new() }
    }

    /// Impact records of a projectile whose mesh is `mesh` name it as the built-in `name` too
    /// ([`mesh::builtin`](crate::mesh::builtin)), so that a replay finds it without being given
    /// the mesh.
    ///
    /// # Errors
    /// [`RecordError::NotRecordable`] when `name` is no built-in mesh or not this one.
    pub fn name_projectile(&mut self, mesh: &TriMesh, name: &str) -> Result<(), RecordError> {
        let hash = content_hash(mesh);
        let builtin = crate::mesh::builtin(name).map_err(|e| RecordError::NotRecordable(format!("{name:?}: {e}")))?;
        if content_hash(&builtin) != hash {
            return Err(RecordError::NotRecordable(format!("the mesh named {name:?}: it is not the built-in one")));
        }
        self.builtins.retain(|(h, _)| *h != hash);
        self.builtins.push((hash, name.to_owned()));
        Ok(())
    }

    /// Starts (or restarts) recording body `key`, called `name` in the file, whose mesh is now
    /// `base` (its own coordinates).
    pub fn track(&mut self, key: K, name: impl Into<String>, base: &TriMesh) {
        let body = BodyDamage::new(name, base);
        match self.bodies.iter_mut().find(|(k, _)| *k == key) {
            Some(entry) => entry.1 = body,
            None => self.bodies.push((key, body)),
        }
    }

    /// Continues recording body `key` from `body`, damage recorded before (a restored save):
    /// the body's mesh is now `body`'s final mesh.
    pub fn resume(&mut self, key: K, body: BodyDamage) {
        match self.bodies.iter_mut().find(|(k, _)| *k == key) {
            Some(entry) => entry.1 = body,
            None => self.bodies.push((key, body)),
        }
    }

    /// Records `plan` (made by [`Damage::plan`](crate::damage::Damage::plan) from `hits` on
    /// `targets`), before the caller applies it: `targets` must still hold the meshes the plan
    /// started from. Untracked bodies are skipped. A tracked body that broke records its
    /// fracture (its rest is its mesh from then on; its pieces are named `<name>/piece<index>`);
    /// one the pattern took whole stops being tracked.
    ///
    /// # Errors
    /// [`RecordError::Tampered`] when a tracked body's mesh is not the one the recorder last
    /// saw (changed outside the plans recorded), [`RecordError::NotRecordable`] for impacts
    /// with a custom falloff; nothing is recorded then.
    pub fn record<T: DentTargets<K>>(
        &mut self,
        targets: &T,
        hits: &[Hit<'_, K>],
        plan: &DamagePlan<K>,
    ) -> Result<(), RecordError> {
        let mut staged = Vec::new();
        for dented in &plan.targets {
            let Some(slot) = self.bodies.iter().position(|(k, _)| *k == dented.key) else { continue };
            let body = &self.bodies[slot].1;
            let view =
                targets.target(dented.key).ok_or_else(|| RecordError::UnknownBody(format!("{:?}", dented.key)))?;
            let before = MeshStamp::of(view.mesh);
            if before != body.final_mesh {
                return Err(RecordError::Tampered {
                    body: body.name.clone(),
                    record: body.records.len(),
                    reason: format!(
                        "its mesh ({}) is not the one last recorded ({}): was it changed outside the plans recorded?",
                        hex64(before.hash),
                        hex64(body.final_mesh.hash)
                    ),
                });
            }
            let dents: Vec<&AppliedDent<K>> = plan.dents.iter().filter(|d| d.target == dented.key).collect();
            let edit = if self.forms.edits { Some(MeshEdit::between(view.mesh, &dented.mesh)?) } else { None };
            let impacts =
                if self.forms.impacts { impact_dents(targets, hits, &dents, &self.builtins)? } else { Vec::new() };
            let after = MeshStamp::of(&dented.mesh);
            let refinement = (!dented.refinement.is_empty()).then(|| dented.refinement.clone());
            let batch = DentBatch { dents: dents.len() as u32, impacts, edit, after: after.hash, refinement };
            staged.push((slot, batch, after));
        }
        let mut ended = Vec::new();
        for (slot, batch, after) in staged {
            let body = &mut self.bodies[slot].1;
            body.records.push(DamageRecord::Dents(batch));
            body.final_mesh = after;
        }
        for fracture in &plan.fractures {
            let Some(slot) = self.bodies.iter().position(|(k, _)| *k == fracture.body) else { continue };
            let body = &mut self.bodies[slot].1;
            let Some(rest) = &fracture.rest else {
                // No mesh is left to record: the body's damage ends with its last dents.
                log::warn!("{}: the fracture pattern took the whole body; its record ends here", body.name);
                ended.push(slot);
                continue;
            };
            let pieces = fracture
                .pieces
                .iter()
                .map(|piece| FracturePiece {
                    name: format!("{}/piece{}", body.name, piece.id.index),
                    index: piece.id.index,
                    shift: Vec3::ZERO,
                    hash: content_hash(&piece.mesh),
                })
                .collect();
            let after = MeshStamp::of(rest);
            body.records.push(DamageRecord::Fracture(FractureRecord {
                frame: plan.step,
                fracture: fracture.record,
                to_model: Vec3::ZERO,
                rest_shift: Vec3::ZERO,
                pieces,
                after: after.hash,
            }));
            body.final_mesh = after;
        }
        for slot in ended.into_iter().rev() {
            self.bodies.remove(slot);
        }
        Ok(())
    }

    /// Body `key`'s damage so far.
    pub fn body(&self, key: K) -> Option<&BodyDamage> {
        self.bodies.iter().find(|(k, _)| *k == key).map(|(_, b)| b)
    }

    /// Every tracked body's damage, in the order they were first tracked.
    pub fn file(&self) -> DamageFile {
        DamageFile { scene: None, bodies: self.bodies.iter().map(|(_, b)| b.clone()).collect() }
    }
}

/// `dents` (of one target) as impact records: each matched to the hit it came from.
fn impact_dents<K: Copy + Eq + std::fmt::Debug, T: DentTargets<K>>(
    targets: &T,
    hits: &[Hit<'_, K>],
    dents: &[&AppliedDent<K>],
    builtins: &[(u64, String)],
) -> Result<Vec<ImpactDent>, RecordError> {
    let mut used = vec![false; hits.len()];
    let mut out = Vec::with_capacity(dents.len());
    for d in dents {
        let found = hits.iter().enumerate().position(|(k, h)| {
            !used[k] && h.target == d.target && h.projectile == d.projectile && h.impact == d.impact
        });
        let Some(k) = found else {
            return Err(RecordError::UnknownBody(format!(
                "no hit made the dent of {:?} by {:?}",
                d.target, d.projectile
            )));
        };
        used[k] = true;
        let hit = &hits[k];
        let view = targets.target(d.target).ok_or_else(|| RecordError::UnknownBody(format!("{:?}", d.target)))?;
        if matches!(view.settings.params.attenuation, Attenuation::Custom(_)) {
            return Err(RecordError::NotRecordable(format!(
                "the dent of {:?}: a custom falloff function is not data (record edits instead)",
                d.target
            )));
        }
        let hash = content_hash(hit.projectile_surface.mesh);
        let builtin = builtins.iter().find(|(h, _)| *h == hash).map(|(_, name)| name.clone());
        out.push(ImpactDent {
            impact: d.impact,
            target_to_world: view.to_world,
            projectile: ProjectileRef { hash, builtin, to_world: hit.projectile_surface.to_world },
            reach: view.settings.projectile_reach(view.radius, d.dent_distance),
            params: DentParams { dent_distance: d.dent_distance, ..view.settings.params.clone() },
            progressive: view.settings.progressive,
        });
    }
    Ok(out)
}
