//! Denting (paper §3): impact → dent frame → dent map → displaced target mesh.

mod apply;
mod artist;
mod batch;
mod error;
mod grid;
mod impact;
mod map;
mod material;
mod params;
mod pipeline;
mod plan;

pub use apply::{DentReport, dent, dent_pair};
pub use artist::gaussian_heights;
pub use batch::{BatchError, DentJob, dent_batch};
pub use error::DentError;
pub(crate) use error::invalid;
pub use grid::{DentFrame, Grid};
pub use impact::Impact;
pub use map::{DentMap, DisplaceReport};
pub use material::DentMaterial;
pub use params::{Attenuation, DentParams, FalloffFn, MAX_RESOLUTION, MIN_COS_FLOOR, Resolution};
pub use pipeline::{DentStages, dent_map, dent_map_stages};
pub use plan::{DentPlan, plan_dent};
