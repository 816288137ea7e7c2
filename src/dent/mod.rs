//! Denting (paper §3): impact → dent frame → dent map → displaced target mesh; the dent
//! decision (threshold / gain / cap or the energy model), projectile cropping and batches on all
//! cores. The world-free damage API built on it is [`crate::damage`].

mod apply;
mod artist;
mod batch;
mod body_state;
mod changed;
mod decide;
mod energy;
mod error;
mod grid;
mod guard;
mod guard_pairs;
#[cfg(feature = "gpu")]
mod host_stages;
mod impact;
mod local_contact;
mod map;
mod material;
mod params;
mod pipeline;
mod plan;
mod progressive;
mod reach;
#[cfg(feature = "gpu")]
mod refine_jobs;
mod refine_setting;
mod refine_target;
mod settings;
mod thickness;
mod volume;
mod volume_mode;

pub use apply::{DentReport, dent, dent_pair};
pub use batch::{BatchError, BatchOutcome, DentJob, dent_batch, dent_batch_tracked};
pub use body_state::BodyState;
pub use changed::{changed_vertices, moved_vertices};
pub use decide::{decide_dent_distance, projectile_offset};
pub(crate) use energy::normal_energy_lost;
pub use error::DentError;
pub(crate) use error::invalid;
pub use grid::{DentFrame, Grid};
#[cfg(feature = "gpu")]
pub(crate) use host_stages::{falloff_may_need_fit, finish_displaced, fit_to_target};
pub use impact::{Impact, MAX_SPEED};
pub use local_contact::{LocalContact, OctDirection, PoseRotation};
pub use map::{DentMap, DisplaceReport};
pub use material::DentMaterial;
pub use params::{Attenuation, DentParams, MAX_RESOLUTION, Resolution};
pub use pipeline::dent_map;
kernels_use!(pipeline::{DentStages, dent_map_stages});
kernels_use!(plan::{DentPlan, GLANCE_RESOLUTION_FLOOR, GLANCE_STRETCH_CAP, plan_dent});
pub(crate) use progressive::ProgressiveDents;
pub use reach::Surface;
pub(crate) use reach::crop_to_ball;
pub use reach::radius_about_origin;
#[cfg(feature = "gpu")]
pub(crate) use refine_jobs::RefinedTargets;
#[cfg(feature = "gpu")]
#[cfg(feature = "gpu")]
pub(crate) use refine_jobs::{plan_jobs, refine_planned};
pub use refine_setting::Refine;
pub use settings::DentSettings;
#[cfg(feature = "gpu")]
pub(crate) use thickness::FittedFalloff;
pub use volume_mode::VolumeMode;
