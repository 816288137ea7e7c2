//! The world-free damage API: dents and fractures from any rigid-body solver's contacts, keyed
//! by the caller's own body ids. The caller reports hits ([`Hit`]) and exposes its bodies
//! ([`DentTargets`]); [`Damage::plan`] decides every dent, crops each projectile to the part that
//! hit, builds the maps from the undented surfaces (Jacobi) and dents copies of the targets on
//! a [`DentBackend`] (all CPU cores, or the GPU), then breaks the breakable bodies a hit or
//! their accumulated dent broke — changing nothing until the caller takes the [`DamagePlan`]:
//! new meshes, the vertices that moved (for a collider refit), how far to move each projectile
//! into its dent, and each fracture's rest and pieces. [`TargetSet`] stores the bodies for a
//! caller whose engine keeps no triangle meshes.

mod backend;
mod error;
mod fracture;
mod hit;
mod plan;
mod target_set;

pub use backend::{CpuBackend, DentBackend};
pub use error::DamageError;
pub use fracture::BreakingHit;
pub use fracture::{BodyFracture, BrokenPiece, PIECE_HULL_SCALE, PieceId, piece_hull_points};
pub use hit::{DentTargets, Hit, TargetView};
pub use plan::{AppliedDent, Damage, DamagePlan, DentedTarget};
pub use target_set::TargetSet;
