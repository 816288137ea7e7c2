//! A thin rigid-body core on parry3d: bodies, collisions, contacts and collision events, stepped
//! in the Guendelman–Bridson–Fedkiw order (ARCHITECTURE.md §2), with denting in the loop (paper
//! Algorithm 1).

mod activity;
mod body;
mod body_kind;
mod broad_phase;
mod capsule_fit;
mod cluster;
mod collider;
mod contact_parts;
mod contacts;
mod dent_impact;
mod dent_record;
mod denting;
mod error;
mod events;
mod gpu_device;
mod joint_rounds;
mod joints;
mod sleep;
mod solver;
mod union_find;
mod warm_start;
mod world;
mod world_settings;

#[cfg(feature = "scene")]
pub(crate) use body::MAX_ANGULAR_SPEED;
pub use body::{BodyDesc, RigidBody, SurfaceMaterial};
pub use body_kind::BodyKind;
pub(crate) use broad_phase::Aabb;
pub use collider::ColliderKind;
pub(crate) use contacts::{ContactPoint, PairContacts};
pub use dent_impact::{DecidedDent, StepContext, SurfaceOverride, body_state};
pub use dent_record::DentRecord;
pub use dentbend::dent::DentSettings;
pub use dentbend::mesh::{MassProperties, mass_properties};
pub use denting::Denter;
pub use error::SimError;
pub use events::{CollisionEvent, StepReport};
pub use gpu_device::GpuDevice;
pub use joints::{BendEvent, Joint, JointKind};
pub(crate) use union_find::UnionFind;
pub use world::{World, WorldState};
pub use world_settings::WorldSettings;
