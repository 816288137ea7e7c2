//! One cut of a closed indexed solid by a plane. The solid is its surface triangles plus its
//! caps (planar faces made by earlier cuts), each cap kept as the directed edges of its boundary
//! until the end ([`Part::triangulated`]), so that a cap cut again is clipped as a polygon
//! instead of multiplying triangles. Cut faces split at points shared by the two faces of each
//! cut edge; where the plane crosses an earlier cap, the segment along the two planes' line
//! bounds both caps. Vertices live in one growing pool, so every part cut from it shares vertex
//! ids with its neighbours.

use std::collections::HashMap;

use glam::{DVec2, DVec3};

use super::cap::{loops, triangulate};

/// A plane; the side kept by a cut is `normal`·x < `offset`. `normal` is unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Plane {
    pub normal: DVec3,
    pub offset: f64,
}

/// A planar face made by a cut: its plane and its boundary, directed so that the face is on
/// the left seen from the plane's normal (outer loops counter-clockwise, holes clockwise).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Cap {
    pub plane: Plane,
    pub edges: Vec<(u32, u32)>,
}

/// A closed solid under cutting: surface triangles (counter-clockwise from outside) and caps.
#[derive(Debug, Clone, Default)]
pub(crate) struct Part {
    pub faces: Vec<[u32; 3]>,
    pub caps: Vec<Cap>,
}

/// The vertex pool and every edge split so far (unordered pair → the vertex between them).
#[derive(Debug, Clone, Default)]
pub(crate) struct Pool {
    pub positions: Vec<DVec3>,
    pub splits: HashMap<(u32, u32), u32>,
}

impl Part {
    /// Whether nothing is left.
    pub(crate) fn is_empty(&self) -> bool {
        self.faces.is_empty() && self.caps.is_empty()
    }

    /// The caps' triangles (each counter-clockwise seen from its plane's normal, so facing out
    /// of the part); they use only the caps' boundary vertices.
    pub(crate) fn cap_triangles(&self, pool: &Pool) -> Vec<[u32; 3]> {
        let mut out = Vec::new();
        for cap in &self.caps {
            let (u, v) = cap.plane.normal.any_orthonormal_pair();
            let at = |id: u32| {
                let p = pool.positions[id as usize];
                DVec2::new(u.dot(p), v.dot(p))
            };
            // u × v = n: counter-clockwise in (u, v) faces +n.
            out.extend(triangulate(&loops(&cap.edges), &at));
        }
        out
    }

    /// Every triangle of the closed surface: the faces, then the caps'.
    pub(crate) fn triangulated(&self, pool: &Pool) -> Vec<[u32; 3]> {
        let mut out = self.faces.clone();
        out.extend(self.cap_triangles(pool));
        out
    }
}

