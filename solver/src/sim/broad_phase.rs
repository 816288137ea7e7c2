//! Broad phase: sweep and prune over world bounding boxes, giving the body pairs whose boxes
//! overlap. Sorting is O(n log n) and the sweep visits only boxes overlapping along the sweep
//! axis, so thousands of bodies cost milliseconds.

use glam::Vec3;
use rayon::prelude::*;

/// Boxes per parallel task of the sweep: enough work to outweigh rayon's scheduling.
const SWEEP_CHUNK: usize = 256;

/// An axis-aligned box, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Aabb {
    /// Whether the boxes overlap (touching counts).
    pub fn overlaps(&self, other: &Self) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }
}

/// Pairs `(i, j)`, `i < j`, of boxes that overlap, skipping pairs where `skip(i, j)` holds (two
/// static bodies, two sleeping ones). Sweeps along the axis of largest spread of box centres;
/// pairs come out sorted, so results do not depend on sorting ties.
pub(crate) fn overlapping_pairs(boxes: &[Aabb], skip: impl Fn(usize, usize) -> bool + Sync) -> Vec<(usize, usize)> {
    if boxes.len() < 2 {
        return Vec::new();
    }
    let axis = sweep_axis(boxes);
    // The boxes in sweep order, stored contiguously with their index: the inner loop reads
    // neighbours in memory order instead of through an index.
    let mut sorted: Vec<(Aabb, usize)> = boxes.iter().copied().zip(0..).collect();
    sorted.sort_unstable_by(|(a, i), (b, j)| a.min[axis].total_cmp(&b.min[axis]).then(i.cmp(j)));
    let (sorted, skip) = (&sorted, &skip);
    let mut pairs: Vec<(usize, usize)> = (0..sorted.len())
        .into_par_iter()
        .with_min_len(SWEEP_CHUNK)
        .flat_map_iter(|k| {
            let (first, i) = sorted[k];
            let reach = first.max[axis];
            sorted[k + 1..]
                .iter()
                .take_while(move |(other, _)| other.min[axis] <= reach)
                .filter(move |(other, _)| first.overlaps(other))
                .map(move |&(_, j)| (i.min(j), i.max(j)))
                .filter(move |&(a, b)| !skip(a, b))
        })
        .collect();
    pairs.par_sort_unstable();
    pairs
}

/// The axis (0, 1, 2) along which box centres spread most.
fn sweep_axis(boxes: &[Aabb]) -> usize {
    let n = boxes.len() as f32;
    let centres = boxes.iter().map(|b| 0.5 * (b.min + b.max));
    let mean = centres.clone().fold(Vec3::ZERO, |s, c| s + c) / n;
    // The first of equal spreads (x before y before z).
    centres.fold(Vec3::ZERO, |s, c| s + (c - mean) * (c - mean)).max_position()
}
