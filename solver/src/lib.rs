//! # dentbend-solver
//!
//! dentbend's own rigid-body solver with denting and bending in the loop: the paper's scenes
//! (falling bunnies, the bent bar, the prescored wall) run here, and the `dentbend` command line
//! is built on it. It uses only [`dentbend`]'s public, engine-neutral API, as the Rapier and Bevy
//! adapters do.
//!
//! - [`sim`]: rigid bodies on parry3d (contacts, joints, restitution, sleeping);
//! - [`coupling`]: denting, bending, fracture and the damage log inside a simulation;
//! - [`scene`]: scene files (TOML) and the built-in scenes of the paper's figures;
//! - [`render`]: offscreen pictures (a wgpu rasterizer with a CPU fallback).
#![warn(missing_docs)]

pub mod coupling;
#[cfg(feature = "render")]
pub mod render;
#[cfg(feature = "scene")]
pub mod scene;
pub mod sim;
