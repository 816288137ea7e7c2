//! Broad phase for face-against-face tests: a uniform grid over triangle bounding boxes that
//! lists each pair of faces whose boxes overlap once.

use glam::Vec3;
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
}

/// Faces binned into the grid cells their boxes cover (compressed rows: `items[starts[c]..
/// starts[c + 1]]` are the faces of cell `c`, and `item_boxes` their boxes, stored alongside so
/// that a query reads them in order).
struct FaceGrid {
    origin: Vec3,
    inv_cell: f32,
    dims: [usize; 3],
    starts: Vec<u32>,
    items: Vec<u32>,
    item_boxes: Vec<Aabb>,
}

/// At most this many grid cells per binned face, so memory stays linear in the face count.
const CELLS_PER_FACE: usize = 4;

impl FaceGrid {
    /// Bins `members` (indices into `boxes`), with cells about one mean box across.
    fn new(boxes: &[Aabb], members: &[u32]) -> Self {
        let bounds = members.iter().fold(Aabb::EMPTY, |b, &f| b.union(boxes[f as usize]));
        let extent = (bounds.max - bounds.min).max(Vec3::ZERO);
        let mean = members.iter().map(|&f| (boxes[f as usize].max - boxes[f as usize].min).max_element()).sum::<f32>()
            / members.len().max(1) as f32;
        let mut cell = mean.max(extent.max_element() * 1e-6).max(f32::MIN_POSITIVE);
        let dims_for = |cell: f32| extent.to_array().map(|e| ((e / cell) as usize).saturating_add(1));
        let mut dims = dims_for(cell);
        let budget = CELLS_PER_FACE * members.len().max(1);
        while dims.iter().try_fold(1usize, |acc, &d| acc.checked_mul(d)).is_none_or(|n| n > budget) {
            cell *= 1.5;
            dims = dims_for(cell);
        }
        let mut grid = Self {
            origin: bounds.min,
            inv_cell: 1.0 / cell,
            dims,
            starts: Vec::new(),
            items: Vec::new(),
            item_boxes: Vec::new(),
        };
        let mut counts = vec![0u32; dims[0] * dims[1] * dims[2] + 1];
        for &f in members {
            grid.for_cells(&boxes[f as usize], |c| counts[c] += 1);
        }
        let mut total = 0;
        for count in counts.iter_mut() {
            let here = *count;
            *count = total;
            total += here;
        }
        let mut fill = counts.clone();
        let mut items = vec![0u32; total as usize];
        let mut item_boxes = vec![Aabb::EMPTY; total as usize];
        for &f in members {
            grid.for_cells(&boxes[f as usize], |c| {
                items[fill[c] as usize] = f;
                item_boxes[fill[c] as usize] = boxes[f as usize];
                fill[c] += 1;
            });
        }
        grid.starts = counts;
        grid.items = items;
        grid.item_boxes = item_boxes;
        grid
    }

    /// Cell coordinates of a point, clamped into the grid.
    fn cell_of(&self, p: Vec3) -> [usize; 3] {
        let r = (p - self.origin) * self.inv_cell;
        [0, 1, 2].map(|a| (r[a].max(0.0) as usize).min(self.dims[a] - 1))
    }

    fn linear(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    fn for_cells(&self, b: &Aabb, mut visit: impl FnMut(usize)) {
        let (lo, hi) = (self.cell_of(b.min), self.cell_of(b.max));
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    visit(self.linear([x, y, z]));
                }
            }
        }
    }
}

/// Every pair `(a, c)` of a face `a` of `active` and a face `c` of `others` (indices into
/// `boxes`) whose boxes overlap, `a ≠ c`, each unordered pair once; `is_active[f]` flags the
/// faces of `active`. Pairs come back in no particular order.
pub(crate) fn overlapping_pairs(boxes: &[Aabb], active: &[u32], is_active: &[bool], others: &[u32]) -> Vec<(u32, u32)> {
    if active.is_empty() || others.is_empty() {
        return Vec::new();
    }
    let grid = FaceGrid::new(boxes, others);
    let visit = |found: &mut Vec<(u32, u32)>, a: u32| {
        let box_a = boxes[a as usize];
        grid.for_cells(&box_a, |cell| {
            let range = grid.starts[cell] as usize..grid.starts[cell + 1] as usize;
            for (&c, box_c) in grid.items[range.clone()].iter().zip(&grid.item_boxes[range]) {
                // Report the pair in one cell only: the one holding the overlap's low corner;
                // a pair of two active faces from its smaller index only.
                if box_a.overlaps(box_c)
                    && c != a
                    && !(c < a && is_active[c as usize])
                    && grid.linear(grid.cell_of(box_a.min.max(box_c.min))) == cell
                {
                    found.push((a, c));
                }
            }
        });
    };
    let run = |chunk: &[u32]| {
        let mut found = Vec::with_capacity(8 * chunk.len());
        chunk.iter().for_each(|&a| visit(&mut found, a));
        found
    };
    if active.len() <= PARALLEL_QUERIES {
        return run(active);
    }
    active.par_chunks(PARALLEL_QUERIES / 2).map(run).flatten_iter().collect()
}

/// Up to this many faces are queried on one thread (waking the pool costs more).
const PARALLEL_QUERIES: usize = 1024;
