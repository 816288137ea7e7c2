//! dentbend for Rapier 0.36: dentable colliders and bendable bodies.
//!
//! Denting (paper §3): [`Adapter::step`] (or [`Adapter::step_with`], with the game's hooks and
//! event handler) records the bodies' states before `PhysicsPipeline::step`
//! ([`BodyStates::record`]), reads the step's impacts from the narrow phase ([`ImpactReader`]:
//! the colliders' event settings play no part) and hands them to [`Dentables::process`], which
//! dents the dentable colliders' meshes (on the CPU or any
//! [`DentBackend`](dentbend::damage::DentBackend)) and refits their colliders. A game with its
//! own loop does the same three calls around its own step.
//!
//! Bending (paper §4): [`Bendable`] drives a body split into Rapier bodies joined by impulse
//! joints whose plasticity and elasticity the adapter applies each step, splits a body where a
//! fast hit lands, and skins the parent mesh from the Rapier poses.
//!
//! Units: metres, seconds, kilograms, radians; world coordinates unless a doc says otherwise.
//!
//! # Example
//! A ball falls on a dentable block; the block's collider is refitted to its dent.
//! ```
//! use dentbend_rapier::dentbend::{dent::DentSettings, mesh};
//! use dentbend_rapier::rapier3d::prelude::RigidBodyBuilder;
//! use dentbend_rapier::{Adapter, PhysicsWorld, convex_collider, trimesh_collider};
//! use glam::Vec3;
//!
//! let mut world = PhysicsWorld::new(Vec3::new(0.0, -9.81, 0.0), 1.0 / 60.0);
//! let mut adapter = Adapter::new();
//! let block_mesh = mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [16, 4, 16])?;
//! let fixed = world.bodies.insert(RigidBodyBuilder::fixed());
//! let block = trimesh_collider(&block_mesh)?;
//! let block = world.colliders.insert_with_parent(block, fixed, &mut world.bodies);
//! // 2 m/s threshold, 1 cm per m/s above it, at most 5 cm.
//! adapter.dentables.insert(&world.colliders, &world.bodies, block, block_mesh, DentSettings::new(2.0, 0.01, 0.05))?;
//!
//! let ball_mesh = mesh::icosphere(0.1, 2)?;
//! let ball = RigidBodyBuilder::dynamic().translation(Vec3::new(0.0, 0.4, 0.0)).linvel(-6.0 * Vec3::Y);
//! let ball = world.bodies.insert(ball);
//! let collider = convex_collider(&ball_mesh)?.density(2000.0);
//! let collider = world.colliders.insert_with_parent(collider, ball, &mut world.bodies);
//! adapter.dentables.insert_projectile(&world.colliders, collider, ball_mesh)?;
//!
//! let mut dents = 0;
//! for _ in 0..30 {
//!     dents += adapter.step(&mut world)?.dents.len();
//! }
//! assert_eq!(dents, 1);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

mod adapter;
mod bend_dent;
mod bendable;
mod contacts;
mod dentable;
mod error;
mod fracture;
mod joints;
mod refit;
mod skinned;
mod split;
mod states;
mod world;

pub use adapter::{Adapter, StepReport};
pub use bend_dent::BendDentReport;
pub use bendable::{BendJoint, BendReport, Bendable, Piece};
/// How bendable bodies are built and their joints' rule and state, as dentbend defines them for
/// every engine.
pub use dentbend::bend::{BendSettings, JointState};
pub mod demo;
pub use contacts::{Contact, ImpactCollector, ImpactReader};
pub use dentable::{DentReport, Dentables};
pub use dentbend::gpu::GpuBackend;
pub use error::AdapterError;
pub use fracture::{BrokenCollider, PieceBody};
pub use joints::apply_joint;
pub use refit::{
    Refit, ShapeKind, convex_collider, convex_shape, prepare_refit, refit_collider, shape_kind, trimesh_collider,
};
pub use states::{BodyStates, body_state, to_affine};
pub use world::PhysicsWorld;

pub use dentbend;
pub use rapier3d;
