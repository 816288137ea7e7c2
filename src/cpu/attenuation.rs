//! The attenuation `a(z)` of a dent with depth into the target (paper §3.1), as the
//! [`displace`](super::displace) kernel evaluates it.

use std::fmt;
use std::sync::Arc;

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
    /// Any function of depth; see `FalloffFn`.
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
}