impl Pool {
    /// Cuts `part` by `plane`: the part inside (closed, with a new cap on the plane) and the
    /// surface faces outside (no cap). The plane is moved along its normal by a few `tolerance`
    /// (m) when a vertex lies within `tolerance` of it, so that no vertex is on it and every
    /// crossing is clean.
    pub(crate) fn cut(&mut self, part: &Part, plane: Plane, tolerance: f64) -> (Part, Vec<[u32; 3]>) {
        let plane = self.clear_of_vertices(part, plane, tolerance);
        // Signed distances of the part's vertices (cut points are made on the plane).
        let mut signed = vec![0.0f64; self.positions.len()];
        for &v in part.faces.iter().flatten().chain(part.caps.iter().flat_map(|c| c.edges.iter().map(|e| &e.0))) {
            signed[v as usize] = plane.normal.dot(self.positions[v as usize]) - plane.offset;
        }
        let inside_of = |v: u32| signed[v as usize] < 0.0;
        let mut inside = Part::default();
        let mut outside = Vec::new();
        let mut new_cap: Vec<(u32, u32)> = Vec::new();
        for face in &part.faces {
            let flags = face.map(inside_of);
            let count = flags.iter().filter(|&&b| b).count();
            match count {
                3 => inside.faces.push(*face),
                0 => outside.push(*face),
                _ => {
                    // Rotate so that corner 0 is the one alone on its side.
                    let lone = (0..3).find(|&k| flags[k] == (count == 1)).unwrap_or(0);
                    let [a, b, c] = [0, 1, 2].map(|k| face[(lone + k) % 3]);
                    let ab = self.split(a, b, &signed);
                    let ca = self.split(c, a, &signed);
                    let (alone, pair) = ([a, ab, ca], [[ab, b, c], [ab, c, ca]]);
                    if count == 1 {
                        inside.faces.push(alone);
                        outside.extend(pair);
                        new_cap.push((ca, ab));
                    } else {
                        outside.push(alone);
                        inside.faces.extend(pair);
                        new_cap.push((ab, ca));
                    }
                }
            }
        }
        for cap in &part.caps {
            let mut kept = Vec::with_capacity(cap.edges.len());
            // Where the boundary leaves (true) or enters (false) the inside half.
            let mut crossings: Vec<(u32, bool)> = Vec::new();
            for &(a, b) in &cap.edges {
                match (inside_of(a), inside_of(b)) {
                    (true, true) => kept.push((a, b)),
                    (false, false) => {}
                    (true, false) => {
                        let x = self.split(a, b, &signed);
                        kept.push((a, x));
                        crossings.push((x, true));
                    }
                    (false, true) => {
                        let x = self.split(a, b, &signed);
                        kept.push((x, b));
                        crossings.push((x, false));
                    }
                }
            }
            if kept.is_empty() {
                continue;
            }
            // Along d = n_cap × n, each exit is followed by an entry; the segment between
            // bounds the cap (this way) and the new cap (the other way).
            let d = cap.plane.normal.cross(plane.normal);
            crossings.sort_by(|x, y| {
                let t = |v: u32| self.positions[v as usize].dot(d);
                t(x.0).total_cmp(&t(y.0))
            });
            for pair in crossings.chunks(2) {
                if let [(exit, true), (entry, false)] = *pair {
                    kept.push((exit, entry));
                    new_cap.push((entry, exit));
                } else if let [(first, _), (second, _)] = *pair {
                    // Out of order within rounding (two crossings at one point): join them anyway.
                    kept.push((first, second));
                    new_cap.push((second, first));
                }
            }
            inside.caps.push(Cap { plane: cap.plane, edges: kept });
        }
        if !new_cap.is_empty() {
            inside.caps.push(Cap { plane, edges: new_cap });
        }
        (inside, outside)
    }

    /// The vertex where edge (a, b) crosses the plane of `signed` (distances of opposite signs),
    /// made once per edge and computed from the lower id so both faces get the same.
    fn split(&mut self, a: u32, b: u32, signed: &[f64]) -> u32 {
        let (lo, hi) = (a.min(b), a.max(b));
        if let Some(&v) = self.splits.get(&(lo, hi)) {
            return v;
        }
        let (slo, shi) = (signed[lo as usize], signed[hi as usize]);
        let (p, q) = (self.positions[lo as usize], self.positions[hi as usize]);
        self.positions.push(p + (q - p) * (slo / (slo - shi)));
        let v = self.positions.len() as u32 - 1;
        self.splits.insert((lo, hi), v);
        v
    }

    /// `plane`, shifted along its normal until no vertex of `part` is within `tolerance` of it.
    fn clear_of_vertices(&self, part: &Part, mut plane: Plane, tolerance: f64) -> Plane {
        let near =
            |plane: &Plane, v: u32| (plane.normal.dot(self.positions[v as usize]) - plane.offset).abs() <= tolerance;
        for attempt in 1..=16 {
            let faces = part.faces.iter().flatten();
            let caps = part.caps.iter().flat_map(|c| c.edges.iter().map(|e| &e.0));
            if !faces.chain(caps).any(|&v| near(&plane, v)) {
                break;
            }
            plane.offset += 3.0 * tolerance * f64::from(attempt);
        }
        plane
    }

    /// `face` with every edge that was split since it was made subdivided at the split vertex
    /// (recursively), so that it meets its neighbours without T-junctions.
    pub(crate) fn conform(&self, face: [u32; 3], out: &mut Vec<[u32; 3]>) {
        let [a, b, c] = face;
        for (k, (p, q)) in [(a, b), (b, c), (c, a)].into_iter().enumerate() {
            if let Some(&m) = self.splits.get(&(p.min(q), p.max(q))) {
                let r = face[(k + 2) % 3];
                self.conform([p, m, r], out);
                self.conform([m, q, r], out);
                return;
            }
        }
        out.push(face);
    }
}
