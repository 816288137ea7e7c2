//! Carrying a game asset's attributes along a replay: a body restored from a damage file keeps
//! its UVs, authored normals and the rest, as the body that was damaged did. Each dent batch's
//! recorded refinement says which edge each new vertex split; a fracture's rest says where each
//! of its vertices lies on the mesh that broke.

use super::records::DamageRecord;
use super::replay::replay_body_traced;
use super::{BodyDamage, DentForm, Projectiles, RecordError, ReplayStep, Replayed};
use crate::dent::changed_vertices;
use crate::fracture::carry_asset;
use crate::mesh::{Asset, MeshError, Refinement};

impl ReplayStep<'_> {
    /// Brings `asset` (an asset of this step's `before` mesh) through the step: an edit's new
    /// vertices interpolate their edge's attributes and its new faces take their parent's
    /// group, as `refinement` (the batch's recorded one) says ([`Asset::follow_dent`]); a
    /// fracture's rest takes its attributes from where its vertices lie ([`carry_asset`]).
    ///
    /// # Errors
    /// [`MeshError::DentMismatch`] when `asset` is not of `before`'s mesh, `refinement` does not
    /// describe the edit, or the edit changed the faces and no refinement says how (a batch
    /// recorded without one); `asset` is unchanged then.
    pub fn carry(&self, asset: &mut Asset, refinement: Option<&Refinement>) -> Result<(), MeshError> {
        let before = match self {
            Self::Edited { before, .. } | Self::Broke { before, .. } => *before,
        };
        let mismatch = |what, expected, actual| MeshError::DentMismatch { what, expected, actual };
        let mine = asset.mesh();
        if mine.vertex_count() != before.vertex_count() {
            return Err(mismatch(
                "the asset's vertex count, the step's mesh's before",
                before.vertex_count(),
                mine.vertex_count(),
            ));
        }
        if mine.face_count() != before.face_count() {
            return Err(mismatch(
                "the asset's face count, the step's mesh's before",
                before.face_count(),
                mine.face_count(),
            ));
        }
        match self {
            Self::Edited { before, after } => {
                let moved = changed_vertices(before, after);
                match refinement {
                    Some(refinement) => asset.follow_dent((*after).clone(), refinement, &moved),
                    None if before.faces() == after.faces() => {
                        asset.follow_dent((*after).clone(), &Refinement::default(), &moved)
                    }
                    None => Err(mismatch(
                        "a refinement recorded with an edit that changed the faces (new vertices)",
                        after.vertex_count() - before.vertex_count().min(after.vertex_count()),
                        0,
                    )),
                }
            }
            Self::Broke { rest, origins, .. } => {
                *asset = carry_asset(asset, (*rest).clone(), origins)?;
                Ok(())
            }
        }
    }
}

/// [`replay_body_traced`] on `base`'s mesh, bringing `base` (the asset the damage was recorded
/// on) along every record: the replayed damage and the asset of its final mesh.
///
/// # Errors
/// As [`replay_body_traced`]; [`RecordError::Mesh`] when a record cannot carry the attributes
/// (a dent batch that refined the mesh, recorded without its refinement). `base` is not
/// touched.
pub fn replay_body_asset(
    body: &BodyDamage,
    base: &Asset,
    (form, projectiles): (DentForm, &Projectiles),
) -> Result<(Replayed, Asset), RecordError> {
    let mut asset = base.clone();
    // The records that tell a step, in order.
    let mut records = body
        .records
        .iter()
        .filter(|r| matches!(r, DamageRecord::Dents(_) | DamageRecord::Skinned { .. } | DamageRecord::Fracture(_)));
    let mut carried = Ok(());
    let replayed = replay_body_traced(body, base.mesh(), (form, projectiles), &mut |step| {
        let refinement = match records.next() {
            Some(DamageRecord::Dents(batch)) => batch.refinement.as_ref(),
            _ => None,
        };
        if carried.is_ok() {
            carried = step.carry(&mut asset, refinement);
        }
    })?;
    carried?;
    Ok((replayed, asset))
}
