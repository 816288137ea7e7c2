//! Helpers shared by the solver's integration tests: its own (running the binary, wall scenes)
//! and, by path, those of the core crate's tests.
#![allow(dead_code, unused_imports, reason = "each test binary uses a different subset")]

pub mod cli;
#[path = "../../../tests/common/geometry.rs"]
pub mod geometry;
#[path = "../../../tests/common/gpu.rs"]
pub mod gpu;
#[path = "../../../tests/common/rng.rs"]
pub mod rng;
#[path = "../../../tests/common/skin_tolerance.rs"]
pub mod skin_tolerance;
#[path = "../../../tests/common/temp.rs"]
pub mod temp;
#[path = "../../../tests/common/text.rs"]
pub mod text;
pub mod walls;

pub use cli::dentbend;
pub use geometry::{cube12, enclosed_volume, self_intersections, sphere_at, triangles_cross};
pub use gpu::context;
pub use rng::SplitMix64;
pub use temp::TempDir;
pub use text::text;
