//! One cut of a closed indexed solid by a plane. The solid is its surface triangles plus its
//! caps (planar faces made by earlier cuts), each cap kept as the directed edges of its boundary
//! until the end ([`Part::triangulated`]), so that a cap cut again is clipped as a polygon
//! instead of multiplying triangles. Cut faces split at points shared by the two faces of each
//! cut edge; where the plane crosses an earlier cap, the segment along the two planes' line
//! bounds both caps. Vertices live in one growing pool, so every part cut from it shares vertex
//! ids with its neighbours.

use glam::{DVec2, DVec3};

use super::cap::{loops, triangulate};
use super::origin::{CAP, Location};
use super::split_table::SplitTable;

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

/// A closed solid under cutting: surface triangles (counter-clockwise from outside), each with
/// the welded input face it lies in (`from`, one per face), and caps.
#[derive(Debug, Clone, Default)]
pub(crate) struct Part {
    pub faces: Vec<[u32; 3]>,
    pub from: Vec<u32>,
    pub caps: Vec<Cap>,
}

/// The vertex pool (with each vertex's [`Location`] on the input), every edge split so far, and
/// scratch space that lets a cut measure the
/// part's vertices against its plane without allocating (kept from cut to cut).
#[derive(Debug, Clone, Default)]
pub(crate) struct Pool {
    pub positions: Vec<DVec3>,
    pub locations: Vec<Location>,
    pub splits: SplitTable,
    /// Per vertex: its signed distance to the current cut's plane, m, where `stamp` is `epoch`.
    signed: Vec<f64>,
    stamp: Vec<u32>,
    /// Numbers the cuts, so that stale entries of `signed` need no clearing.
    epoch: u32,
    /// The vertices the current cut measured: the part's face corners and cap edge starts.
    present: Vec<u32>,
    /// Where a cap's boundary crosses the current plane (see [`Pool::cut`]).
    crossings: Vec<(u32, bool)>,
}

impl Part {
    /// Whether nothing is left.
    pub(crate) fn is_empty(&self) -> bool {
        self.faces.is_empty() && self.caps.is_empty()
    }

    /// Appends the caps' triangles (each counter-clockwise seen from its plane's normal, so
    /// facing out of the part) to `faces`, and their origins (`CAP | k` for cap k) to `from`;
    /// they use only the caps' boundary vertices.
    pub(crate) fn cap_triangles(&self, pool: &Pool, faces: &mut Vec<[u32; 3]>, from: &mut Vec<u32>) {
        for (k, cap) in self.caps.iter().enumerate() {
            let (u, v) = cap.plane.normal.any_orthonormal_pair();
            let at = |id: u32| {
                let p = pool.positions[id as usize];
                DVec2::new(u.dot(p), v.dot(p))
            };
            // u × v = n: counter-clockwise in (u, v) faces +n.
            faces.extend(triangulate(&loops(&cap.edges), &at));
            from.resize(faces.len(), CAP | (k as u32));
        }
    }

    /// The caps' planes' unit normals (out of the part), in cap order.
    pub(crate) fn cap_normals(&self) -> Vec<DVec3> {
        self.caps.iter().map(|c| c.plane.normal).collect()
    }

    /// Every triangle of the closed surface, the faces then the caps', with their origins.
    pub(crate) fn triangulated(&self, pool: &Pool) -> (Vec<[u32; 3]>, Vec<u32>) {
        let (mut faces, mut from) = (self.faces.clone(), self.from.clone());
        self.cap_triangles(pool, &mut faces, &mut from);
        (faces, from)
    }
}

impl Pool {
    /// A pool of `positions` at `locations` with no split edge.
    pub(crate) fn new(positions: Vec<DVec3>, locations: Vec<Location>) -> Self {
        Self { positions, locations, ..Self::default() }
    }

    /// Starts over from `positions` at `locations` with no split edge, keeping the memory.
    pub(crate) fn reset(&mut self, positions: &[DVec3], locations: &[Location]) {
        self.positions.clear();
        self.positions.extend_from_slice(positions);
        self.locations.clear();
        self.locations.extend_from_slice(locations);
        self.splits.clear();
    }

