//! CPU twins of the compute shaders: plain functions over flat slices that read like the WGSL
//! kernels in `shaders/` (same stem, same inputs in binding order). They are the reference in
//! tests and the fallback when no GPU adapter exists.
//!
//! The kernel functions are public with the `kernels` feature only; the parameter layouts they
//! share with the shaders, CPU skinning and the falloff curves are always public.

mod attenuation;
mod displace;
mod envelope_cols;
mod envelope_rows;
mod glance;
mod heat;
#[cfg_attr(not(feature = "kernels"), allow(dead_code, reason = "its kernel is the GPU one's reference"))]
mod interleave;
mod layout;
#[cfg_attr(not(feature = "kernels"), allow(dead_code, reason = "its kernel is the GPU one's reference"))]
mod moved;
/// Brute-force references for the kernels' tests (public with the `kernels` feature).
#[cfg(feature = "kernels")]
pub mod reference;
mod sample;
mod skin;
mod skin_error;
mod skin_layout;
mod zbuffer;

pub use attenuation::{Attenuation, FalloffFn};
pub(crate) use glance::glance_band;
pub use interleave::{InterleaveParams, NO_NORMAL};
pub use layout::{DisplaceParams, EnvelopeParams, GlanceParams, GridUniform, HeatParams, ZbufferParams, falloff};
pub use moved::MovedParams;
pub use skin::{Skinned, skin};
#[cfg(feature = "gpu")]
pub(crate) use skin::{check_length, validate_bones, validate_vertices};
pub use skin_error::{SkinError, WEIGHT_SUM_TOLERANCE};
pub use skin_layout::{SkinBone, SkinInfluence, SkinParams, skin_bones};

/// Re-exports kernel functions: public with the `kernels` feature (parity tests, benchmarks,
/// `dentbend-bench`), crate-private without it (the dent pipeline calls them).
macro_rules! kernels {
    ($($tree:tt)*) => {
        #[cfg(feature = "kernels")]
        pub use $($tree)*;
        #[cfg(not(feature = "kernels"))]
        #[allow(unused_imports, reason = "the pipeline calls most kernels; all are public with `kernels`")]
        pub(crate) use $($tree)*;
    };
}

kernels!(displace::{displace, falloff_table});
kernels!(envelope_cols::envelope_cols);
kernels!(envelope_rows::envelope_rows);
kernels!(glance::glance);
kernels!(heat::{heat, heat_step});
kernels!(interleave::interleave);
kernels!(moved::moved);
kernels!(zbuffer::zbuffer);
