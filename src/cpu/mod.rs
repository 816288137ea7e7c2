//! CPU twins of the compute shaders: plain functions over flat slices that read like the WGSL
//! kernels in `shaders/` (same stem, same inputs in binding order). They are the reference in
//! tests and the fallback when no GPU adapter exists.

mod attenuation;
mod displace;
mod envelope_cols;
mod envelope_rows;
mod glance;
mod heat;
mod interleave;
mod layout;
mod moved;
pub mod reference;
mod sample;
mod skin;
mod skin_error;
mod skin_layout;
mod zbuffer;

pub use attenuation::{Attenuation, FalloffFn};
pub use displace::{displace, falloff_table};
pub use envelope_cols::envelope_cols;
pub use envelope_rows::envelope_rows;
pub use glance::glance;
pub(crate) use glance::glance_band;
pub use heat::{heat, heat_step};
pub use interleave::NO_NORMAL;
pub use interleave::{InterleaveParams, interleave};
pub use layout::{DisplaceParams, EnvelopeParams, GlanceParams, GridUniform, HeatParams, ZbufferParams, falloff};
pub use moved::{MovedParams, moved};
pub use skin::{Skinned, skin};
#[cfg(feature = "gpu")]
pub(crate) use skin::{check_length, validate_bones, validate_vertices};
pub use skin_error::{SkinError, WEIGHT_SUM_TOLERANCE};
pub use skin_layout::{SkinBone, SkinInfluence, SkinParams, skin_bones};
pub use zbuffer::zbuffer;
