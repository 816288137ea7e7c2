//! A dent's contact in the target's own coordinates, in the one exact form every path builds
//! its job from: the damage API, the rigid-body core, a replay and a replication client. The
//! directions and the projectile's rotation are stored as small integer codes, so that the
//! form crosses a network in a few dozen bytes and the receiver decodes the very f32 values
//! the sender dented with (bit-identical meshes on the CPU path).
//!
//! - Unit directions (the denting normal, the view direction): octahedral codes, 2 × u16
//!   (angular error below 1e-4 rad).
//! - The projectile's rotation in the target's coordinates: the smallest three components of
//!   its unit quaternion, 3 × f32, and which component was dropped (f32 rounding);
//!   a projectile whose pose in the target's coordinates is not a rotation (a scaled body)
//!   keeps its whole 3×3 matrix.
//! - The contact point and the projectile's translation: exact f32.

use glam::{Affine3A, Mat3A, Quat, Vec2, Vec3};

use super::{DentJob, DentParams, Impact, crop_to_ball};
use crate::mesh::TriMesh;

/// A unit direction as an octahedral code (2 × 16 bits).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct OctDirection(pub [u16; 2]);

impl OctDirection {
    /// The code of the direction of `v` (need not be unit length); the code of +Z for a zero or
    /// non-finite vector.
    pub fn encode(v: Vec3) -> Self {
        let l1 = v.x.abs() + v.y.abs() + v.z.abs();
        if !(l1 > 0.0 && l1.is_finite()) {
            return Self::encode(Vec3::Z);
        }
        let mut p = Vec2::new(v.x / l1, v.y / l1);
        if v.z < 0.0 {
            p = fold(p);
        }
        let q = |c: f32| ((c.clamp(-1.0, 1.0) * 0.5 + 0.5) * STEPS).round() as u16;
        Self([q(p.x), q(p.y)])
    }

    /// The unit direction the code stands for.
    pub fn decode(self) -> Vec3 {
        let p = Vec2::new(f32::from(self.0[0]), f32::from(self.0[1])) / STEPS * 2.0 - 1.0;
        let z = 1.0 - p.x.abs() - p.y.abs();
        let p = if z < 0.0 { fold(p) } else { p };
        Vec3::new(p.x, p.y, z).normalize()
    }
}

/// Steps of a code over [−1, 1]: an even number, so that 0 is a code (32767) and the axes and
/// the diagonals of the coordinate planes are coded exactly (a head-on hit along an axis stays
/// along it).
const STEPS: f32 = 65534.0;

/// The octahedron's lower half folded onto the square's corners (an involution).
fn fold(p: Vec2) -> Vec2 {
    Vec2::new((1.0 - p.y.abs()) * p.x.signum(), (1.0 - p.x.abs()) * p.y.signum())
}

/// The projectile's rotation in the target's coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PoseRotation {
    /// A rotation: the unit quaternion's largest component (`largest`: 0 = x … 3 = w, made
    /// positive) is dropped and the other three kept, in order.
    Quaternion {
        /// Which component was dropped.
        largest: u8,
        /// The other three.
        rest: [f32; 3],
    },
    /// Not a rotation (a scale in either body's transform): the matrix, exactly.
    Matrix(Mat3A),
}

/// How far a rotation matrix's columns may be from unit length and orthogonal (f32 rounding of
/// a product of two rigid transforms stays far below this).
const RIGID_TOLERANCE: f32 = 1e-4;

impl PoseRotation {
    /// The code of the linear part `m` of a pose.
    pub fn encode(m: Mat3A) -> Self {
        let (x, y, z) = (m.x_axis, m.y_axis, m.z_axis);
        let unit = |c: glam::Vec3A| (c.length() - 1.0).abs() <= RIGID_TOLERANCE;
        let orthogonal =
            x.dot(y).abs() <= RIGID_TOLERANCE && y.dot(z).abs() <= RIGID_TOLERANCE && z.dot(x).abs() <= RIGID_TOLERANCE;
        if !(unit(x) && unit(y) && unit(z) && orthogonal && m.determinant() > 0.0) {
            return Self::Matrix(m);
        }
        let q = Quat::from_mat3a(&m).normalize().to_array();
        let largest = (0..4).max_by(|&a, &b| q[a].abs().total_cmp(&q[b].abs())).unwrap_or(3);
        let sign = if q[largest] < 0.0 { -1.0 } else { 1.0 };
        let mut rest = [0.0f32; 3];
        for (slot, k) in (0..4).filter(|&k| k != largest).enumerate() {
            rest[slot] = sign * q[k];
        }
        Self::Quaternion { largest: largest as u8, rest }
    }

