//! The fracture pattern (paper Figure 3, after Su–Schroeder–Fedkiw 2009 and Müller–Chentanez–Kim
//! 2013): Voronoi cells computed once in a reference frame whose origin is the impact point and
//! whose z axis is the impact normal. Seeds are drawn in the frame's xy disk with a density that
//! grows towards the origin (radius = R·u for u uniform in [0, 1), so the density per area falls
//! as 1/r), deterministically from a seed; each cell is the seed's 2D Voronoi region clipped to a
//! 16-gon of inradius R, extruded over z ∈ [−R, R]: a convex prism that cuts straight through a
//! wall along the normal.

use glam::DVec2;
use serde::{Deserialize, Serialize};

use super::FractureError;
use super::error::invalid;
use crate::mesh::MAX_COORDINATE;

/// Sides of the polygon that bounds the pattern (its inradius is the pattern's radius).
pub(crate) const BOUND_SIDES: usize = 16;

/// What a pattern is made from: with the same parameters it is the same, bit for bit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PatternParams {
    /// Number of Voronoi cells, 1..=[`MAX_CELLS`](Self::MAX_CELLS).
    pub cells: u32,
    /// Seed of the generator that places the cells.
    pub seed: u64,
    /// Radius within which the body breaks, m (> 0, at most [`MAX_COORDINATE`]): the cells fill
    /// the 16-gon of this inradius, and reach this far along the normal both ways.
    pub radius: f32,
}

impl PatternParams {
    /// Most cells a pattern may have.
    pub const MAX_CELLS: u32 = 256;

    /// Checks every field.
    ///
    /// # Errors
    /// [`FractureError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<(), FractureError> {
        if !(1..=Self::MAX_CELLS).contains(&self.cells) {
            return Err(invalid("cells", self.cells, "must be in 1..=256"));
        }
        if !(self.radius.is_finite() && self.radius > 0.0 && self.radius <= MAX_COORDINATE) {
            return Err(invalid("radius", self.radius, "must be finite, > 0 and at most 1e6 m"));
        }
        Ok(())
    }
}

/// One side of a cell: the points x of the frame's xy plane with `normal`·x ≤ `offset` are in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellSide {
    /// Outward unit normal in the frame's xy plane.
    pub normal: DVec2,
    /// Offset along the normal, m.
    pub offset: f64,
    /// Whether the side is shared with another cell (a Voronoi bisector) rather than on the
    /// pattern's bounding polygon.
    pub shared: bool,
}

/// A convex cell of the pattern: a polygon of the frame's xy plane, extruded over z ∈ [−R, R].
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// The cell's Voronoi seed, frame coordinates, m.
    pub seed: DVec2,
    /// Corners, counter-clockwise seen from +z, m.
    pub corners: Vec<DVec2>,
    /// Sides, the one from `corners[k]` to `corners[k + 1]` at `k`.
    pub sides: Vec<CellSide>,
}

impl Cell {
    /// Area of the cell's polygon, m².
    pub fn area(&self) -> f64 {
        shoelace(&self.corners)
    }
}

/// Voronoi cells in the reference frame (origin at the impact point, z along the normal),
/// computed once from [`PatternParams`].
#[derive(Debug, Clone, PartialEq)]
pub struct FracturePattern {
    params: PatternParams,
    cells: Vec<Cell>,
    bound: Vec<CellSide>,
}

impl FracturePattern {
    /// Builds the pattern of `params`: `params.cells` seeds (drawn from `params.seed`), their
    /// Voronoi cells clipped to the bounding 16-gon. O(cells² · sides).
    ///
    /// # Errors
    /// [`FractureError::InvalidParameter`] for a bad field; nothing is built then.
    pub fn new(params: PatternParams) -> Result<Self, FractureError> {
        params.validate()?;
        let radius = f64::from(params.radius);
        let bound = bounding_polygon(radius);
        let seeds = seeds(params.seed, params.cells as usize, radius);
        let cells = seeds
            .iter()
            .enumerate()
            .map(|(i, &seed)| {
                let mut polygon: Vec<(DVec2, bool)> = bound.iter().map(|&c| (c, false)).collect();
                for (j, &other) in seeds.iter().enumerate() {
                    let along = other - seed;
                    if j == i || along.length_squared() < 1e-24 * radius * radius {
                        continue;
                    }
                    let normal = along.normalize();
                    polygon = clip_polygon(&polygon, normal, normal.dot(0.5 * (seed + other)));
                }
                cell_of(seed, &polygon)
            })
            .filter(|c| c.corners.len() >= 3)
            .collect();
        let bound_sides = cell_of(DVec2::ZERO, &bound.iter().map(|&c| (c, false)).collect::<Vec<_>>()).sides;
        Ok(Self { params, cells, bound: bound_sides })
    }

