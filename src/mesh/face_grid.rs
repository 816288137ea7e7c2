//! Broad phase for face-against-face tests: a loose uniform grid over triangle bounding boxes
//! that lists each pair of faces whose boxes overlap once.
//!
//! Each box is binned once, in the cell of its low corner; a query for a box visits the cells
//! from its low corner less the largest binned box's size to its high corner, which hold every
//! binned box that can overlap it. Boxes much larger than the typical one (a long sliver, a big
//! face beside fine ones) do not make the cells coarse: they go up to a coarser level, a grid of
//! their own sized to them, and so on (a dented, refined surface mixes faces of many sizes, and
//! one list of them all scanned by every query made the broad phase quadratic); only the last
//! level's few largest boxes are scanned by every query.

use glam::{Vec3, Vec3A};
use rayon::prelude::*;

/// An axis-aligned box, world units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Aabb {
    pub(crate) min: Vec3,
    pub(crate) max: Vec3,
}

impl Aabb {
    /// The empty box (the identity of [`union`](Self::union)).
    pub(crate) const EMPTY: Self = Self { min: Vec3::INFINITY, max: Vec3::NEG_INFINITY };

    /// The box of some points.
    pub(crate) fn of(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, p| Self { min: b.min.min(p), max: b.max.max(p) })
    }

    pub(crate) fn union(self, other: Self) -> Self {
        Self { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    /// Closed overlap: boxes that only touch overlap (coplanar faces in an axis plane do).
    pub(crate) fn overlaps(&self, other: &Self) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    fn extent(&self) -> Vec3 {
        (self.max - self.min).max(Vec3::ZERO)
    }
}

/// A box as the grid files it: 16-byte lanes, so that an overlap test is two vector compares.
#[derive(Debug, Clone, Copy)]
struct LaneBox {
    min: Vec3A,
    max: Vec3A,
}

impl LaneBox {
    const EMPTY: Self = Self { min: Vec3A::INFINITY, max: Vec3A::NEG_INFINITY };

    fn of(b: &Aabb) -> Self {
        Self { min: b.min.into(), max: b.max.into() }
    }

    /// Closed overlap, as [`Aabb::overlaps`].
    #[inline]
    fn overlaps(&self, other: &Self) -> bool {
        (self.min.cmple(other.max) & other.min.cmple(self.max)).all()
    }
}

/// Cell side in mean box sizes: a box up to this size is binned, a larger one listed apart.
const CELL_IN_MEAN_BOXES: f32 = 1.0;
/// At most this many grid cells per binned box, so memory stays linear in the box count.
const CELLS_PER_BOX: usize = 2;
/// At most this many levels; the boxes too large for the last are scanned by every query.
const MAX_LEVELS: usize = 8;
/// Boxes too large for a level that are scanned by every query rather than given a level.
const SCANNED_BOXES: usize = 32;

/// Levels of grids from fine to coarse, each holding the boxes too large for the one before,
/// and the few boxes left over, with their boxes.
struct LooseGrid {
    levels: Vec<Level>,
    large: Vec<(u32, LaneBox)>,
}

impl LooseGrid {
    fn new(boxes: &[Aabb]) -> Self {
        let mut left: Vec<(u32, Aabb)> = boxes.iter().copied().zip(0..).map(|(b, k)| (k, b)).collect();
        let mut levels = Vec::new();
        while left.len() > SCANNED_BOXES && levels.len() < MAX_LEVELS {
            let (level, larger) = Level::new(&left);
            levels.push(level);
            left = larger;
        }
        Self { levels, large: left.iter().map(|(k, b)| (*k, LaneBox::of(b))).collect() }
    }

    /// Calls `visit(k)` for every box `k` that overlaps `b` (closed).
    fn for_overlapping(&self, b: &Aabb, mut visit: impl FnMut(u32)) {
        let lanes = LaneBox::of(b);
        for level in &self.levels {
            level.for_overlapping(b, &lanes, &mut visit);
        }
        self.large.iter().filter(|(_, item)| lanes.overlaps(item)).for_each(|(k, _)| visit(*k));
    }
}

/// One level: boxes binned by the cell of their low corner (compressed rows: `items[starts[c]..
/// starts[c + 1]]` are the boxes of cell `c`, `item_boxes` their boxes in the same order).
struct Level {
    origin: Vec3,
    inv_cell: f32,
    dims: [usize; 3],
    /// Largest extent of a binned box on each axis.
    reach: Vec3,
    starts: Vec<u32>,
    items: Vec<u32>,
    item_boxes: Vec<LaneBox>,
}

impl Level {
    /// A level for `boxes` (id and box each, at least one), and the boxes too large for its cells.
    /// Those are fewer: the cell is the mean box size, which not every box exceeds.
    fn new(boxes: &[(u32, Aabb)]) -> (Self, Vec<(u32, Aabb)>) {
        let bounds = boxes.iter().fold(Aabb::EMPTY, |b, (_, x)| b.union(*x));
        let extent = bounds.extent();
        let mean = boxes.iter().map(|(_, b)| b.extent().max_element()).sum::<f32>() / boxes.len().max(1) as f32;
        let mut cell = (CELL_IN_MEAN_BOXES * mean).max(extent.max_element() * 1e-6).max(f32::MIN_POSITIVE);
        let dims_for = |cell: f32| extent.to_array().map(|e| ((e / cell) as usize).saturating_add(1));
        let mut dims = dims_for(cell);
        let budget = CELLS_PER_BOX * boxes.len().max(1);
        while dims.iter().try_fold(1usize, |acc, &d| acc.checked_mul(d)).is_none_or(|n| n > budget) {
            cell *= 1.5;
            dims = dims_for(cell);
        }
        let mut grid = Self {
            origin: bounds.min,
            inv_cell: 1.0 / cell,
            dims,
            reach: Vec3::ZERO,
            starts: Vec::new(),
            items: Vec::new(),
            item_boxes: Vec::new(),
        };
        let mut larger = Vec::new();
        let mut cell_of_box = vec![u32::MAX; boxes.len()];
        let mut counts = vec![0u32; dims[0] * dims[1] * dims[2] + 1];
        for (k, (id, b)) in boxes.iter().enumerate() {
            let size = b.extent();
            if size.max_element() > cell {
                larger.push((*id, *b));
                continue;
            }
            grid.reach = grid.reach.max(size);
            let c = grid.linear(grid.cell_of(b.min));
            cell_of_box[k] = c as u32;
            counts[c] += 1;
        }
        let mut total = 0;
        for count in counts.iter_mut() {
            let here = *count;
            *count = total;
            total += here;
        }
        let mut fill = counts.clone();
        let mut items = vec![0u32; total as usize];
        let mut item_boxes = vec![LaneBox::EMPTY; total as usize];
        for (k, &c) in cell_of_box.iter().enumerate().filter(|(_, c)| **c != u32::MAX) {
            let slot = fill[c as usize] as usize;
            items[slot] = boxes[k].0;
            item_boxes[slot] = LaneBox::of(&boxes[k].1);
            fill[c as usize] += 1;
        }
        grid.starts = counts;
        grid.items = items;
        grid.item_boxes = item_boxes;
        (grid, larger)
    }

    /// Cell coordinates of a point, clamped into the grid (monotone in each coordinate).
    fn cell_of(&self, p: Vec3) -> [usize; 3] {
        let r = ((p - self.origin) * self.inv_cell).max(Vec3::ZERO);
        let [x, y, z] = self.dims;
        [(r.x as usize).min(x - 1), (r.y as usize).min(y - 1), (r.z as usize).min(z - 1)]
    }

    fn linear(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// Calls `visit(k)` for every box `k` binned here that overlaps `b` (closed; `lanes` is `b`).
    fn for_overlapping(&self, b: &Aabb, lanes: &LaneBox, visit: &mut impl FnMut(u32)) {
        // A binned box overlapping `b` has its low corner in [b.min − reach, b.max]. The reach is
        // widened by a few ulps of the magnitudes involved, so that neither the rounding of
        // `b.min − reach` nor that of the binned boxes' extents can leave a corner just outside.
        let margin = (b.min.abs() + self.reach) * (4.0 * f32::EPSILON);
        let (lo, hi) = (self.cell_of(b.min - self.reach - margin), self.cell_of(b.max));
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                let row = self.linear([0, y, z]);
                let range = self.starts[row + lo[0]] as usize..self.starts[row + hi[0] + 1] as usize;
                for (&k, item) in self.items[range.clone()].iter().zip(&self.item_boxes[range]) {
                    if lanes.overlaps(item) {
                        visit(k);
                    }
                }
            }
        }
    }
}

