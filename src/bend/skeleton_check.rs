//! Checking a skeleton against the closed mesh it is meant to bend: every bone must lie at least
//! partly inside it or touch its surface. A bone that pokes out (the bunny's neck, paper
//! Figure 12) is fine; a bone floating beside the body is an error.

use glam::Vec3;
use rayon::prelude::*;

use super::geometry::{segment_hits_triangle, solid_angle, triangle_dist2};
use super::{BendError, Skeleton};
use crate::mesh::TriMesh;

/// Default tolerance of [`Skeleton::check_against`], as a fraction of the mesh's bounding-box
/// diagonal: a bone wholly outside but within this distance of the surface is accepted.
pub(crate) const OUTSIDE_TOLERANCE_FRACTION: f32 = 0.02;
/// Points sampled along a bone (ends included) to measure its distance to the surface.
const DISTANCE_SAMPLES: usize = 9;

impl Skeleton {
    /// Checks every bone against the closed `mesh` with the default tolerance
    /// (2 % × the mesh's bounding-box diagonal).
    ///
    /// # Errors
    /// [`BendError::BoneOutsideMesh`] for the first bone that lies entirely outside the mesh and
    /// farther than the tolerance from its surface; [`BendError::ZeroLengthBone`] for a bone
    /// shorter than 10⁻⁶ × the mesh's diagonal.
    pub fn check_against(&self, mesh: &TriMesh) -> Result<(), BendError> {
        let (lo, hi) = mesh.bounds();
        self.check_against_with(mesh, OUTSIDE_TOLERANCE_FRACTION * lo.distance(hi))
    }

    /// As [`check_against`](Self::check_against) with an explicit `tolerance`, m (finite, ≥ 0).
    ///
    /// A bone passes if it crosses the surface, if its head is inside (winding number of the
    /// mesh above ½, so the test is robust to small defects), or if one of 9 points spread evenly
    /// along it is within `tolerance` of the surface. Cost: O(bones × triangles), on all cores.
    ///
    /// # Errors
    /// As [`check_against`](Self::check_against), plus [`BendError::InvalidParameter`] for a bad
    /// tolerance.
    pub fn check_against_with(&self, mesh: &TriMesh, tolerance: f32) -> Result<(), BendError> {
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            let value = tolerance.to_string();
            return Err(BendError::InvalidParameter { name: "tolerance", value, reason: "must be finite and ≥ 0" });
        }
        let (lo, hi) = mesh.bounds();
        let minimum = super::MIN_BONE_FRACTION * lo.distance(hi);
        for (bone, b) in self.bones().iter().enumerate() {
            let length = b.length();
            if length <= minimum {
                return Err(BendError::ZeroLengthBone { bone, length, minimum });
            }
            if crosses_surface(mesh, b.head, b.tail) || winding_number(mesh, b.head).abs() > 0.5 {
                continue;
            }
            let samples: Vec<Vec3> =
                (0..DISTANCE_SAMPLES).map(|i| b.point_at(i as f32 / (DISTANCE_SAMPLES - 1) as f32)).collect();
            let distance = surface_distance(mesh, &samples);
            if distance > tolerance {
                return Err(BendError::BoneOutsideMesh { bone, distance, tolerance });
            }
        }
        Ok(())
    }
}

/// Whether the segment `p`–`q` meets any triangle of `mesh`.
fn crosses_surface(mesh: &TriMesh, p: Vec3, q: Vec3) -> bool {
    let positions = mesh.positions();
    mesh.faces().par_iter().any(|f| {
        let [a, b, c] = f.map(|v| positions[v as usize]);
        segment_hits_triangle(p, q, a, b, c)
    })
}

/// Generalized winding number of `mesh` at `p`: 1 inside a closed outward-wound mesh, 0 outside
/// (−1 inside an inward-wound one), computed in f64.
pub(crate) fn winding_number(mesh: &TriMesh, p: Vec3) -> f64 {
    let positions = mesh.positions();
    let p = p.as_dvec3();
    let total: f64 = mesh
        .faces()
        .par_iter()
        .map(|f| {
            let [a, b, c] = f.map(|v| positions[v as usize].as_dvec3());
            solid_angle(p, a, b, c)
        })
        .sum();
    total / (4.0 * std::f64::consts::PI)
}

/// Smallest distance from any of `points` to the surface of `mesh`, m.
fn surface_distance(mesh: &TriMesh, points: &[Vec3]) -> f32 {
    let positions = mesh.positions();
    let best = mesh
        .faces()
        .par_iter()
        .map(|f| {
            let [a, b, c] = f.map(|v| positions[v as usize]);
            points.iter().map(|&p| triangle_dist2(p, a, b, c)).fold(f32::INFINITY, f32::min)
        })
        .reduce(|| f32::INFINITY, f32::min);
    best.sqrt()
}
