//! Tuning knobs of the dent pipeline, with their defaults and units.

use super::error::invalid;
use super::{DentError, VolumeMode};
pub use crate::cpu::Attenuation;
use crate::mesh::MAX_COORDINATE;

/// Smallest accepted `min_cos`: θ ≤ 89.4°, a 100× stretch of the map along the velocity.
pub(crate) const MIN_COS_FLOOR: f32 = 0.01;

/// Largest grid side accepted, cells: 2048² cells is 16 MiB per f32 stage, far past the paper's 400².
pub const MAX_RESOLUTION: u32 = 2048;

/// How the dent grid's side is chosen, in cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Resolution {
    /// From the meshes' mean edge lengths (two cells per edge of the finer mesh), clamped to
    /// `min..=max`.
    Auto {
        /// Smallest side, cells.
        min: u32,
        /// Largest side, cells.
        max: u32,
    },
    /// Exactly this many cells per side.
    Fixed(u32),
}

impl Default for Resolution {
    /// `Auto { min: 25, max: 400 }`, the paper's range.
    fn default() -> Self {
        Self::Auto { min: 25, max: 400 }
    }
}

/// Checks the falloff for dent distance `d`; a custom one must give a(0) = 1 and stay finite
/// at the depths [`cpu::displace`](crate::cpu::displace) samples it.
pub(crate) fn validate_attenuation(attenuation: &Attenuation, d: f32) -> Result<(), DentError> {
    match attenuation {
        Attenuation::Linear { scale } if !(scale.is_finite() && *scale > 0.0) => {
            Err(invalid("attenuation.scale", scale, "must be finite and > 0"))
        }
        Attenuation::Custom(f) => {
            let at_zero = f(0.0, d);
            if !at_zero.is_finite() || (at_zero - 1.0).abs() > 1e-3 {
                return Err(invalid("attenuation", at_zero, "a custom falloff must give a(0) = 1"));
            }
            let (_, _, table) = crate::cpu::falloff_table(attenuation, d);
            match table.into_iter().find(|a| !a.is_finite()) {
                Some(bad) => Err(invalid("attenuation", bad, "a custom falloff must stay finite")),
                None => Ok(()),
            }
        }
        _ => Ok(()),
    }
}

/// Parameters of one dent (paper Algorithm 1). Lengths are world units.
///
/// # Example
/// ```
/// use dentbend::DentParams;
/// let params = DentParams { sigma: Some(0.05), ..DentParams::new(0.2) };
/// assert!(params.validate().is_ok());
/// ```
#[derive(Debug, Clone)]
pub struct DentParams {
    /// Dent distance `d`: peak displacement of the map, world units (> 0).
    pub dent_distance: f32,
    /// Width σ of the broadening Gaussians, world units; `None` uses `d / 2`.
    pub sigma: Option<f32>,
    /// Grid side, cells. Default: automatic in 25..=400.
    pub resolution: Resolution,
    /// k₁: plain heat steps after broadening (default 8). Smoothing costs (k₁ + k₂)·res² cell
    /// updates; both counts are capped at 100,000.
    pub heat_iters: u32,
    /// k₂: clamped, increase-only heat steps after rescaling (default 16).
    pub clamp_iters: u32,
    /// α of the explicit step `E ← E + α·ΔE`, in (0, ¼] (default 0.2).
    pub heat_rate: f32,
    /// Falloff `a(z)` with depth below the collision plane (default: the paper's logistic).
    pub attenuation: Attenuation,
    /// Widening `t` of glancing dents, 1/world unit, ≥ 0 (default 0: the plain shear).
    pub widen: f32,
    /// Lower clamp of cos θ for glancing impacts, in [0.01, 1] (default 0.1, θ ≤ 84.3°).
    pub min_cos: f32,
    /// Refinement of the target under the dent before it is displaced (default
    /// [`Refine::Auto`](super::Refine::Auto): where the map needs it, capped).
    pub refine: super::Refine,
    /// Whether the dent's cavity is lost (default [`VolumeMode::Free`], the paper's behaviour)
    /// or put back as a raised rim ([`VolumeMode::Preserve`]).
    pub volume: VolumeMode,
    /// Scale a dent back so that it makes no faces of its target cross (default on; the report's
    /// `limited_to` says when it did). Every batch path applies it (`dent`, `dent_pair`, the CPU
    /// batches and `GpuDenter::dent_batch`).
    pub guard_crossings: bool,
}