/// Every pair `(a, c)` of boxes with `a < active` (an active box) and any `c ≠ a` whose boxes
/// overlap (closed) and that `keep(a, c)` keeps, each unordered pair once. Pairs come back in
/// no particular order.
pub(crate) fn overlapping_pairs(
    boxes: &[Aabb],
    active: usize,
    keep: impl Fn(u32, u32) -> bool + Sync,
) -> Vec<(u32, u32)> {
    let active = active.min(boxes.len());
    if active == 0 || boxes.len() < 2 {
        return Vec::new();
    }
    let grid = LooseGrid::new(boxes);
    // A pair of two active boxes is reported from its smaller index only.
    let wanted = |a: u32, c: u32| c != a && (c as usize >= active || c > a);
    let visit = |found: &mut Vec<(u32, u32)>, a: u32| {
        grid.for_overlapping(&boxes[a as usize], |c| {
            if wanted(a, c) && keep(a, c) {
                found.push((a, c));
            }
        });
    };
    queried_in_chunks(active, |range| {
        let mut found = Vec::with_capacity(8 * range.len());
        range.for_each(|a| visit(&mut found, a));
        found
    })
}

/// Every pair `(l, r)` of a box of `left` and a box of `right` that overlap (closed) and that
/// `keep(l, r)` keeps, each once, in no particular order. `left` is binned and `right`
/// queried: the larger set should go left.
pub(crate) fn pairs_between(left: &[Aabb], right: &[Aabb], keep: impl Fn(u32, u32) -> bool + Sync) -> Vec<(u32, u32)> {
    if left.is_empty() || right.is_empty() {
        return Vec::new();
    }
    let grid = LooseGrid::new(left);
    queried_in_chunks(right.len(), |range| {
        let mut found = Vec::new();
        for r in range {
            grid.for_overlapping(&right[r as usize], |l| {
                if keep(l, r) {
                    found.push((l, r));
                }
            });
        }
        found
    })
}

