//! # dentbend
//!
//! Real-time denting and bending of rigid bodies without finite elements, after Heo, Hashemi,
//! Fedkiw et al., *Efficient Denting and Bending of Rigid Bodies* (SCA 2014).
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
//! Every kernel lives in [`cpu`] as a plain function over flat slices, the reference for the
//! WGSL twins; [`dent`] strings them together for one impact or a pair of dentable bodies.
//!
//! ## Getting started
//!
//! ```
//! use dentbend::{dent, glam::Vec3, mesh, DentParams, Impact};
//! let mut block = mesh::builtin("block").unwrap();
//! let ball = mesh::builtin("sphere").unwrap();
//! // The ball rests on the block's top face (y = 0.5), moving down.
//! let (_, top) = ball.bounds();
//! let mut ball_placed = ball.clone();
//! ball_placed.transform(dentbend::glam::Affine3A::from_translation(Vec3::new(0.0, 0.5 - (-1.0), 0.0))).unwrap();
//! let impact = Impact { point: Vec3::new(0.0, 0.5, 0.0), normal: -Vec3::Y, relative_velocity: -Vec3::Y };
//! let report = dent::dent(&mut block, &ball_placed, &impact, &DentParams::new(0.2)).unwrap();
//! assert!(report.max_displacement > 0.19);
//! # let _ = top;
//! ```

pub mod cpu;
pub mod dent;
pub mod io;
pub mod mesh;

pub use dent::{Attenuation, DentError, DentMap, DentParams, Impact, Resolution};
pub use glam;
pub use mesh::{MeshError, TriMesh};
