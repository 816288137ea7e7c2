//! Bending, geometry half (paper §4): the articulated [`Skeleton`] of a body, its [`LevelSet`],
//! volumetric-geodesic [`SkinWeights`] (updated for the split bone only after a
//! [`Skeleton::split_bone`]) and the [`SubBodies`] each bone simulates as, with their mass
//! properties.
//!
//! ```text
//! Skeleton (artist / auto_skeleton) ──► WeightCache (LevelSet + voxel graph) ──► SkinWeights
//!        │ split_bone                                                        │ after_split
//!        └──────────────────────────────────────────────────────────────────┴──► SubBodies
//! ```

mod auto_skeleton;
mod bend_settings;
mod bunny;
mod error;
mod geodesic;
mod geometry;
mod joint_rules;
mod joint_state;
mod level_set;
mod rig;
mod skeleton;
mod skeleton_check;
mod sub_bodies;
mod voxelize;
mod weights;
mod weights_solve;

pub use auto_skeleton::MAX_AUTO_BONES;
pub use auto_skeleton::auto_skeleton;
pub use bend_settings::BendSettings;
pub use bunny::bunny_bones;
pub use bunny::{BUNNY_BODY, BUNNY_HEAD, BUNNY_LEFT_EAR, BUNNY_RIGHT_EAR, bunny_skeleton};
pub use error::BendError;
pub use joint_rules::{JointRule, damped_bend_rate, spring};
pub use joint_state::{ElasticJoint, JointBodies, JointState, JointStep, PlasticJoint};
pub(crate) use level_set::DEFAULT_RESOLUTION;
pub use level_set::LevelSet;
pub use rig::{Rig, RigSplit};
pub(crate) use skeleton::MIN_BONE_FRACTION;
pub use skeleton::{Bone, BoneDesc, BoneJoint, Skeleton};
pub use sub_bodies::{NO_BONE, SubBodies, SubBody};
pub use weights::MAX_INFLUENCES;
pub use weights::{SkinWeights, WeightParams};
pub use weights_solve::{WeightCache, compute_weights};