/// `query(range)` over `0..count`, on one thread up to [`PARALLEL_QUERIES`], in chunks on the
/// pool beyond; the results concatenated.
fn queried_in_chunks(count: usize, query: impl Fn(std::ops::Range<u32>) -> Vec<(u32, u32)> + Sync) -> Vec<(u32, u32)> {
    if count <= PARALLEL_QUERIES {
        return query(0..count as u32);
    }
    let chunk = PARALLEL_QUERIES / 2;
    (0..count.div_ceil(chunk))
        .into_par_iter()
        .map(|k| query((k * chunk) as u32..((k + 1) * chunk).min(count) as u32))
        .flatten_iter()
        .collect()
}

/// Up to this many boxes are queried on one thread (waking the pool costs more: on a 2-core VM
/// the 1,800 queries of a 60° dent took 0.52 ms split over two threads and 0.34 ms on one).
const PARALLEL_QUERIES: usize = 8192;

#[cfg(test)]
mod tests {
    use super::*;

    /// Every overlapping pair with an active box, once, against the all-pairs answer, on random
    /// boxes of mixed sizes (some far larger than the rest) and on touching boxes.
    #[test]
    fn finds_every_overlapping_pair_once() {
        let mut next = crate::mesh::test_support::unit_floats(7);
        for round in 0..6 {
            let n = 300 + 200 * round;
            let boxes: Vec<Aabb> = (0..n)
                .map(|k| {
                    // Rounds 0–2: a few boxes far larger than the rest (one level and the
                    // scanned list); rounds 3–5: sizes spread over 10⁻³..3 (many levels).
                    let size = match (round < 3, k % 37 == 0) {
                        (true, true) => 3.0,
                        (true, false) => 0.02 + 0.2 * next(),
                        (false, _) => 10f32.powf(-3.0 + 3.5 * next()),
                    };
                    let min = Vec3::new(next(), next() * 0.3, next()) * 5.0;
                    Aabb { min, max: min + Vec3::new(next(), next(), next()) * size }
                })
                .collect();
            let active = n / 3;
            if round >= 3 {
                assert!(LooseGrid::new(&boxes).levels.len() >= 3, "round {round} takes several levels");
            }
            let mut found = overlapping_pairs(&boxes, active, |_, _| true);
            let count = found.len();
            found.iter_mut().for_each(|p| *p = (p.0.min(p.1), p.0.max(p.1)));
            found.sort_unstable();
            found.dedup();
            assert_eq!(found.len(), count, "a pair reported twice");
            let mut expected = Vec::new();
            for a in 0..n as u32 {
                for c in a + 1..n as u32 {
                    if ((a as usize) < active || (c as usize) < active)
                        && boxes[a as usize].overlaps(&boxes[c as usize])
                    {
                        expected.push((a, c));
                    }
                }
            }
            assert_eq!(found, expected, "round {round}");
            // A pair `keep` refuses is left out, and only those.
            let keep = |a: u32, c: u32| !(a + c).is_multiple_of(3);
            let mut kept = overlapping_pairs(&boxes, active, keep);
            kept.iter_mut().for_each(|p| *p = (p.0.min(p.1), p.0.max(p.1)));
            kept.sort_unstable();
            let expected_kept: Vec<(u32, u32)> = expected.iter().copied().filter(|&(a, c)| keep(a, c)).collect();
            assert_eq!(kept, expected_kept, "round {round}, kept");
            // Between the active boxes and the others: the same pairs less those of two active.
            let (left, right) = boxes.split_at(active);
            let mut between: Vec<(u32, u32)> =
                pairs_between(left, right, |_, _| true).into_iter().map(|(l, r)| (l, r + active as u32)).collect();
            let between_count = between.len();
            between.sort_unstable();
            between.dedup();
            assert_eq!(between.len(), between_count, "a pair reported twice");
            expected.retain(|&(_, c)| c as usize >= active);
            assert_eq!(between, expected, "round {round}, between");
        }
        // Boxes that only touch (a shared face of two grid cells) overlap.
        let boxes = [Aabb { min: Vec3::ZERO, max: Vec3::ONE }, Aabb { min: Vec3::X, max: Vec3::new(2.0, 1.0, 1.0) }];
        assert_eq!(overlapping_pairs(&boxes, 1, |_, _| true), vec![(0, 1)]);
        assert_eq!(overlapping_pairs(&boxes, 1, |_, _| false), vec![]);
    }
}
