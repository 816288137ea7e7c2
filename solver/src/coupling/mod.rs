//! The coupling layer, above the rigid core (`sim`) and the rig (`bend`): the bending driver
//! (articulated bodies in a world, skinning them, splitting bones where fast hits land,
//! plastic/elastic joints as world joints), condensation of quiet articulated bodies, denting
//! coupled with bending, and [`Simulation`], which steps a world with all of it.

mod articulated;
mod bendable;
mod bending;
mod condensation;
mod contact_merge;
mod damage_log;
mod dent_coupling;
mod fracture_step;
#[cfg(feature = "gpu")]
mod gpu_skinning;
mod joint_override;
mod pose_dent;
mod rest_revision;
mod simulation;
mod skinning;
mod split;
mod step_stats;

pub use articulated::ArticulatedBody;
pub use bendable::{BendableDesc, DynamicArticulation, SkeletonSpec};
pub use bending::{BendRecord, Bending, JointRecord};
pub use condensation::CondenseSettings;
pub use damage_log::DamageLog;
pub(crate) use dent_coupling::step_motions;
pub use dent_coupling::{BendDenter, StagedBendDents, dent_step};
pub use fracture_step::FractureEvent;
pub(crate) use fracture_step::Fracturer;
#[cfg(feature = "gpu")]
pub use gpu_skinning::GpuSkinner;
pub use joint_override::JointOverride;
pub use pose_dent::PoseDent;
pub use simulation::{Simulation, StepTiming};
pub use skinning::Skinner;
pub use split::SplitOutcome;
pub use step_stats::{StepStats, StepStatsStream};
