//! Helpers shared by the integration tests.
#![allow(dead_code, unused_imports, reason = "each test binary uses a different subset")]

pub mod cli;
pub mod closed;
pub mod envelope;
pub mod geometry;
pub mod gpu;
pub mod hits;
pub mod rng;
pub mod seams;
pub mod skin_tolerance;
pub mod temp;
pub mod view;
pub mod walls;

pub use cli::{dentbend, text};
pub use geometry::{cube12, enclosed_volume, self_intersections, sphere_at, triangles_cross};
pub use gpu::context;
pub use rng::SplitMix64;
pub use temp::TempDir;
