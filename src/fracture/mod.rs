//! Prescored fracture (paper Figure 3; after Su–Schroeder–Fedkiw 2009 and Müller–Chentanez–Kim
//! 2013): a [`FracturePattern`] of convex Voronoi cells, finer near its origin, is
//! computed once; when a hit passes a body's toughness ([`FractureSettings::breaks`]) the
//! pattern is [placed](Placement) at the impact point along its normal and [`break_body`] cuts
//! the body into closed pieces (one per cell within the radius, with mass properties) and one
//! closed rest. Engine-neutral: meshes and body states in, meshes and velocities out
//! ([`Piece::velocity`]); a [`FractureRecord`] [replays](replay) a fracture bit for bit;
//! [`carry_asset`] carries a game asset's UVs and other attributes over to the rest and pieces.
//! Dent first, then break, so the pieces keep the dent.

mod cap;
mod carry;
mod cell_cut;
mod clip;
mod error;
mod origin;
mod outcome;
mod outgoing;
mod pattern;
mod placement;
mod settings;
mod split_table;
mod tally;
mod weld;

pub use carry::{carry_asset, cut_uv_axes, texel_density};
pub use error::FractureError;
pub use origin::{SurfacePoint, VertexOrigin};
pub use outcome::{FractureOutcome, FractureRecord, Piece, break_body, replay, volume_after};
pub use pattern::{Cell, CellSide, FracturePattern, PatternParams};
pub use placement::Placement;
pub use settings::{DEFAULT_MAX_PIECES, FractureCause, FractureSettings, MAX_PIECES};
pub use tally::DentTally;
pub(crate) use weld::check_mesh_closed;
