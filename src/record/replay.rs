//! Replaying a body's damage onto its base mesh: every record checked as it applies (each dent
//! batch's result hash, then the final mesh's), on a copy, so a refused file changes nothing.

use std::collections::HashMap;

use glam::{Affine3A, Vec3};

use super::records::{DamageRecord, DentBatch, FractureRecord, ImpactDent, ProjectileRef};
use super::{BodyDamage, MeshStamp, RecordError, hex64};
use crate::dent::{DentJob, LocalContact, dent_batch_tracked};
use crate::fracture::VertexOrigin;
use crate::mesh::{SplitVertex, TriMesh, builtin, content_hash, infer_splits};

/// Which form of a dent batch a replay uses when the file carries both.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DentForm {
    /// The recorded mesh edits (exact whatever computed them, GPU included); impacts where a
    /// batch has no edit.
    #[default]
    Edits,
    /// Recompute every dent from its impact on the CPU; edits where a batch has no impacts.
    Impacts,
}

/// The projectile meshes a replay of impact records may need, by content hash; built-in
/// meshes named by a record are found by name.
#[derive(Debug, Clone, Default)]
pub struct Projectiles {
    meshes: HashMap<u64, TriMesh>,
}

impl Projectiles {
    /// None yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds `mesh` (its own coordinates, as the damage API saw it); returns its content hash.
    pub fn insert(&mut self, mesh: TriMesh) -> u64 {
        let hash = content_hash(&mesh);
        self.meshes.insert(hash, mesh);
        hash
    }

    /// The mesh `projectile` names, checked against its hash.
    ///
    /// # Errors
    /// [`RecordError::MissingProjectile`].
    pub fn resolve(&self, projectile: &ProjectileRef) -> Result<std::borrow::Cow<'_, TriMesh>, RecordError> {
        if let Some(mesh) = self.meshes.get(&projectile.hash) {
            return Ok(std::borrow::Cow::Borrowed(mesh));
        }
        let named = projectile.builtin.as_deref().and_then(|name| builtin(name).ok());
        match named {
            Some(mesh) if content_hash(&mesh) == projectile.hash => Ok(std::borrow::Cow::Owned(mesh)),
            _ => Err(RecordError::MissingProjectile {
                hash: hex64(projectile.hash),
                builtin: projectile.builtin.clone(),
            }),
        }
    }
}

/// What one record of a replay did to the body's mesh, for a caller that carries more than
/// positions along (an engine's vertex attributes: UVs, colours, …).
#[derive(Debug, Clone, Copy)]
pub enum ReplayStep<'a> {
    /// A dent batch or a skinned edit turned `before` into `after`: the indices of `before`'s
    /// vertices and faces keep their meaning, and each vertex appended past them (a refinement)
    /// bisected an edge of the mesh as it was when it was made ([`splits`](Self::splits)).
    Edited {
        /// The mesh before the record.
        before: &'a TriMesh,
        /// The mesh after it.
        after: &'a TriMesh,
    },
    /// A fracture broke `before`; `rest` is the body's mesh from then on.
    Broke {
        /// The mesh that broke.
        before: &'a TriMesh,
        /// The rest.
        rest: &'a TriMesh,
        /// Where each of the rest's vertices lies on `before`.
        origins: &'a [VertexOrigin],
    },
}

impl ReplayStep<'_> {
    /// For an edit, the edge each vertex it appended bisected, in order (both parents have
    /// smaller indices; fraction 0.5), told from the meshes: the edges of `before`, each new
    /// vertex replacing the edge it halves, its parents the edge whose ends it reaches through
    /// the vertices appended after it and whose midpoint lies nearest to it. A vertex no
    /// refinement made (no such edge) names its first older neighbour twice, fraction 0.
    /// Empty for a fracture.
    pub fn splits(&self) -> Vec<SplitVertex> {
        match self {
            Self::Edited { before, after } => infer_splits(before, after),
            Self::Broke { .. } => Vec::new(),
        }
    }
}

/// A body's replayed damage: its final mesh and the bodies its fractures made.
#[derive(Debug, Clone)]
pub struct Replayed {
    /// The final mesh, the body's own coordinates.
    pub mesh: TriMesh,
    /// Each fracture's pieces that became bodies, in record order: name and mesh as the new
    /// body started (its own coordinates), the base its own damage replays from.
    pub pieces: Vec<(String, TriMesh)>,
}

