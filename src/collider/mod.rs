//! Collider refits for engines on parry3d (Rapier, Bevy with bevy_rapier3d, dentbend's own
//! world): a triangle-mesh collider updated in place over the vertices a dent moved, without
//! rebuilding it. `parry` feature.

mod refit;

pub use refit::{RefitError, RefitStats, VertexMap, refit_shared_trimesh, refit_trimesh, validate_refit};
