//! Collider refits for engines on parry3d (Rapier, Bevy with bevy_rapier3d, dentbend's own
//! world): a triangle-mesh collider updated in place over the vertices a dent moved, without
//! rebuilding it, and convex-hull colliders of dented meshes. `parry` feature.

mod hull;
mod refit;

pub use hull::convex_hull;
pub use refit::{RefitError, RefitStats, VertexMap, refit_shared_trimesh, refit_trimesh, validate_refit};
