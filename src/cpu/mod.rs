//! CPU twins of the compute shaders: plain functions over flat slices that read like the WGSL
//! kernels in `shaders/` (same stem, same inputs in binding order). They are the reference in
//! tests and the fallback when no GPU adapter exists.
//!
//! The kernel functions, the parameter layouts they share with the shaders and the falloff
//! curves are public with the `kernels` feature only; CPU skinning is always public.

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
kernels_use!(layout::{DisplaceParams, EnvelopeParams, GlanceParams, GridUniform, HeatParams, ZbufferParams, falloff});
pub use moved::MovedParams;
#[cfg(feature = "gpu")]
pub(crate) use skin::check_length;
pub use skin::{Skinned, skin};
pub use skin_error::{SkinError, WEIGHT_SUM_TOLERANCE};
pub use skin_layout::{SkinBone, SkinInfluence, SkinParams, skin_bones};

kernels_use!(displace::{displace, falloff_table});
kernels_use!(envelope_cols::envelope_cols);
kernels_use!(envelope_rows::envelope_rows);
kernels_use!(glance::glance);
kernels_use!(heat::{heat, heat_step});
kernels_use!(interleave::interleave);
kernels_use!(moved::moved);
kernels_use!(zbuffer::zbuffer);