    /// The linear part the code stands for.
    pub fn decode(self) -> Mat3A {
        match self {
            Self::Matrix(m) => m,
            Self::Quaternion { largest, rest: small } => {
                let big = (1.0 - small.iter().map(|c| c * c).sum::<f32>()).max(0.0).sqrt();
                let mut q = [0.0; 4];
                let largest = usize::from(largest.min(3));
                let mut small = small.into_iter();
                for (k, slot) in q.iter_mut().enumerate() {
                    *slot = if k == largest { big } else { small.next().unwrap_or(0.0) };
                }
                Mat3A::from_quat(Quat::from_array(q).normalize())
            }
        }
    }
}

/// A dent's contact and the projectile's pose, in the target's mesh coordinates, as coded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalContact {
    /// Contact point, target mesh coordinates.
    pub point: Vec3,
    /// Denting normal (into the target).
    pub normal: OctDirection,
    /// Direction the projectile moved relative to the target (the Z-buffer's view): the
    /// normal's code for a head-on or a grazing contact.
    pub view: OctDirection,
    /// Projectile mesh → target mesh coordinates: rotation…
    pub rotation: PoseRotation,
    /// …and translation, target mesh coordinates.
    pub translation: Vec3,
}

impl LocalContact {
    /// The coded form of the world `impact` on a target whose mesh → world transform is
    /// `target_to_world`, hit by a projectile whose mesh → world transform is
    /// `projectile_to_world`.
    pub fn new(impact: &Impact, target_to_world: Affine3A, projectile_to_world: Affine3A) -> Self {
        let to_target = target_to_world.inverse();
        let (point, normal, view) = coded(impact, to_target);
        let pose = to_target * projectile_to_world;
        Self { point, normal, view, rotation: PoseRotation::encode(pose.matrix3), translation: pose.translation.into() }
    }

    /// The contact in target mesh coordinates, as every dent job takes it.
    pub fn impact(&self) -> Impact {
        decoded(self.point, self.normal, self.view)
    }

    /// [`impact`](Self::impact) of the contact of world `impact` on a target whose mesh → world
    /// transform is `target_to_world` (it does not depend on the projectile).
    pub fn impact_in_target(impact: &Impact, target_to_world: Affine3A) -> Impact {
        let (point, normal, view) = coded(impact, target_to_world.inverse());
        decoded(point, normal, view)
    }

    /// Projectile mesh → target mesh coordinates.
    pub fn projectile_pose(&self) -> Affine3A {
        Affine3A { matrix3: self.rotation.decode(), translation: self.translation.into() }
    }

    /// The dent job of this contact against batch target `slot`: `projectile` already in target
    /// mesh coordinates ([`crop`](Self::crop)), the target's `params` at `dent_distance` m.
    pub fn job<'p>(
        &self,
        projectile: &'p TriMesh,
        params: &DentParams,
        dent_distance: f32,
        slot: usize,
    ) -> DentJob<'p> {
        DentJob {
            target: slot,
            projectile,
            impact: self.impact(),
            params: DentParams { dent_distance, ..params.clone() },
        }
    }

    /// The triangles of `projectile` (its own coordinates) within `reach` m of the contact, in
    /// target mesh coordinates; `None` when none is that close.
    pub fn crop(&self, projectile: &TriMesh, reach: f32) -> Option<TriMesh> {
        let pose = self.projectile_pose();
        let centre = pose.inverse().transform_point3(self.point);
        let mut mesh = crop_to_ball(projectile, centre, reach)?;
        // A rigid motion of a valid mesh stays finite.
        let _ = mesh.transform(pose);
        Some(mesh)
    }
}

