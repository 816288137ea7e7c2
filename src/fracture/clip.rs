//! One cut of a closed indexed mesh by a plane: the faces inside (n·x < d) and outside, the cut
//! faces split at points shared by the two faces of each cut edge, and the cross-section capped
//! ([`super::cap`]) so the inside part is closed again. Vertices live in one growing pool, so
//! every part cut from it shares vertex ids with its neighbours.

use std::collections::HashMap;

use glam::{DVec2, DVec3};

use super::cap::{loops, triangulate};

/// A plane; the side kept by a cut is `normal`·x < `offset`. `normal` is unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Plane {
    pub normal: DVec3,
    pub offset: f64,
}

/// A face of a mesh under cutting: its vertex ids and whether it lies on a cutting plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Face {
    pub v: [u32; 3],
    pub cap: bool,
}

/// The vertex pool and every edge split so far (unordered pair → the vertex between them).
#[derive(Debug, Clone, Default)]
pub(crate) struct Pool {
    pub positions: Vec<DVec3>,
    pub splits: HashMap<(u32, u32), u32>,
}

/// The two sides of a cut.
#[derive(Debug, Default)]
pub(crate) struct Halves {
    /// Faces inside, cap included (closed when the input was).
    pub inside: Vec<Face>,
    /// Faces outside, without a cap.
    pub outside: Vec<Face>,
}

impl Pool {
    /// Cuts `faces` (a closed surface over this pool) by `plane`. The plane is moved along its
    /// normal by a few `tolerance` (m) when a vertex lies within `tolerance` of it, so that no
    /// vertex is on it and every crossing is clean.
    pub(crate) fn cut(&mut self, faces: &[Face], plane: Plane, tolerance: f64) -> Halves {
        let plane = self.clear_of_vertices(faces, plane, tolerance);
        // Signed distances of the pool's vertices as of now (cut points are made on the plane).
        let signed: Vec<f64> = self.positions.iter().map(|&p| plane.normal.dot(p) - plane.offset).collect();
        let mut halves = Halves::default();
        let mut cap_edges: Vec<(u32, u32)> = Vec::new();
        for face in faces {
            let s = face.v.map(|v| signed[v as usize]);
            let inside = s.map(|x| x < 0.0);
            match inside.iter().filter(|&&b| b).count() {
                3 => halves.inside.push(*face),
                0 => halves.outside.push(*face),
                count => {
                    // Rotate so that corner 0 is the one alone on its side.
                    let lone = (0..3).find(|&k| (inside[k]) == (count == 1)).unwrap_or(0);
                    let [a, b, c] = [0, 1, 2].map(|k| face.v[(lone + k) % 3]);
                    let [sa, sb, sc] = [0, 1, 2].map(|k| s[(lone + k) % 3]);
                    let ab = self.split(a, b, sa, sb);
                    let ca = self.split(c, a, sc, sa);
                    let make = |v: [u32; 3]| Face { v, cap: face.cap };
                    let (alone, pair) = (make([a, ab, ca]), [make([ab, b, c]), make([ab, c, ca])]);
                    if count == 1 {
                        halves.inside.push(alone);
                        halves.outside.extend(pair);
                        cap_edges.push((ca, ab));
                    } else {
                        halves.outside.push(alone);
                        halves.inside.extend(pair);
                        cap_edges.push((ab, ca));
                    }
                }
            }
        }
        let (u, v) = plane.normal.any_orthonormal_pair();
        let at = |id: u32| {
            let p = self.positions[id as usize];
            DVec2::new(u.dot(p), v.dot(p))
        };
        // u × v = n, so counter-clockwise in (u, v) faces +n: out of the inside part.
        let cap = triangulate(&loops(&cap_edges), &at);
        halves.inside.extend(cap.into_iter().map(|v| Face { v, cap: true }));
        halves
    }

    /// The vertex where edge (a, b) crosses the plane (signed distances `sa`, `sb` of opposite
    /// signs), made once per edge and computed from the lower id so both faces get the same.
    fn split(&mut self, a: u32, b: u32, sa: f64, sb: f64) -> u32 {
        let (lo, hi, slo, shi) = if a < b { (a, b, sa, sb) } else { (b, a, sb, sa) };
        if let Some(&v) = self.splits.get(&(lo, hi)) {
            return v;
        }
        let (p, q) = (self.positions[lo as usize], self.positions[hi as usize]);
        self.positions.push(p + (q - p) * (slo / (slo - shi)));
        let v = self.positions.len() as u32 - 1;
        self.splits.insert((lo, hi), v);
        v
    }

    /// `plane`, shifted along its normal until no vertex of `faces` is within `tolerance` of it.
    fn clear_of_vertices(&self, faces: &[Face], mut plane: Plane, tolerance: f64) -> Plane {
        for attempt in 1..=16 {
            let near = faces
                .iter()
                .flat_map(|f| f.v)
                .any(|v| (plane.normal.dot(self.positions[v as usize]) - plane.offset).abs() <= tolerance);
            if !near {
                break;
            }
            plane.offset += 3.0 * tolerance * f64::from(attempt);
        }
        plane
    }

    /// `face` with every edge that was split since it was made subdivided at the split vertex
    /// (recursively), so that it meets its neighbours without T-junctions.
    pub(crate) fn conform(&self, face: Face, out: &mut Vec<Face>) {
        let [a, b, c] = face.v;
        for (k, (p, q)) in [(a, b), (b, c), (c, a)].into_iter().enumerate() {
            if let Some(&m) = self.splits.get(&(p.min(q), p.max(q))) {
                let r = face.v[(k + 2) % 3];
                self.conform(Face { v: [p, m, r], cap: face.cap }, out);
                self.conform(Face { v: [m, q, r], cap: face.cap }, out);
                return;
            }
        }
        out.push(face);
    }
}
