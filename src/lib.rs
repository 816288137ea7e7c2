//! # dentbend
//!
//! Real-time denting and bending of rigid bodies without finite elements, after Patkar,
//! Aanjaneya, Bartle, Lee and Fedkiw, *Efficient Denting and Bending of Rigid Bodies* (SCA 2014).
//!
//! Denting works with any rigid-body solver: feed your contacts to the world-free damage API
//! ([`Damage`], keyed by your own body ids) and apply the meshes, moved vertices and
//! projectile offsets it returns; `dentbend-rapier` does this for Rapier. The rig and the
//! plastic / elastic joint rules are in [`bend`]. See ARCHITECTURE.md for the layers.
//!
//! ## Data flow of a dent (paper Algorithm 1)
//!
//! ```text
//! Impact ──► DentFrame + Grid ──► zbuffer ──► envelope_rows ──► envelope_cols ──► heat ──► glance ──► displace
//!            (dent::frame)        profile P   log-domain rows    exact Gaussian     k₁ plain,   3-vector   target
//!                                 (0..=d)     (parabola DT)      envelope E         rescale,    map on the vertices
//!                                                                                   k₂ clamped  collision  moved, normals
//!                                                                                                plane      refreshed
//! ```
//!
//! The host plans each dent first (`dent::plan_dent`, public with the `kernels` feature: frame,
//! grids, kernel parameter blocks).
//! Every kernel lives in [`cpu`] as a plain function over flat slices and in `shaders/` as a
//! WGSL compute shader that serves a whole batch of dents per dispatch ([`gpu`]); the CPU twins
//! are the reference in tests and the fallback without an adapter (`DENTBEND_BACKEND=cpu|gpu|auto`).
//! [`mod@dent`] strings the CPU kernels together for one impact ([`dent()`]), a pair of dentable
//! bodies ([`dent_pair`]) or a batch on all cores ([`dent::dent_batch`]); [`gpu::GpuDenter`]
//! does batches on the GPU with the targets resident there.
//!
//! ## Getting started
//!
//! ```
//! use dentbend::{DentParams, Impact, dent, glam::{Affine3A, Vec3}, mesh};
//!
//! // A 4 × 1 × 4 block (top face at y = 0.5) and a unit ball resting on it.
//! let mut block = mesh::builtin("block")?;
//! let mut ball = mesh::builtin("sphere")?;
//! ball.transform(Affine3A::from_translation(Vec3::new(0.0, 1.5, 0.0)))?;
//!
//! // The ball moves down into the block: the denting normal points into the block.
//! let impact = Impact { point: Vec3::new(0.0, 0.5, 0.0), normal: -Vec3::Y, relative_velocity: -3.0 * Vec3::Y };
//! let report = dent(&mut block, &ball, &impact, &DentParams::new(0.2))?;
//! assert!((report.max_displacement - 0.2).abs() < 0.01);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

/// Declares a method or function of the dent stages taken one by one: public with the `kernels`
/// feature, crate-private without it.
macro_rules! kernels_fn {
    ($(#[$meta:meta])* fn $($rest:tt)*) => {
        #[cfg(feature = "kernels")]
        $(#[$meta])* pub fn $($rest)*
        #[cfg(not(feature = "kernels"))]
        #[allow(dead_code, reason = "public with `kernels`")]
        $(#[$meta])* pub(crate) fn $($rest)*
    };
}

/// Re-exports items of the dent stages taken one by one (kernel functions, their parameter
/// layouts, the per-stage plan and outputs): public with the `kernels` feature (parity tests,
/// benchmarks, `dentbend-bench`, the command line's `dentmap`), crate-private without it (the
/// dent pipeline uses them).
macro_rules! kernels_use {
    ($($tree:tt)*) => {
        #[cfg(feature = "kernels")]
        pub use $($tree)*;
        #[cfg(not(feature = "kernels"))]
        #[allow(unused_imports, reason = "the pipeline uses most of them; all are public with `kernels`")]
        pub(crate) use $($tree)*;
    };
}

pub mod bend;
#[cfg(feature = "parry")]
pub mod collider;
pub mod cpu;
pub mod damage;
pub mod dent;
pub mod fracture;
#[cfg(feature = "gpu")]
pub mod gpu;
#[cfg(feature = "io")]
pub mod io;
pub mod mesh;
pub mod record;

pub use damage::{Damage, DamagePlan, DentTargets, Hit, TargetSet};
pub use dent::{
    Attenuation, DentError, DentMap, DentParams, DentReport, Impact, Resolution, VolumeMode, dent, dent_map, dent_pair,
};
pub use glam;
pub use mesh::{MeshError, TriMesh};
/// The wgpu version dentbend's GPU path is built on, for handing it an application's device
/// ([`gpu::GpuContext::from_device`]).
#[cfg(feature = "gpu")]
pub use wgpu;