/// The point of world `impact` in target coordinates (through `to_target`), its normal's code
/// and its view's.
fn coded(impact: &Impact, to_target: Affine3A) -> (Vec3, OctDirection, OctDirection) {
    let local = impact.transformed(to_target);
    let normal = OctDirection::encode(local.unit_normal());
    let moving = local.relative_velocity != Vec3::ZERO;
    let view = OctDirection::encode(if moving { local.view_direction() } else { local.unit_normal() });
    // The dent needs a view that does not leave the surface; a grazing contact, whose coded
    // view might, looks along the normal.
    let view = if view.decode().dot(normal.decode()) > 0.0 { view } else { normal };
    (local.point, normal, view)
}

fn decoded(point: Vec3, normal: OctDirection, view: OctDirection) -> Impact {
    Impact { point, normal: normal.decode(), relative_velocity: view.decode() }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::test_support::centred_floats;

    #[test]
    fn directions_decode_within_a_ten_thousandth_of_a_radian() {
        let mut r = centred_floats(7);
        for _ in 0..2000 {
            let v = Vec3::new(r(), r(), r());
            let Some(unit) = v.try_normalize() else { continue };
            let decoded = OctDirection::encode(v).decode();
            // 16 bits over the octahedron's [-1, 1] square: a step of 3e-5, at most about
            // 5e-5 rad after the fold; 1e-4 leaves room for rounding.
            let angle = decoded.cross(unit).length().atan2(decoded.dot(unit));
            assert!(angle < 1e-4, "{v} → {decoded}: {angle} rad");
            assert!((decoded.length() - 1.0).abs() < 1e-6);
            assert_eq!(OctDirection::encode(decoded).decode(), decoded, "decoding is stable for {v}");
        }
        assert_eq!(OctDirection::encode(Vec3::ZERO), OctDirection::encode(Vec3::Z));
        assert_eq!(OctDirection::encode(Vec3::NAN), OctDirection::encode(Vec3::Z));
        for axis in [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z] {
            assert_eq!(OctDirection::encode(axis).decode(), axis, "an axis is coded exactly");
        }
    }

    #[test]
    fn rotations_decode_within_a_millionth_of_a_radian_and_scales_stay_exact() {
        let mut r = centred_floats(11);
        for _ in 0..1000 {
            let raw = Quat::from_xyzw(r(), r(), r(), r());
            if raw.length() < 1e-3 {
                continue;
            }
            let q = raw.normalize();
            let code = PoseRotation::encode(Mat3A::from_quat(q));
            assert!(matches!(code, PoseRotation::Quaternion { .. }));
            let back = Quat::from_mat3a(&code.decode());
            // f32 components: the angle is a few 1e-7 rad of rounding.
            // q and −q are one rotation: the angle of q⁻¹·back, whichever sign.
            let rel = q.inverse() * back;
            let angle = 2.0 * rel.xyz().length().atan2(rel.w.abs());
            assert!(angle < 1e-6, "{q} → {back}: {angle} rad");
        }
        let scaled = Mat3A::from_diagonal(Vec3::new(1.0, 2.0, 1.0));
        assert_eq!(PoseRotation::encode(scaled), PoseRotation::Matrix(scaled));
        let mirrored = Mat3A::from_diagonal(Vec3::new(-1.0, 1.0, 1.0));
        assert_eq!(PoseRotation::encode(mirrored), PoseRotation::Matrix(mirrored));
    }

    #[test]
    fn a_grazing_contact_views_along_its_normal() {
        // Moving almost along the surface: the view may not leave it after coding.
        let impact = Impact { point: Vec3::ZERO, normal: -Vec3::Y, relative_velocity: Vec3::new(1.0, -1e-7, 0.0) };
        let local = LocalContact::new(&impact, Affine3A::IDENTITY, Affine3A::IDENTITY);
        assert!(local.impact().view_direction().dot(local.impact().unit_normal()) > 0.0);
        let head_on = Impact { relative_velocity: Vec3::ZERO, ..impact };
        let local = LocalContact::new(&head_on, Affine3A::IDENTITY, Affine3A::IDENTITY);
        assert_eq!(local.view, local.normal);
    }
}
