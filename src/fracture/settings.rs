//! When a body breaks: its toughness (impact energy, J) and/or the dent it may accumulate (m),
//! and the pattern it breaks along.

use std::sync::Arc;

use super::error::invalid;
use super::{FractureError, FractureOutcome, FracturePattern, PatternParams, Placement};
use crate::dent::{BodyState, Impact, normal_energy_lost};
use crate::mesh::TriMesh;

/// A breakable body's fracture behaviour.
#[derive(Debug, Clone, PartialEq)]
pub struct FractureSettings {
    /// The pattern, built once (shared, so copies of a body do not copy it).
    pub pattern: Arc<FracturePattern>,
    /// Breaks when one impact removes more than this kinetic energy along the normal, J (the
    /// energy a fully inelastic normal impulse between the two bodies takes away); `None`:
    /// impacts alone never break it.
    pub toughness: Option<f32>,
    /// Breaks when its accumulated dent distance passes this, m; `None`: dents never break it.
    pub dent_limit: Option<f32>,
    /// Density of the pieces of a body that has no mass of its own (static or kinematic), kg/m³;
    /// a dynamic body's pieces take its own density. Default 1000.
    pub density: f32,
    /// Most pieces one break may make, 1..=[`MAX_PIECES`]; a break that would make more is
    /// refused ([`FractureError::TooManyPieces`]) and the body stays whole. A cell that cuts a
    /// concave body several times gives several pieces, so a pattern of `n` cells can make more
    /// than `n`. Default [`DEFAULT_MAX_PIECES`].
    pub max_pieces: u32,
}

/// The default [`FractureSettings::max_pieces`]: four pieces a cell of the largest pattern.
pub const DEFAULT_MAX_PIECES: u32 = 1024;
/// The largest [`FractureSettings::max_pieces`] accepted.
pub const MAX_PIECES: u32 = 1 << 16;

/// Why a body broke.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FractureCause {
    /// An impact's energy passed the toughness.
    Energy,
    /// The accumulated dent passed the dent limit.
    Dent,
}

impl FractureSettings {
    /// Settings that break along the pattern of `params` when an impact's energy passes
    /// `toughness` J or the accumulated dent passes `dent_limit` m (at least one given).
    ///
    /// # Errors
    /// [`FractureError::InvalidParameter`] for a bad pattern field, a toughness or dent limit
    /// that is NaN, infinite or negative, or neither given.
    pub fn new(params: PatternParams, toughness: Option<f32>, dent_limit: Option<f32>) -> Result<Self, FractureError> {
        let settings = Self {
            pattern: Arc::new(FracturePattern::new(params)?),
            toughness,
            dent_limit,
            density: 1000.0,
            max_pieces: DEFAULT_MAX_PIECES,
        };
        settings.validate()?;
        Ok(settings)
    }

    /// Checks the toughness, dent limit, density and piece limit (the pattern was checked when
    /// built).
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn validate(&self) -> Result<(), FractureError> {
        if let Some(t) = self.toughness
            && !(t.is_finite() && t >= 0.0)
        {
            return Err(invalid("toughness", t, "J must be finite and >= 0"));
        }
        if let Some(d) = self.dent_limit
            && !(d.is_finite() && d >= 0.0)
        {
            return Err(invalid("dent_limit", d, "m must be finite and >= 0"));
        }
        if !(self.density.is_finite() && self.density > 0.0 && self.density <= 1.0e6) {
            return Err(invalid("density", self.density, "kg/m³ must be finite, > 0 and at most 1e6"));
        }
        if !(1..=MAX_PIECES).contains(&self.max_pieces) {
            return Err(invalid("max_pieces", self.max_pieces, "must be in 1..=65536"));
        }
        if self.toughness.is_none() && self.dent_limit.is_none() {
            return Err(invalid("toughness", "none", "give a toughness, a dent_limit or both"));
        }
        Ok(())
    }

    /// Breaks the closed `mesh` along these settings' pattern at `placement` with pieces at
    /// `density` ([`break_body`](super::break_body)), within the piece limit.
    ///
    /// # Errors
    /// As [`break_body`](super::break_body); [`FractureError::TooManyPieces`] for a break that
    /// would make more than [`max_pieces`](Self::max_pieces).
    pub fn break_mesh(
        &self,
        mesh: &TriMesh,
        placement: &Placement,
        density: f32,
    ) -> Result<Option<FractureOutcome>, FractureError> {
        let outcome = super::break_body(mesh, &self.pattern, placement, density)?;
        match outcome {
            Some(o) if o.pieces.len() > self.max_pieces as usize => {
                Err(FractureError::TooManyPieces { pieces: o.pieces.len(), limit: self.max_pieces })
            }
            outcome => Ok(outcome),
        }
    }

    /// Whether a hit breaks the body, and why: the energy `impact` removes along the normal
    /// between the two bodies' states passes the toughness, or `accumulated_dent` (m, dents
    /// included of this hit) passes the dent limit. Energy wins when both do.
    pub fn breaks(
        &self,
        impact: &Impact,
        target: &BodyState,
        projectile: &BodyState,
        accumulated_dent: f32,
    ) -> Option<FractureCause> {
        let energy = normal_energy_lost(impact, target, projectile);
        if self.toughness.is_some_and(|t| energy > t) {
            Some(FractureCause::Energy)
        } else if self.dent_limit.is_some_and(|d| accumulated_dent > d) {
            Some(FractureCause::Dent)
        } else {
            None
        }
    }
}