    /// The parameters it was built from.
    pub fn params(&self) -> PatternParams {
        self.params
    }

    /// The cells (as many as `params.cells`, fewer only where two seeds coincide).
    pub fn cells(&self) -> &[Cell] {
        &self.cells
    }

    /// The sides of the bounding 16-gon (the union of the cells), counter-clockwise.
    pub fn bound(&self) -> &[CellSide] {
        &self.bound
    }

    /// The pattern's radius, m.
    pub fn radius(&self) -> f64 {
        f64::from(self.params.radius)
    }
}

/// SplitMix64: a small, well-mixed generator, the same on every platform.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `count` seeds in the disk of `radius`: distance R·u, angle uniform (denser near the origin).
fn seeds(seed: u64, count: usize, radius: f64) -> Vec<DVec2> {
    let mut rng = SplitMix(seed);
    (0..count)
        .map(|_| {
            let r = radius * rng.unit();
            let angle = std::f64::consts::TAU * rng.unit();
            DVec2::new(r * angle.cos(), r * angle.sin())
        })
        .collect()
}

/// Corners of the regular [`BOUND_SIDES`]-gon of inradius `radius`, counter-clockwise.
fn bounding_polygon(radius: f64) -> Vec<DVec2> {
    let n = BOUND_SIDES as f64;
    let corner = radius / (std::f64::consts::PI / n).cos();
    (0..BOUND_SIDES)
        .map(|k| {
            let angle = std::f64::consts::TAU * (k as f64 + 0.5) / n;
            DVec2::new(corner * angle.cos(), corner * angle.sin())
        })
        .collect()
}

/// The part of convex `polygon` (corners with a flag per side from that corner: shared or not)
/// where `normal`·x ≤ `offset`; the new side along the line is shared (a bisector).
fn clip_polygon(polygon: &[(DVec2, bool)], normal: DVec2, offset: f64) -> Vec<(DVec2, bool)> {
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for k in 0..polygon.len() {
        let (a, side) = polygon[k];
        let b = polygon[(k + 1) % polygon.len()].0;
        let (sa, sb) = (normal.dot(a) - offset, normal.dot(b) - offset);
        let cut = || a + (b - a) * (sa / (sa - sb));
        if sa <= 0.0 {
            out.push((a, side));
            if sb > 0.0 {
                out.push((cut(), true));
            }
        } else if sb <= 0.0 {
            out.push((cut(), side));
        }
    }
    out
}

/// A cell from its clipped polygon: sides with outward normals, zero-length sides dropped.
fn cell_of(seed: DVec2, polygon: &[(DVec2, bool)]) -> Cell {
    let mut corners = Vec::new();
    let mut sides = Vec::new();
    for k in 0..polygon.len() {
        let (a, shared) = polygon[k];
        let b = polygon[(k + 1) % polygon.len()].0;
        let edge = b - a;
        if edge.length_squared() <= 1e-24 * a.length_squared().max(1e-30) {
            continue;
        }
        let normal = DVec2::new(edge.y, -edge.x).normalize();
        corners.push(a);
        sides.push(CellSide { normal, offset: normal.dot(a), shared });
    }
    Cell { seed, corners, sides }
}

/// Signed area of a polygon, positive counter-clockwise.
pub(crate) fn shoelace(corners: &[DVec2]) -> f64 {
    let n = corners.len();
    0.5 * (0..n).map(|k| corners[k].perp_dot(corners[(k + 1) % n])).sum::<f64>()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cells tile the bounding polygon: their areas sum to its area (to 1e-9 relative), and
    /// each cell holds its own seed.
    #[test]
    fn cells_tile_the_bound() {
        let pattern = FracturePattern::new(PatternParams { cells: 40, seed: 7, radius: 0.5 }).unwrap();
        let bound: Vec<DVec2> = bounding_polygon(0.5);
        let total: f64 = pattern.cells().iter().map(Cell::area).sum();
        assert!((total - shoelace(&bound)).abs() < 1e-9 * shoelace(&bound), "{total} vs {}", shoelace(&bound));
        for cell in pattern.cells() {
            assert!(cell.sides.iter().all(|s| s.normal.dot(cell.seed) <= s.offset + 1e-12));
        }
        assert_eq!(pattern.cells().len(), 40);
    }
}
