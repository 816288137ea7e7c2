//! One cell's share of the broken part: the part cut by the cell's shared sides in order.
//! Most faces of the part lie far from a given cell, and the cuts would carry each of them
//! through every plane it lies well inside of until one it lies well outside of drops it. Such
//! a face is never split and never moves a plane (see [`Pool::cut`]: only vertices within a
//! few hundred tolerances of a plane can), so it is dropped before the first cut, and the cuts
//! make exactly what they would make from the whole part, bit for bit, with fewer faces.

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
        let count = base.len();
        let side = |plane: usize, v: u32| self.sides[plane * count + v as usize];
        // The faces some cut touches: all but those well inside every plane before one they lie
        // well outside of.
        self.next.faces.clear();
        self.next.faces.extend(broken.faces.iter().filter(|face| {
            for plane in 0..self.planes.len() {
                let corners = face.map(|v| side(plane, v));
                if corners == [Side::Out; 3] {
                    return false;
                }
                if corners != [Side::In; 3] {
                    return true;
                }
            }
            true
        }));
        self.next.caps.clone_from(&broken.caps);
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
