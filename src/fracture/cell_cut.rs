//! One cell's share of the broken part: the part cut by the cell's shared sides in order.
//! Most faces (and caps) of the part lie far from a given cell, and the cuts would carry each
//! of them through every plane it lies well inside of until one it lies well outside of drops
//! it. Such a face is never split and never moves a plane (see [`Pool::cut`]: only vertices
//! within a few hundred tolerances of a plane can), so it is dropped before the first cut, and
//! the cuts make exactly what they would make from the whole part, bit for bit, with fewer
//! faces.

use glam::DVec3;

use super::clip::{Part, Plane, Pool};
use super::origin::Location;

/// How far from a plane a vertex is out of reach of every shift of the plane (at most
/// 3·(1 + 2 + … + 16) = 408 tolerances) and of the tolerance around it, in tolerances, with
/// room to spare for rounding.
const REACH: f64 = 1000.0;

/// What one thread reuses from cell to cell.
#[derive(Debug, Default)]
pub(crate) struct CellCutter {
    pool: Pool,
    part: Part,
    next: Part,
    planes: Vec<Plane>,
    /// Per base vertex, where the planes first leave it out of reach ([`fate`]).
    fates: Vec<u16>,
}

impl CellCutter {
    /// Cuts `broken` (over the vertices `base`, at `locations`) by `planes` in order, each cut
    /// moved off the vertices by `tolerance` (m) as [`Pool::cut`] does: the triangles of what
    /// is left, closed (its caps triangulated), over the vertices of the returned pool, their
    /// origins, and the outward unit normals of the caps they name.
    pub(crate) fn cut(
        &mut self,
        (base, locations): (&[DVec3], &[Location]),
        broken: &Part,
        planes: impl Iterator<Item = Plane>,
        tolerance: f64,
    ) -> (&Pool, Vec<[u32; 3]>, Vec<u32>, Vec<DVec3>) {
        self.pool.reset(base, locations);
        self.planes.clear();
        self.planes.extend(planes);
        if self.planes.is_empty() {
            let (faces, from) = broken.triangulated(&self.pool);
            return (&self.pool, faces, from, broken.cap_normals());
        }
        let reach = REACH * tolerance;
        self.fates.clear();
        self.fates.extend(base.iter().map(|&p| fate(&self.planes, p, reach)));
        let fates = &self.fates;
        // A face or cap is dropped untouched when all its corners have the same fate, and it is
        // to lie well outside a plane (odd).
        let untouched = |mut corners: std::slice::Iter<'_, u32>| {
            let first = corners.next().map_or(1, |&v| fates[v as usize]);
            first % 2 == 1 && corners.all(|&v| fates[v as usize] == first)
        };
        self.next.faces.clear();
        self.next.from.clear();
        for (face, &origin) in broken.faces.iter().zip(&broken.from) {
            if !untouched(face.iter()) {
                self.next.faces.push(*face);
                self.next.from.push(origin);
            }
        }
        self.next.caps.clear();
        for cap in &broken.caps {
            let corners: Vec<u32> = cap.edges.iter().flat_map(|e| [e.0, e.1]).collect();
            if !untouched(corners.iter()) {
                self.next.caps.push(cap.clone());
            }
        }
        for &plane in &self.planes {
            self.pool.cut(&self.next, plane, tolerance, &mut self.part, None);
            std::mem::swap(&mut self.part, &mut self.next);
            if self.next.is_empty() {
                break;
            }
        }
        let (faces, from) = self.next.triangulated(&self.pool);
        (&self.pool, faces, from, self.next.cap_normals())
    }
}

/// Where `planes` (in order) first leave the point `p` out of [`REACH`] (`reach`, m) inside:
/// 2·k when `p` lies within reach of plane k, 2·k + 1 when it lies well outside it, 2·n when
/// it lies well inside all n. A face (or cap) whose corners all have the same odd fate 2·k + 1
/// lies well inside every plane before k and well outside k: cut k drops it whole, and the
/// cuts before carry it unchanged. Any other face is touched by some cut (or kept whole).
fn fate(planes: &[Plane], p: DVec3, reach: f64) -> u16 {
    for (k, plane) in planes.iter().enumerate() {
        let distance = plane.normal.dot(p) - plane.offset;
        if distance >= -reach {
            return 2 * k as u16 + u16::from(distance > reach);
        }
    }
    2 * planes.len() as u16
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::fracture::weld::{Soup, weld};

    /// The closed triangles a cut sequence leaves, as their corners' coordinate bits.
    fn corners(pool: &Pool, faces: &[[u32; 3]]) -> Vec<[[u64; 3]; 3]> {
        faces.iter().map(|f| f.map(|v| pool.positions[v as usize].to_array().map(f64::to_bits))).collect()
    }

    /// Skipping the faces no cut touches changes nothing: on a 1,200-triangle slab, cut by
    /// plane sequences that pass through rows of vertices (so that cuts shift) and across
    /// them, the cutter leaves the same triangles, bit for bit, as cutting the whole slab.
    #[test]
    fn skipping_untouched_faces_changes_no_bit() {
        let slab = crate::mesh::subdivided_box(Vec3::new(3.0, 2.0, 0.2), [30, 20, 1]).unwrap();
        let soup = weld(&slab);
        let locations = soup.locations();
        let Soup { positions, faces, input_face, .. } = soup;
        let whole = Part { faces, from: input_face, caps: Vec::new() };
        let tolerance = 3e-6;
        let plane = |x: f64, y: f64, offset: f64| {
            let normal = DVec3::new(x, y, 0.0).normalize();
            Plane { normal, offset }
        };
        let sequences = [
            vec![plane(1.0, 0.0, 0.3), plane(-1.0, 0.0, 0.1), plane(0.0, 1.0, 0.2), plane(0.0, -1.0, 0.4)],
            vec![plane(0.6, 0.8, 0.25), plane(-0.8, 0.6, 0.3), plane(-0.6, -0.8, 0.0), plane(1.0, 0.0, 0.5)],
            vec![plane(1.0, 1.0, 0.0), plane(-1.0, 0.2, 0.7), plane(0.1, -1.0, 0.35)],
        ];
        let mut cutter = CellCutter::default();
        for planes in sequences {
            let mut pool = Pool::new(positions.clone(), locations.clone());
            let mut part = whole.clone();
            for &p in &planes {
                let mut next = Part::default();
                pool.cut(&part, p, tolerance, &mut next, None);
                part = next;
            }
            let (expected_faces, expected_from) = part.triangulated(&pool);
            let expected = corners(&pool, &expected_faces);
            assert!(!expected.is_empty());
            let (pool, faces, from, _) =
                cutter.cut((&positions, &locations), &whole, planes.iter().copied(), tolerance);
            assert_eq!(corners(pool, &faces), expected);
            assert_eq!(from, expected_from);
        }
    }
}
