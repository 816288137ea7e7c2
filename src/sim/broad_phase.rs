//! Broad phase: sweep and prune over world bounding boxes, giving the body pairs whose boxes
//! overlap. Sorting is O(n log n) and the sweep visits only boxes overlapping along the sweep
//! axis, so thousands of bodies cost milliseconds.

use glam::Vec3;

/// An axis-aligned box, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
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
pub fn overlapping_pairs(boxes: &[Aabb], skip: impl Fn(usize, usize) -> bool) -> Vec<(usize, usize)> {
    if boxes.len() < 2 {
        return Vec::new();
    }
    let axis = sweep_axis(boxes);
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_unstable_by(|&a, &b| boxes[a].min[axis].total_cmp(&boxes[b].min[axis]).then(a.cmp(&b)));
    let mut pairs = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        let reach = boxes[i].max[axis];
        for &j in &order[k + 1..] {
            if boxes[j].min[axis] > reach {
                break;
            }
            if boxes[i].overlaps(&boxes[j]) && !skip(i.min(j), i.max(j)) {
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

/// The axis (0, 1, 2) along which box centres spread most.
fn sweep_axis(boxes: &[Aabb]) -> usize {
    let n = boxes.len() as f32;
    let centres = boxes.iter().map(|b| 0.5 * (b.min + b.max));
    let mean = centres.clone().fold(Vec3::ZERO, |s, c| s + c) / n;
    let spread = centres.fold(Vec3::ZERO, |s, c| s + (c - mean) * (c - mean));
    if spread.x >= spread.y && spread.x >= spread.z {
        0
    } else if spread.y >= spread.z {
        1
    } else {
        2
    }
}
