//! One cell's share of the broken part: the part cut by the cell's shared sides in order.
//! Most faces (and caps) of the part lie far from a given cell, and the cuts would carry each
//! of them through every plane it lies well inside of until one it lies well outside of drops
//! it. Such a face is never split and never moves a plane (see [`Pool::cut`]: only vertices
//! within a few hundred tolerances of a plane can), so it is dropped before the first cut, and
//! the cuts make exactly what they would make from the whole part, bit for bit, with fewer
//! faces.

use glam::DVec3;

use super::clip::{Part, Plane, Pool};

/// How far from a plane a vertex is out of reach of every shift of the plane (at most
/// 3·(1 + 2 + … + 16) = 408 tolerances) and of the tolerance around it, in tolerances, with
/// room to spare for rounding.
const REACH: f64 = 1000.0;

/// Where a vertex lies from a plane, beyond [`REACH`] or within it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    In,
    Near,
    Out,
}

/// What one thread reuses from cell to cell.
#[derive(Debug, Default)]
pub(crate) struct CellCutter {
    pool: Pool,
    part: Part,
    next: Part,
    planes: Vec<Plane>,
    /// The side of every vertex of the base from each plane, plane by plane.
    sides: Vec<Side>,
}

impl CellCutter {
    /// Cuts `broken` (over the vertices `base`) by `planes` in order, each cut moved off the
    /// vertices by `tolerance` (m) as [`Pool::cut`] does: the triangles of what is left, closed
    /// (its caps triangulated), over the vertices of the returned pool.
    pub(crate) fn cut(
        &mut self,
        base: &[DVec3],
        broken: &Part,
        planes: impl Iterator<Item = Plane>,
        tolerance: f64,
    ) -> (&Pool, Vec<[u32; 3]>) {
        self.pool.reset(base);
        self.planes.clear();
        self.planes.extend(planes);
        if self.planes.is_empty() {
            return (&self.pool, broken.triangulated(&self.pool));
        }
        self.classify(base, tolerance);
        let (sides, count, planes) = (&self.sides[..], base.len(), self.planes.len());
        self.next.faces.clear();
        self.next.faces.extend(broken.faces.iter().filter(|f| touched(sides, count, planes, f.iter().copied())));
        self.next.caps.clear();
        self.next.caps.extend(
            broken
                .caps
                .iter()
                .filter(|c| touched(sides, count, planes, c.edges.iter().flat_map(|e| [e.0, e.1])))
                .cloned(),
        );
        for &plane in &self.planes {
            self.pool.cut(&self.next, plane, tolerance, &mut self.part, None);
            std::mem::swap(&mut self.part, &mut self.next);
            if self.next.is_empty() {
                break;
            }
        }
        (&self.pool, self.next.triangulated(&self.pool))
    }

    /// Fills `sides` for every base vertex and plane.
    fn classify(&mut self, base: &[DVec3], tolerance: f64) {
        let reach = REACH * tolerance;
        self.sides.clear();
        for plane in &self.planes {
            self.sides.extend(base.iter().map(|&p| {
                let distance = plane.normal.dot(p) - plane.offset;
                if distance < -reach {
                    Side::In
                } else if distance > reach {
                    Side::Out
                } else {
                    Side::Near
                }
            }));
        }
    }
}

/// Whether a cut by the planes of `sides` (`count` vertices a plane) touches a face or cap with
/// these corners: not when they lie well inside every plane before one they all lie well outside
/// of (that cut drops it whole, and the ones before carry it unchanged).
fn touched(sides: &[Side], count: usize, planes: usize, corners: impl Iterator<Item = u32> + Clone) -> bool {
    for plane in 0..planes {
        let row = &sides[plane * count..(plane + 1) * count];
        let (mut all_in, mut all_out) = (true, true);
        for v in corners.clone() {
            match row[v as usize] {
                Side::In => all_out = false,
                Side::Out => all_in = false,
                Side::Near => return true,
            }
        }
        if all_out {
            return false;
        }
        if !all_in {
            return true;
        }
    }
    true
}
