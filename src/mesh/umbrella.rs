//! Umbrella certificates: a cheap proof that no two faces around a vertex cross.
//!
//! The faces around a vertex `a` (its umbrella) are certified when they form one closed fan
//! (each rim edge `b → c` of a face `(a, b, c)` continues into the next face, and the chain
//! closes after visiting every face once) whose projection onto the plane normal to their
//! summed area normal `n` is embedded: every face is wound counter-clockwise about `n` (by a
//! margin), so each covers a sector of angle in `(0, π)` around `a`, and those sectors go around
//! once (the winding number, counted as the sectors holding a reference direction, is 1).
//!
//! Then the sectors tile the plane around `a` once, so two faces of the umbrella project onto
//! triangles that meet only along their common ray (consecutive faces: their shared edge) or at
//! `a` itself. As the projection is one-to-one on each face, the faces themselves meet only
//! there: they touch and do not cross, which is what [`triangles_cross`] decides too. A pair of
//! faces sharing a certified vertex needs no exact test.
//!
//! [`triangles_cross`]: super::tri_tri::triangles_cross

use std::sync::atomic::{AtomicU8, Ordering};

use glam::{DVec3, Vec3};

use super::local_vertices::LocalVertices;

/// A face counts as wound about `n` when `(b − a)×(c − a)·n̂ > ORIENTATION_MARGIN·|b − a|·|c − a|`
/// (its plane tilts less than about 89.99994° from the projection plane).
const ORIENTATION_MARGIN: f64 = 1e-6;
/// A rim direction within this relative distance of the reference direction leaves the
/// winding count undecided (the vertex is not certified).
const REFERENCE_MARGIN: f64 = 1e-9;
/// Umbrellas with more faces than this are not certified (they are rare; the exact tests
/// handle them).
const MAX_FAN: usize = 32;

/// The umbrellas around the corners of some faces, each certified (module documentation) the
/// first time it is asked about, on whichever thread asks.
pub(crate) struct Umbrellas<'a> {
    positions: &'a [Vec3],
    faces: &'a [[u32; 3]],
    /// The corners asked about, numbered locally.
    local: LocalVertices,
    /// Faces around each corner, compressed rows: `fans[starts[k]..starts[k + 1]]`.
    starts: Vec<u32>,
    fans: Vec<u32>,
    /// Per corner: [`UNKNOWN`], [`OPEN`] (not certified) or [`CERTIFIED`].
    verdicts: Vec<AtomicU8>,
}

const UNKNOWN: u8 = 0;
const OPEN: u8 = 1;
const CERTIFIED: u8 = 2;

impl<'a> Umbrellas<'a> {
    /// The umbrellas of the corners of the faces `owners`; `around` must list every face of
    /// `faces` that uses one of them (it may list others). Nothing is certified yet.
    pub(crate) fn new(positions: &'a [Vec3], faces: &'a [[u32; 3]], owners: &[u32], around: &[u32]) -> Self {
        let mut local = LocalVertices::new(positions.len());
        local.add_corners(faces, owners);
        let corners = local.len();
        let mut starts = vec![0u32; corners + 1];
        let rows = |f: u32| faces[f as usize].into_iter().filter_map(|v| local.get(v));
        around.iter().flat_map(|&f| rows(f)).for_each(|k| starts[k + 1] += 1);
        for k in 0..corners {
            starts[k + 1] += starts[k];
        }
        let mut fill = starts.clone();
        let mut fans = vec![0u32; starts[corners] as usize];
        for &f in around {
            for k in rows(f) {
                fans[fill[k] as usize] = f;
                fill[k] += 1;
            }
        }
        let verdicts = (0..corners).map(|_| AtomicU8::new(UNKNOWN)).collect();
        Self { positions, faces, local, starts, fans, verdicts }
    }

