//! The `arm` scene's body: one closed tube swept along a smooth centreline (a thick torso that
//! narrows into a long arm), and a chain of bones laid along the same centreline.

use glam::{Quat, Vec3};

use dentbend::bend::BoneDesc;
use dentbend::mesh::{MeshError, TriMesh};

/// A smooth curve as a dense polyline with its arclengths.
#[derive(Debug, Clone)]
pub(super) struct Centreline {
    points: Vec<Vec3>,
    /// Arclength from the first point to each point, m.
    lengths: Vec<f32>,
}

impl Centreline {
    /// The polyline `corners` (at least two points, m) with its corners cut `rounds` times
    /// (Chaikin: each segment keeps its middle half), keeping both ends: a curve tangent to the
    /// polyline's segments with rounded corners.
    pub fn smoothed(corners: &[Vec3], rounds: usize) -> Self {
        let mut points = corners.to_vec();
        for _ in 0..rounds {
            let mut cut = Vec::with_capacity(2 * points.len());
            cut.push(points[0]);
            for pair in points.windows(2) {
                cut.push(pair[0].lerp(pair[1], 0.25));
                cut.push(pair[0].lerp(pair[1], 0.75));
            }
            cut.push(points[points.len() - 1]);
            points = cut;
        }
        let mut lengths = vec![0.0];
        for pair in points.windows(2) {
            lengths.push(lengths[lengths.len() - 1] + pair[0].distance(pair[1]));
        }
        Self { points, lengths }
    }

    /// Total length, m.
    pub fn length(&self) -> f32 {
        self.lengths[self.lengths.len() - 1]
    }

    /// The segment holding arclength `s` (clamped to the curve) and the fraction along it.
    fn locate(&self, s: f32) -> (usize, f32) {
        let s = s.clamp(0.0, self.length());
        let k = self.lengths.partition_point(|&l| l <= s).clamp(1, self.points.len() - 1) - 1;
        let span = self.lengths[k + 1] - self.lengths[k];
        (k, if span > 0.0 { (s - self.lengths[k]) / span } else { 0.0 })
    }

    /// The point at arclength `s`, m.
    pub fn at(&self, s: f32) -> Vec3 {
        let (k, t) = self.locate(s);
        self.points[k].lerp(self.points[k + 1], t)
    }

    /// The unit tangent at arclength `s` (direction of the segment holding it).
    pub fn tangent(&self, s: f32) -> Vec3 {
        let (k, _) = self.locate(s);
        (self.points[k + 1] - self.points[k]).normalize_or(Vec3::X)
    }

    /// A chain of bones between the points at arclengths `knots` (ascending, m): bone k runs
    /// from knot k to knot k + 1 and hangs from bone k − 1.
    pub fn bones(&self, knots: &[f32]) -> Vec<BoneDesc> {
        knots
            .windows(2)
            .enumerate()
            .map(|(k, pair)| BoneDesc::new(self.at(pair[0]), self.at(pair[1]), k.checked_sub(1)))
            .collect()
    }
}

