//! dentbend for Rapier 0.36: dentable colliders and bendable bodies.
//!
//! Denting (paper §3): record the bodies' states before `PhysicsPipeline::step`
//! ([`BodyStates::record`]), step with an [`ImpactCollector`] as the event handler, then hand
//! its impacts to [`Dentables::process`], which dents the dentable colliders' meshes (on the
//! CPU or any [`DentBackend`](dentbend::dent::DentBackend)) and refits their colliders.
//!
//! Bending (paper §4): [`Bendable`] drives a body split into Rapier bodies joined by impulse
//! joints whose plasticity and elasticity the adapter applies each step, splits a body where a
//! fast hit lands, and skins the parent mesh from the Rapier poses.
//!
//! Units: metres, seconds, kilograms, radians; world coordinates unless a doc says otherwise.

mod adapter;
mod bend_dent;
mod bendable;
mod contacts;
mod dentable;
mod elastic;
mod error;
mod gpu;
mod plastic;
mod refit;
mod states;
mod world;

pub use adapter::{Adapter, StepReport};
pub use bend_dent::{BendDentReport, SINGULAR_BLEND};
pub use bendable::{BendJoint, BendReport, BendSettings, Bendable, JointKind, JointRule, Piece};
pub mod demo;
pub use contacts::{Contact, ImpactCollector};
pub use dentable::{DentReport, Dentables};
pub use elastic::ElasticJoint;
pub use error::AdapterError;
pub use gpu::GpuBackend;
pub use plastic::{DRIFT_CORRECTION, JointStep, PlasticJoint};
pub use refit::{Refit, ShapeKind, convex_collider, prepare_refit, refit_collider, shape_kind, trimesh_collider};
pub use states::{BodyStates, body_state, to_affine};
pub use world::PhysicsWorld;

pub use dentbend;
pub use rapier3d;
