//! Tuning knobs of the dent pipeline, with their defaults and units.

use std::fmt;
use std::sync::Arc;

use super::DentError;
use super::error::invalid;

/// Smallest accepted `min_cos`: θ ≤ 89.4°, a 100× stretch of the map along the velocity.
pub const MIN_COS_FLOOR: f32 = 0.01;

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

/// A user-supplied falloff `a(z, d)`: `z` is depth into the target (world units, ≥ 0), `d` the
/// dent distance; it must return 1 at `z = 0`.
pub type FalloffFn = dyn Fn(f32, f32) -> f32 + Send + Sync;

/// The attenuation `a(z)` that scales the dent map at depth `z` below the collision plane
/// (paper §3.1). Points in front of the plane (`z < 0`) always get `a = 1`.
#[derive(Clone, Default)]
pub enum Attenuation {
    /// The paper's `a(z) = 2 / (1 + e^{z/d})`: the back of a block bulges by `a(thickness)·d`.
    #[default]
    Logistic,
    /// `a(z) = max(0, 1 − z / (scale·d))`; `scale < 1` is steeper than the no-fold bound.
    Linear {
        /// Depth at which the dent has faded out, in dent distances.
        scale: f32,
    },
    /// `a(z) = 1`: the whole body moves with the dent map (no falloff).
    None,
    /// Any function of depth; see [`FalloffFn`].
    Custom(Arc<FalloffFn>),
}

impl fmt::Debug for Attenuation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Logistic => f.write_str("Logistic"),
            Self::Linear { scale } => f.debug_struct("Linear").field("scale", scale).finish(),
            Self::None => f.write_str("None"),
            Self::Custom(_) => f.write_str("Custom(..)"),
        }
    }
}

impl Attenuation {
    /// `a(z)` for depth `z` (world units) and dent distance `d > 0`.
    #[inline]
    pub fn eval(&self, z: f32, d: f32) -> f32 {
        if z <= 0.0 {
            return 1.0;
        }
        match self {
            Self::Logistic => 2.0 / (1.0 + (z / d).exp()),
            Self::Linear { scale } => (1.0 - z / (scale * d)).max(0.0),
            Self::None => 1.0,
            Self::Custom(f) => f(z, d),
        }
    }

    /// Steepest descent of `a` over `z ∈ [0, 8d]`, in units of `1/d`: the falloff folds thin
    /// walls when this exceeds 1, the slope of `1 − z/d` (paper §3.1, Figure 2d). Sampled at
    /// 1024 intervals, so a custom function's kink narrower than `d/128` can be missed.
    pub fn max_steepness(&self, d: f32) -> f32 {
        const SAMPLES: usize = 1024;
        let dz = 8.0 * d / SAMPLES as f32;
        (0..SAMPLES)
            .map(|k| {
                let z = k as f32 * dz;
                (self.eval(z, d) - self.eval(z + dz, d)) / dz * d
            })
            .fold(0.0, f32::max)
    }

    /// Checks the falloff for dent distance `d`; a custom one must give a(0) = 1 and stay finite
    /// at the depths [`cpu::displace`](crate::cpu::displace) samples it.
    pub(crate) fn validate(&self, d: f32) -> Result<(), DentError> {
        match self {
            Self::Linear { scale } if !(scale.is_finite() && *scale > 0.0) => {
                Err(invalid("attenuation.scale", scale, "must be finite and > 0"))
            }
            Self::Custom(f) => {
                let at_zero = f(0.0, d);
                if !at_zero.is_finite() || (at_zero - 1.0).abs() > 1e-3 {
                    return Err(invalid("attenuation", at_zero, "a custom falloff must give a(0) = 1"));
                }
                let (_, _, table) = crate::cpu::falloff_table(self, d);
                match table.into_iter().find(|a| !a.is_finite()) {
                    Some(bad) => Err(invalid("attenuation", bad, "a custom falloff must stay finite")),
                    None => Ok(()),
                }
            }
            _ => Ok(()),
        }
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
        }
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
        if !(d.is_finite() && d > 0.0) {
            return Err(invalid("dent_distance", d, "must be finite and > 0"));
        }
        if let Some(s) = self.sigma
            && !(s.is_finite() && s > 0.0)
        {
            return Err(invalid("sigma", s, "must be finite and > 0"));
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
        self.attenuation.validate(d)
    }
}