impl DentParams {
    /// Defaults for a dent of depth `dent_distance` (world units).
    pub fn new(dent_distance: f32) -> Self {
        Self {
            dent_distance,
            sigma: None,
            resolution: Resolution::default(),
            heat_iters: 8,
            clamp_iters: 16,
            heat_rate: 0.2,
            attenuation: Attenuation::Logistic,
            widen: 0.0,
            min_cos: 0.1,
            refine: super::Refine::default(),
            volume: VolumeMode::Free,
            guard_crossings: true,
        }
    }

    /// The stages of this dent that run on the host, around the map kernels and the
    /// displacement: `"refinement"`, `"intersection guard"`, `"volume rim"` (empty for the
    /// paper's dent). A falloff steep enough to fold a wall under its map (not the default
    /// logistic one) is also fitted on the host, which only the plan can tell.
    pub fn host_stages(&self) -> Vec<&'static str> {
        let mut stages = Vec::new();
        if self.refine != super::Refine::Off {
            stages.push("refinement");
        }
        if self.guard_crossings {
            stages.push("intersection guard");
        }
        if self.volume == VolumeMode::Preserve {
            stages.push("volume rim");
        }
        stages
    }

    /// The same dent without its host stages: no refinement, no guard, no volume rim (the
    /// paper's dent, which the GPU kernels make alone).
    pub fn without_host_stages(self) -> Self {
        Self { refine: super::Refine::Off, guard_crossings: false, volume: VolumeMode::Free, ..self }
    }

    /// The Gaussian width actually used, world units.
    pub fn sigma_or_default(&self) -> f32 {
        self.sigma.unwrap_or(0.5 * self.dent_distance)
    }

    /// Checks every field's range.
    ///
    /// # Errors
    /// [`DentError::InvalidParameter`] naming the first bad field.
    pub fn validate(&self) -> Result<(), DentError> {
        let d = self.dent_distance;
        if !(d.is_finite() && d > 0.0 && d <= MAX_COORDINATE) {
            return Err(invalid("dent_distance", d, "must be finite, > 0 and at most 1e6 (the coordinate range)"));
        }
        if let Some(s) = self.sigma
            && !(s.is_finite() && s > 0.0 && s <= MAX_COORDINATE)
        {
            return Err(invalid("sigma", s, "must be finite, > 0 and at most 1e6 (the coordinate range)"));
        }
        match self.resolution {
            Resolution::Fixed(n) if !(1..=MAX_RESOLUTION).contains(&n) => {
                return Err(invalid("resolution", n, "must be in 1..=2048 cells"));
            }
            Resolution::Auto { min, max } if min == 0 || min > max || max > MAX_RESOLUTION => {
                return Err(invalid("resolution", format!("{min}..={max}"), "needs 1 <= min <= max <= 2048"));
            }
            _ => {}
        }
        const MAX_ITERS: u32 = 100_000;
        if self.heat_iters > MAX_ITERS {
            return Err(invalid("heat_iters", self.heat_iters, "must be at most 100000"));
        }
        if self.clamp_iters > MAX_ITERS {
            return Err(invalid("clamp_iters", self.clamp_iters, "must be at most 100000"));
        }
        if !(self.heat_rate > 0.0 && self.heat_rate <= 0.25) {
            return Err(invalid("heat_rate", self.heat_rate, "must be in (0, 0.25] for a stable explicit step"));
        }
        if !(self.widen.is_finite() && self.widen >= 0.0) {
            return Err(invalid("widen", self.widen, "must be finite and >= 0"));
        }
        if !(self.min_cos >= MIN_COS_FLOOR && self.min_cos <= 1.0) {
            return Err(invalid("min_cos", self.min_cos, "must be in [0.01, 1]"));
        }
        self.refine.validate()?;
        validate_attenuation(&self.attenuation, d)
    }
}
