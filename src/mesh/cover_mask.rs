//! A coarse occupancy mask: which cells of a grid laid over a region some boxes cover, and a
//! cheap test of whether another box may overlap one of them. It keeps a broad phase from
//! taking in everything inside one loose bounding box (the far side of a body under a dent,
//! the corners of a ring).

use glam::Vec3;

use super::face_grid::Aabb;

/// Cells along the region's longest axis (the others get as many as keep the cells cubic).
const CELLS_ALONG_LONGEST: f32 = 32.0;

/// Cells of a grid over a region, flagged where a box covers them.
pub(crate) struct CoverMask {
    region: Aabb,
    inv_cell: f32,
    dims: [usize; 3],
    covered: Vec<bool>,
}

impl CoverMask {
    /// A mask over the union of `boxes`, each of its cells flagged when one of them overlaps it.
    pub(crate) fn new(boxes: &[Aabb]) -> Self {
        let region = boxes.iter().fold(Aabb::EMPTY, |r, b| r.union(*b));
        let extent = (region.max - region.min).max(Vec3::ZERO);
        let cell = (extent.max_element() / CELLS_ALONG_LONGEST).max(f32::MIN_POSITIVE);
        let dims = extent.to_array().map(|e| ((e / cell) as usize).clamp(1, CELLS_ALONG_LONGEST as usize));
        let mut mask = Self { region, inv_cell: 1.0 / cell, dims, covered: vec![false; dims[0] * dims[1] * dims[2]] };
        for b in boxes {
            let (lo, hi) = (mask.cell_of(b.min), mask.cell_of(b.max));
            for z in lo[2]..=hi[2] {
                for y in lo[1]..=hi[1] {
                    let row = (z * dims[1] + y) * dims[0];
                    mask.covered[row + lo[0]..=row + hi[0]].fill(true);
                }
            }
        }
        mask
    }

    /// Whether `b` may overlap one of the boxes the mask was made from: `false` only when it
    /// overlaps none of them (closed overlap, as [`Aabb::overlaps`]).
    ///
    /// Sound because the cell of a point is monotone in each coordinate: a point common to `b`
    /// and a covering box lies in a cell of both boxes' cell ranges, which is flagged.
    pub(crate) fn may_overlap(&self, b: &Aabb) -> bool {
        if !b.overlaps(&self.region) {
            return false;
        }
        let (lo, hi) = (self.cell_of(b.min), self.cell_of(b.max));
        (lo[2]..=hi[2]).any(|z| {
            (lo[1]..=hi[1]).any(|y| {
                let row = (z * self.dims[1] + y) * self.dims[0];
                self.covered[row + lo[0]..=row + hi[0]].contains(&true)
            })
        })
    }

    /// Cell coordinates of a point, clamped into the grid (monotone in each coordinate).
    fn cell_of(&self, p: Vec3) -> [usize; 3] {
        let r = (p - self.region.min) * self.inv_cell;
        [0, 1, 2].map(|a| (r[a].max(0.0) as usize).min(self.dims[a] - 1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(min: Vec3, side: f32) -> Aabb {
        Aabb { min, max: min + Vec3::splat(side) }
    }

    #[test]
    fn a_box_between_two_far_covers_is_cleared_and_one_touching_a_cover_is_not() {
        // Two small boxes at the ends of a long diagonal: their union is one large loose box.
        let covers = [cube(Vec3::ZERO, 0.1), cube(Vec3::splat(10.0), 0.1)];
        let mask = CoverMask::new(&covers);
        assert!(!mask.may_overlap(&cube(Vec3::splat(5.0), 0.1)), "the empty middle of the region");
        assert!(!mask.may_overlap(&cube(Vec3::splat(20.0), 0.1)), "outside the region");
        // Touching a cover's corner only (closed overlap counts), and overlapping it.
        assert!(mask.may_overlap(&cube(Vec3::splat(0.1), 0.5)));
        assert!(mask.may_overlap(&cube(Vec3::splat(9.95), 0.01)));
        // Sound for random boxes: whenever a box overlaps a cover, the mask says it may.
        let mut next = crate::mesh::test_support::unit_floats(1);
        let covers: Vec<Aabb> =
            (0..40).map(|_| cube(Vec3::new(next(), next(), next()) * 3.0, 0.05 + 0.2 * next())).collect();
        let mask = CoverMask::new(&covers);
        let mut cleared = 0;
        for _ in 0..20_000 {
            let b = cube(Vec3::new(next(), next(), next()) * 3.2 - 0.1, 0.01 + 0.1 * next());
            if covers.iter().any(|c| c.overlaps(&b)) {
                assert!(mask.may_overlap(&b), "{b:?}");
            } else {
                cleared += usize::from(!mask.may_overlap(&b));
            }
        }
        assert!(cleared > 5_000, "the mask should clear most boxes far from every cover: {cleared}");
    }
}