    /// Cuts `part` by `plane` into `inside` (cleared first): the part inside, closed, with a new
    /// cap on the plane. The surface faces outside (no cap) are appended to `outside` when one is
    /// given, with their origins. The plane is moved along its normal by a few `tolerance` (m) when a vertex lies
    /// within `tolerance` of it, so that no vertex is on it and every crossing is clean.
    pub(crate) fn cut(
        &mut self,
        part: &Part,
        plane: Plane,
        tolerance: f64,
        inside: &mut Part,
        mut outside: Option<&mut Vec<([u32; 3], u32)>>,
    ) {
        let plane = self.measure(part, plane, tolerance);
        inside.faces.clear();
        inside.from.clear();
        inside.caps.clear();
        let signed = std::mem::take(&mut self.signed);
        let inside_of = |v: u32| signed[v as usize] < 0.0;
        let mut new_cap: Vec<(u32, u32)> = Vec::new();
        for (face, &origin) in part.faces.iter().zip(&part.from) {
            let flags = face.map(inside_of);
            let count = flags.iter().filter(|&&b| b).count();
            match count {
                3 => {
                    inside.faces.push(*face);
                    inside.from.push(origin);
                }
                0 => outside.iter_mut().for_each(|out| out.push((*face, origin))),
                _ => {
                    // Rotate so that corner 0 is the one alone on its side.
                    let lone = (0..3).find(|&k| flags[k] == (count == 1)).unwrap_or(0);
                    let [a, b, c] = [0, 1, 2].map(|k| face[(lone + k) % 3]);
                    let ab = self.split(a, b, &signed);
                    let ca = self.split(c, a, &signed);
                    let (alone, pair) = ([a, ab, ca], [[ab, b, c], [ab, c, ca]]);
                    if count == 1 {
                        inside.faces.push(alone);
                        inside.from.push(origin);
                        outside.iter_mut().for_each(|out| out.extend(pair.map(|f| (f, origin))));
                        new_cap.push((ca, ab));
                    } else {
                        outside.iter_mut().for_each(|out| out.push((alone, origin)));
                        inside.faces.extend(pair);
                        inside.from.extend([origin; 2]);
                        new_cap.push((ab, ca));
                    }
                }
            }
        }
        let mut crossings = std::mem::take(&mut self.crossings);
        for cap in &part.caps {
            let mut kept = Vec::with_capacity(cap.edges.len());
            // Where the boundary leaves (true) or enters (false) the inside half.
            crossings.clear();
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
        self.signed = signed;
        self.crossings = crossings;
    }

    /// `plane`, shifted along its normal until no vertex of `part` is within `tolerance` of it
    /// (at most 16 times), with `signed` then holding every vertex's signed distance to it: the
    /// part's face corners and cap edge starts, and 0 for a cap edge end that is neither.
    fn measure(&mut self, part: &Part, mut plane: Plane, tolerance: f64) -> Plane {
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.stamp.fill(0);
            self.epoch = 1;
        }
        let count = self.positions.len();
        if self.stamp.len() < count {
            self.stamp.resize(count, 0);
            self.signed.resize(count, 0.0);
        }
        self.present.clear();
        let (epoch, normal) = (self.epoch, plane.normal);
        let (stamp, signed, present, positions) =
            (&mut self.stamp, &mut self.signed, &mut self.present, &self.positions);
        let mut visit = |v: u32| {
            if stamp[v as usize] != epoch {
                stamp[v as usize] = epoch;
                signed[v as usize] = normal.dot(positions[v as usize]);
                present.push(v);
            }
        };
        // Plain loops: a flattened, chained iterator costs several times more here.
        for face in &part.faces {
            for &v in face {
                visit(v);
            }
        }
        for cap in &part.caps {
            for &(v, _) in &cap.edges {
                visit(v);
            }
        }
        // `signed` holds n·x here; the distance is n·x − offset, as the cut uses it below.
        let near = |offset: f64| self.present.iter().any(|&v| (self.signed[v as usize] - offset).abs() <= tolerance);
        for attempt in 1..=16 {
            if !near(plane.offset) {
                break;
            }
            plane.offset += 3.0 * tolerance * f64::from(attempt);
        }
        for &v in &self.present {
            self.signed[v as usize] -= plane.offset;
        }
        for &(_, b) in part.caps.iter().flat_map(|c| &c.edges) {
            if self.stamp[b as usize] != self.epoch {
                self.stamp[b as usize] = self.epoch;
                self.signed[b as usize] = 0.0;
            }
        }
        plane
    }

    /// The vertex where edge (a, b) crosses the plane of `signed` (distances of opposite signs),
    /// made once per edge and computed from the lower id so both faces get the same.
    fn split(&mut self, a: u32, b: u32, signed: &[f64]) -> u32 {
        let (lo, hi) = (a.min(b), a.max(b));
        if let Some(v) = self.splits.get(lo, hi) {
            return v;
        }
        let (slo, shi) = (signed[lo as usize], signed[hi as usize]);
        let (p, q) = (self.positions[lo as usize], self.positions[hi as usize]);
        self.positions.push(p + (q - p) * (slo / (slo - shi)));
        self.locations.push(Location::between(self.locations[lo as usize], self.locations[hi as usize]));
        let v = self.positions.len() as u32 - 1;
        self.splits.insert(lo, hi, v);
        v
    }

    /// `face` with every edge that was split since it was made subdivided at the split vertex
    /// (recursively), so that it meets its neighbours without T-junctions.
    pub(crate) fn conform(&self, face: [u32; 3], out: &mut Vec<[u32; 3]>) {
        let [a, b, c] = face;
        for (k, (p, q)) in [(a, b), (b, c), (c, a)].into_iter().enumerate() {
            if let Some(m) = self.splits.get(p.min(q), p.max(q)) {
                let r = face[(k + 2) % 3];
                self.conform([p, m, r], out);
                self.conform([m, q, r], out);
                return;
            }
        }
        out.push(face);
    }
}