/// `body`'s final mesh, rebuilt from `base` (its own coordinates, not posed), with the meshes of
/// the pieces its fractures made (bit for bit those the recording started their bodies from):
/// checks that `base` is the mesh the damage was recorded on, applies every record in order and
/// checks each dent batch's and fracture's result and the final mesh against their recorded
/// hashes.
///
/// # Errors
/// [`RecordError::BaseMismatch`], [`RecordError::Tampered`], [`RecordError::Fracture`] (a
/// fracture record the fracture module refuses), [`RecordError::Unsupported`] (a progressive
/// dent as an impact), [`RecordError::MissingProjectile`]; `base` is not touched.
pub fn replay_body(
    body: &BodyDamage,
    base: &TriMesh,
    form: DentForm,
    projectiles: &Projectiles,
) -> Result<Replayed, RecordError> {
    replay_body_traced(body, base, (form, projectiles), &mut |_| {})
}

/// As [`replay_body`], telling `each` what every record that changed the mesh did,
/// in order, as it applies (so a caller can carry vertex attributes along). A replay that fails
/// later may already have told some steps: keep what they built until it succeeds.
///
/// # Errors
/// As [`replay_body`].
pub fn replay_body_traced(
    body: &BodyDamage,
    base: &TriMesh,
    (form, projectiles): (DentForm, &Projectiles),
    each: &mut dyn FnMut(ReplayStep<'_>),
) -> Result<Replayed, RecordError> {
    let stamp = MeshStamp::of(base);
    if stamp != body.base {
        return Err(RecordError::BaseMismatch {
            body: body.name.clone(),
            expected: hex64(body.base.hash),
            found: hex64(stamp.hash),
        });
    }
    let tampered = |record: usize, reason: String| RecordError::Tampered { body: body.name.clone(), record, reason };
    let mut mesh = base.clone();
    let mut pieces = Vec::new();
    for (k, record) in body.records.iter().enumerate() {
        let after = match record {
            DamageRecord::Dents(batch) => {
                let after = replay_batch(body, k, batch, &mesh, form, projectiles)?;
                each(ReplayStep::Edited { before: &mesh, after: &after });
                mesh = after;
                batch.after
            }
            DamageRecord::Skinned { edit, after } => {
                let edited =
                    edit.apply(&mesh).map_err(|e| tampered(k, format!("the skinned edit does not apply: {e}")))?;
                each(ReplayStep::Edited { before: &mesh, after: &edited });
                mesh = edited;
                *after
            }
            DamageRecord::Fracture(f) => {
                let (rest, origins, made) = replay_fracture(body, k, f, &mesh)?;
                each(ReplayStep::Broke { before: &mesh, rest: &rest, origins: &origins });
                mesh = rest;
                pieces.extend(made);
                f.after
            }
            // Bends, rest rotations and splits are the joints' story; the mesh they give is
            // the skinned record's.
            DamageRecord::Bend(_) | DamageRecord::Rest(_) | DamageRecord::Split(_) => continue,
        };
        let found = content_hash(&mesh);
        if found != after {
            return Err(tampered(
                k,
                format!("the result hashes to {}, the record says {}", hex64(found), hex64(after)),
            ));
        }
    }
    let found = MeshStamp::of(&mesh);
    if found != body.final_mesh {
        return Err(tampered(
            body.records.len(),
            format!("the final mesh hashes to {}, the file says {}", hex64(found.hash), hex64(body.final_mesh.hash)),
        ));
    }
    Ok(Replayed { mesh, pieces })
}

/// A fracture's rest, where its vertices lie on the mesh that broke, and its named pieces.
type ReplayedFracture = (TriMesh, Vec<VertexOrigin>, Vec<(String, TriMesh)>);

/// One fracture of `mesh` (the body's own coordinates): the rest in the body's new coordinates
/// with its vertices' origins, and the named pieces in theirs.
fn replay_fracture(
    body: &BodyDamage,
    record: usize,
    f: &FractureRecord,
    mesh: &TriMesh,
) -> Result<ReplayedFracture, RecordError> {
    let tampered = |reason: String| RecordError::Tampered { body: body.name.clone(), record, reason };
    let moved = |mut mesh: TriMesh, by: Vec3, what: &str| {
        mesh.transform(Affine3A::from_translation(by)).map(|()| mesh).map_err(|e| tampered(format!("{what}: {e}")))
    };
    // As the simulation: the body's mesh always moved to the coordinates it broke in; the rest
    // and each piece moved to their bodies' coordinates only when their centre is not the origin.
    let model = moved(mesh.clone(), f.to_model, "moving the mesh to the coordinates it broke in")?;
    let outcome = crate::fracture::replay(&model, &f.fracture)
        .map_err(|error| RecordError::Fracture { body: body.name.clone(), record, error })?
        .ok_or_else(|| tampered("the fracture pattern misses the body".into()))?;
    let rest = outcome.rest.ok_or_else(|| tampered("the fracture pattern takes the whole body".into()))?;
    let shifted = |mesh: TriMesh, by: Vec3, what: &str| if by == Vec3::ZERO { Ok(mesh) } else { moved(mesh, by, what) };
    let rest = shifted(rest, f.rest_shift, "the rest's shift")?;
    let mut pieces = Vec::with_capacity(f.pieces.len());
    for p in &f.pieces {
        let piece = outcome.pieces.get(p.index as usize).ok_or_else(|| {
            tampered(format!("piece \"{}\" is number {}; the fracture made {}", p.name, p.index, outcome.pieces.len()))
        })?;
        let mesh = shifted(piece.mesh.clone(), p.shift, "a piece's shift")?;
        let found = content_hash(&mesh);
        if found != p.hash {
            return Err(tampered(format!(
                "piece \"{}\" hashes to {}, the record says {}",
                p.name,
                hex64(found),
                hex64(p.hash)
            )));
        }
        pieces.push((p.name.clone(), mesh));
    }
    Ok((rest, outcome.rest_origins, pieces))
}

/// One dent batch, in the form asked for (the other when the batch lacks it).
fn replay_batch(
    body: &BodyDamage,
    record: usize,
    batch: &DentBatch,
    mesh: &TriMesh,
    form: DentForm,
    projectiles: &Projectiles,
) -> Result<TriMesh, RecordError> {
    let tampered = |reason: String| RecordError::Tampered { body: body.name.clone(), record, reason };
    let has_impacts = !batch.impacts.is_empty();
    let use_impacts = match (form, &batch.edit) {
        (_, None) => true,
        (DentForm::Impacts, Some(_)) => has_impacts,
        (DentForm::Edits, Some(_)) => false,
    };
    if !use_impacts {
        let edit = batch.edit.as_ref().expect("an edit");
        return edit.apply(mesh).map_err(|e| tampered(format!("the dent edit does not apply: {e}")));
    }
    if batch.impacts.len() != batch.dents as usize {
        return Err(tampered(format!("{} dents but {} impacts and no edit", batch.dents, batch.impacts.len())));
    }
    if batch.impacts.iter().any(|d| d.progressive) {
        return Err(RecordError::Unsupported {
            body: body.name.clone(),
            record,
            what: "a progressive dent from its impact (record edits for progressive bodies)".into(),
        });
    }
    let cropped: Vec<TriMesh> = batch
        .impacts
        .iter()
        .map(|d| {
            crop(d, projectiles)
                .and_then(|m| m.ok_or_else(|| tampered("a projectile lies nowhere near its impact".into())))
        })
        .collect::<Result<_, _>>()?;
    let jobs: Vec<DentJob<'_>> = batch
        .impacts
        .iter()
        .zip(&cropped)
        .map(|(d, projectile)| DentJob {
            target: 0,
            projectile,
            impact: LocalContact::impact_in_target(&d.impact, d.target_to_world),
            params: d.params.clone(),
        })
        .collect();
    let mut meshes = vec![mesh.clone()];
    dent_batch_tracked(&mut meshes, &jobs)
        .map_err(|e| tampered(format!("dent {} does not apply: {}", e.job, e.error)))?;
    Ok(meshes.pop().expect("one mesh"))
}

/// The projectile of `d`, cropped and in the target's coordinates as the damage API cropped it.
fn crop(d: &ImpactDent, projectiles: &Projectiles) -> Result<Option<TriMesh>, RecordError> {
    let mesh = projectiles.resolve(&d.projectile)?;
    Ok(LocalContact::new(&d.impact, d.target_to_world, d.projectile.to_world).crop(&mesh, d.reach))
}
