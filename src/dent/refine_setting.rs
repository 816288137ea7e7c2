//! The refine setting of a dent ([`Refine`]) and its limits; the stage itself is in
//! `refine_target`.

use super::DentError;
use super::error::invalid;
use crate::mesh::MAX_COORDINATE;

/// Whether, and how finely, the target is refined under a dent before it is displaced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Refine {
    /// Where the target is too coarse for the dent (an edge under the footprint longer than 4×
    /// what the map resolves and than half the map's width,
    /// `auto_coarse_edge`), refine the footprint to the edges the
    /// map resolves, `max(2σ, 2 map cells, width/12)`
    /// (`auto_max_edge`). A target finer than that is left as it is,
    /// so repeated dents do not keep growing it. A dent that would need more than
    /// `max_new_triangles` new triangles is refined with edges twice, four or eight times as
    /// long (the first that fits), or not at all, with a warning in its
    /// report. The default, with [`DEFAULT_MAX_NEW_TRIANGLES`](Self::DEFAULT_MAX_NEW_TRIANGLES).
    Auto {
        /// Most triangles one dent may add.
        max_new_triangles: u32,
    },
    /// Never refine: the dent moves the target's vertices as they are.
    Off,
    /// Refine until no edge under the footprint is longer than this, world units (finite and
    /// positive). A dent that would need more than [`MAX_EDGE_NEW_TRIANGLES`](Self::MAX_EDGE_NEW_TRIANGLES) new triangles
    /// fails with [`DentError::InvalidParameter`] and changes nothing.
    MaxEdge(f32),
}

/// Times [`Refine::Auto`] doubles its edge length before it gives up on a dent.
pub(crate) const AUTO_DOUBLINGS: u32 = 3;

impl Default for Refine {
    /// `Auto { max_new_triangles: Refine::DEFAULT_MAX_NEW_TRIANGLES }`.
    fn default() -> Self {
        Self::Auto { max_new_triangles: Self::DEFAULT_MAX_NEW_TRIANGLES }
    }
}

impl Refine {
    /// Triangles one dent may add under [`Refine::Auto`] by default: enough for a 1 m² footprint
    /// with 2.5 cm edges (a 12-triangle 2 m crate hit by a 1 m ball with d = 0.1 m adds about
    /// 700).
    pub const DEFAULT_MAX_NEW_TRIANGLES: u32 = 20_000;

    /// Triangles one dent may add under [`Refine::MaxEdge`].
    pub const MAX_EDGE_NEW_TRIANGLES: usize = 1_000_000;

    /// Checks the setting.
    ///
    /// # Errors
    /// [`DentError::InvalidParameter`] for a `MaxEdge` that is NaN, infinite, ≤ 0 or above
    /// [`MAX_COORDINATE`].
    pub fn validate(&self) -> Result<(), DentError> {
        match *self {
            Self::MaxEdge(edge) if !(edge.is_finite() && edge > 0.0 && edge <= MAX_COORDINATE) => {
                Err(invalid("refine", edge, "must be a finite edge length > 0 and at most 1e6"))
            }
            _ => Ok(()),
        }
    }
}