    /// Whether the umbrella of `v` is certified; `false` for a vertex that is not a corner of
    /// the faces the umbrellas were made for.
    pub(crate) fn certified(&self, v: u32) -> bool {
        let Some(k) = self.local.get(v) else {
            return false;
        };
        match self.verdicts[k].load(Ordering::Relaxed) {
            UNKNOWN => {
                let fan = &self.fans[self.starts[k] as usize..self.starts[k + 1] as usize];
                let embedded = fan_is_embedded(self.positions, self.faces, v, fan);
                self.verdicts[k].store(if embedded { CERTIFIED } else { OPEN }, Ordering::Relaxed);
                embedded
            }
            verdict => verdict == CERTIFIED,
        }
    }

    /// Whether faces `f` and `g` share a vertex whose umbrella is certified: then they touch
    /// there and do not cross.
    pub(crate) fn only_touch(&self, f: u32, g: u32) -> bool {
        let q = self.faces[g as usize];
        self.faces[f as usize].iter().any(|v| q.contains(v) && self.certified(*v))
    }
}

/// Whether the faces `fan` (all the faces around `a`) form a closed fan whose projection is
/// embedded (module documentation).
fn fan_is_embedded(positions: &[Vec3], faces: &[[u32; 3]], a: u32, fan: &[u32]) -> bool {
    if fan.len() < 3 || fan.len() > MAX_FAN {
        return false;
    }
    // Each face's rim edge b → c, with the face turned so that it reads (a, b, c).
    let mut rim = [(0u32, 0u32); MAX_FAN];
    for (slot, &f) in rim.iter_mut().zip(fan) {
        let [x, y, z] = faces[f as usize];
        let edge = if x == a {
            (y, z)
        } else if y == a {
            (z, x)
        } else {
            (x, y)
        };
        if edge.0 == a || edge.1 == a || edge.0 == edge.1 {
            return false;
        }
        *slot = edge;
    }
    let rim = &rim[..fan.len()];
    // Put the rim in cycle order: each edge starts where the previous one ends, once around.
    let count = rim.len();
    let mut ring = [0u32; MAX_FAN];
    ring[0] = rim[0].0;
    let mut current = rim[0];
    for slot in ring.iter_mut().take(count).skip(1) {
        *slot = current.1;
        let mut next = rim.iter().filter(|e| e.0 == current.1);
        match (next.next(), next.next()) {
            (Some(&e), None) => current = e,
            _ => return false,
        }
    }
    let ring = &ring[..count];
    // Closed, and every rim vertex once: a chain that closed early would repeat one.
    if current.1 != ring[0] || ring.iter().enumerate().any(|(i, v)| ring[..i].contains(v)) {
        return false;
    }
    let origin = positions[a as usize].as_dvec3();
    let mut arms = [DVec3::ZERO; MAX_FAN];
    arms.iter_mut().zip(ring).for_each(|(arm, &v)| *arm = positions[v as usize].as_dvec3() - origin);
    let arms = &arms[..count];
    let normal = (0..arms.len()).map(|k| arms[k].cross(arms[(k + 1) % arms.len()])).sum::<DVec3>();
    let Some(n) = normal.try_normalize() else {
        return false;
    };
    let wound = (0..arms.len()).all(|k| {
        let (u, w) = (arms[k], arms[(k + 1) % arms.len()]);
        u.cross(w).dot(n) > ORIENTATION_MARGIN * u.length() * w.length()
    });
    if !wound {
        return false;
    }
    // The reference direction: the bisector of the first sector, in the projection plane.
    let flat = |u: DVec3| (u - n * u.dot(n)).try_normalize();
    let (Some(first), Some(second)) = (flat(arms[0]), flat(arms[1])) else {
        return false;
    };
    let reference = first + second;
    let side = |u: DVec3| u.cross(reference).dot(n);
    let mut holding = 0;
    for k in 0..arms.len() {
        let (u, w) = (arms[k], arms[(k + 1) % arms.len()]);
        let s = side(u);
        if s.abs() <= REFERENCE_MARGIN * u.length() * reference.length() && u.dot(reference) > 0.0 {
            return false;
        }
        // Sector k (from u to w, counter-clockwise, under π) holds the reference direction.
        if s > 0.0 && -side(w) > 0.0 {
            holding += 1;
        }
    }
    holding == 1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tri_tri::triangles_cross;

    fn fan_faces(n: u32) -> Vec<[u32; 3]> {
        (0..n).map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect()
    }

    fn ring(n: u32, turns: f32, lift: impl Fn(f32) -> f32) -> Vec<Vec3> {
        let mut p = vec![Vec3::ZERO];
        p.extend((0..n).map(|k| {
            let t = turns * std::f32::consts::TAU * k as f32 / n as f32;
            Vec3::new(t.cos(), lift(t), t.sin())
        }));
        p
    }

    fn certified(positions: &[Vec3], faces: &[[u32; 3]]) -> bool {
        let around: Vec<u32> = (0..faces.len() as u32).collect();
        Umbrellas::new(positions, faces, &around, &around).certified(0)
    }

    #[test]
    fn flat_and_wavy_fans_are_certified_in_either_winding() {
        for n in [3, 6, 7, 12] {
            let faces = fan_faces(n);
            assert!(certified(&ring(n, 1.0, |_| 0.0), &faces), "flat fan of {n}");
            assert!(certified(&ring(n, 1.0, |t| 0.3 * (3.0 * t).sin()), &faces), "wavy fan of {n}");
            // A cone, seen from below or above: the normal is their sum, so both windings pass.
            let reversed: Vec<[u32; 3]> = faces.iter().map(|&[a, b, c]| [a, c, b]).collect();
            assert!(certified(&ring(n, 1.0, |_| -0.8), &reversed), "cone of {n}");
        }
    }

    #[test]
    fn fans_that_wind_twice_fold_or_are_open_are_not_certified() {
        // Twelve faces going twice around (each pair of faces six apart overlaps).
        let faces = fan_faces(12);
        let twice = ring(12, 2.0, |t| 0.01 * t);
        assert!(!certified(&twice, &faces));
        // One face folded back over its neighbour.
        let mut folded = ring(6, 1.0, |_| 0.0);
        folded[2] = Vec3::new(0.9, 0.01, -0.3);
        assert!(!certified(&folded, &fan_faces(6)));
        // An open fan (a boundary vertex), and a closed fan with one face missing from `around`.
        let open: Vec<[u32; 3]> = fan_faces(6).into_iter().take(5).collect();
        assert!(!certified(&ring(6, 1.0, |_| 0.0), &open));
        let flat = ring(6, 1.0, |_| 0.0);
        let all = fan_faces(6);
        let listed: Vec<u32> = (0..5).collect();
        assert!(!Umbrellas::new(&flat, &all, &[0], &listed).certified(0));
        let every: Vec<u32> = (0..6).collect();
        assert!(Umbrellas::new(&flat, &all, &[0], &every).certified(0));
        // A vertex that is no corner of the faces asked about is not certified.
        assert!(!Umbrellas::new(&flat, &all, &[], &every).certified(0));
    }

    /// Wherever a vertex is certified, no two faces around it cross by the exact test: random
    /// fans, smooth and crumpled.
    #[test]
    fn no_certified_fan_has_crossing_faces() {
        let mut next = crate::mesh::test_support::centred_floats(11);
        let (mut checked, mut crossing_seen) = (0, 0);
        for round in 0..4000 {
            let n = 3 + round % 9;
            let faces = fan_faces(n);
            let jitter = if round % 2 == 0 { 0.2 } else { 2.0 };
            let mut p = ring(n, 1.0, |_| 0.0);
            p.iter_mut().skip(1).for_each(|q| *q += Vec3::new(next(), next(), next()) * jitter);
            let to_d = |f: &[u32; 3]| f.map(|v| p[v as usize].as_dvec3());
            let crossing = (0..faces.len())
                .any(|i| (i + 1..faces.len()).any(|j| triangles_cross(to_d(&faces[i]), to_d(&faces[j]))));
            crossing_seen += usize::from(crossing);
            if certified(&p, &faces) {
                checked += 1;
                assert!(!crossing, "round {round}: certified fan with crossing faces: {p:?}");
            }
        }
        assert!(checked > 1000 && crossing_seen > 100, "{checked} certified, {crossing_seen} crossing");
    }
}
