//! Helpers shared by the integration tests.
#![allow(dead_code, unused_imports, reason = "each test binary uses a different subset")]

pub mod closed;
pub mod envelope;
pub mod geometry;
pub mod gpu;
pub mod hits;
pub mod rng;
pub mod seams;
pub mod skin_tolerance;
pub mod temp;
pub mod text;
pub mod view;

pub use geometry::{cube12, enclosed_volume, self_intersections, sphere_at, triangles_cross};
pub use gpu::context;
pub use rng::SplitMix64;
pub use temp::TempDir;
pub use text::text;