/// A closed tube around `line`: `rings` rings of `around` vertices evenly spaced along it, ring
/// radius `radius(s)` at arclength s (m, > 0), and a hemispherical cap of `around / 4` rings at
/// each end. Wound counter-clockwise seen from outside. The rings' frames are transported along
/// the curve (each turned by the least rotation between successive tangents), so the tube does
/// not twist.
///
/// # Errors
/// [`MeshError::InvalidParameter`] for fewer than 2 rings or 3 vertices around, or a radius
/// that is not finite and positive.
pub(super) fn tube(
    line: &Centreline,
    radius: impl Fn(f32) -> f32,
    rings: usize,
    around: usize,
) -> Result<TriMesh, MeshError> {
    if rings < 2 || around < 3 {
        return Err(MeshError::InvalidParameter(format!("a tube needs 2 rings of 3 vertices, got {rings} × {around}")));
    }
    // (centre, tangent, normal, radius) of every ring along the axis, caps included.
    let mut frames = Vec::with_capacity(rings + around / 2 + 2);
    let mut normal = line.tangent(0.0).any_orthonormal_vector();
    let mut previous = line.tangent(0.0);
    for i in 0..rings {
        let s = line.length() * i as f32 / (rings - 1) as f32;
        let tangent = line.tangent(s);
        normal = (Quat::from_rotation_arc(previous, tangent) * normal).reject_from(tangent).normalize();
        previous = tangent;
        let r = radius(s);
        if !(r.is_finite() && r > 0.0) {
            return Err(MeshError::InvalidParameter(format!("tube radius at {s} m must be finite and > 0, got {r}")));
        }
        frames.push((line.at(s), tangent, normal, r));
    }
    let cap_rings = (around / 4).max(2);
    let cap = |&(centre, tangent, normal, r): &(Vec3, Vec3, Vec3, f32), k: usize, outward: f32| {
        let angle = std::f32::consts::FRAC_PI_2 * k as f32 / cap_rings as f32;
        (centre + outward * r * angle.sin() * tangent, tangent, normal, r * angle.cos())
    };
    let (first, last) = (frames[0], frames[rings - 1]);
    let start: Vec<_> = (1..cap_rings).rev().map(|k| cap(&first, k, -1.0)).collect();
    let end: Vec<_> = (1..cap_rings).map(|k| cap(&last, k, 1.0)).collect();
    let frames: Vec<_> = start.into_iter().chain(frames).chain(end).collect();

    let mut positions = vec![first.0 - first.1 * first.3];
    for &(centre, tangent, normal, r) in &frames {
        let binormal = tangent.cross(normal);
        positions.extend((0..around).map(|j| {
            let phi = std::f32::consts::TAU * j as f32 / around as f32;
            centre + r * (phi.cos() * normal + phi.sin() * binormal)
        }));
    }
    positions.push(last.0 + last.1 * last.3);
    let end_pole = (positions.len() - 1) as u32;
    let vertex = |ring: usize, j: usize| (1 + ring * around + j % around) as u32;
    let mut faces = Vec::with_capacity(2 * around * (frames.len() + 1));
    for j in 0..around {
        faces.push([0, vertex(0, j + 1), vertex(0, j)]);
        let top = frames.len() - 1;
        faces.push([vertex(top, j), vertex(top, j + 1), end_pole]);
        for ring in 0..top {
            let (a, b) = (vertex(ring, j), vertex(ring, j + 1));
            let (c, d) = (vertex(ring + 1, j + 1), vertex(ring + 1, j));
            faces.extend([[a, b, c], [a, c, d]]);
        }
    }
    TriMesh::new(positions, faces)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight tube of radius 0.1 along 1 m: closed (volume of the cylinder plus a sphere's,
    /// less the polygon's shortfall: the 32-gon covers 99.4 % of the circle, the caps' 8-step
    /// rings lose a little more) and wound outward (positive volume).
    #[test]
    fn a_straight_tube_is_a_closed_capsule() {
        let line = Centreline::smoothed(&[Vec3::ZERO, Vec3::X], 0);
        let mesh = tube(&line, |_| 0.1, 11, 32).unwrap();
        let exact = std::f32::consts::PI * 0.01 * 1.0 + 4.0 / 3.0 * std::f32::consts::PI * 0.001;
        let volume = mesh.volume();
        assert!(volume > 0.97 * exact && volume < exact, "volume {volume} vs {exact}");
        let (lo, hi) = mesh.bounds();
        assert!((lo.x + 0.1).abs() < 1e-5 && (hi.x - 1.1).abs() < 1e-5, "{lo} {hi}");
    }

    /// Corner cutting keeps the ends and stays inside the polyline's bend.
    #[test]
    fn the_centreline_keeps_its_ends_and_rounds_corners() {
        let line = Centreline::smoothed(&[Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0)], 4);
        assert_eq!(line.at(0.0), Vec3::ZERO);
        assert_eq!(line.at(line.length()), Vec3::new(1.0, 1.0, 0.0));
        assert!(line.length() < 2.0 && line.length() > 1.5, "{}", line.length());
        let bones = line.bones(&[0.0, 0.5, line.length()]);
        assert_eq!(bones.len(), 2);
        assert_eq!(bones[1].parent, Some(0));
        assert_eq!(bones[0].tail, bones[1].head);
    }
}
