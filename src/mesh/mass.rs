//! Mass, centre of mass and inertia tensor of a closed triangle mesh of uniform density, by the
//! divergence theorem over the signed tetrahedra (origin, a, b, c) of its faces, summed in f64.

use glam::{DMat3, DVec3, Mat3, Vec3};

use super::TriMesh;

/// Mass properties of a solid body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// Mass, kg.
    pub mass: f32,
    /// Centre of mass in the mesh's coordinates, m.
    pub center: Vec3,
    /// Inertia tensor about the centre of mass, axes of the mesh's coordinates, kg·m².
    pub inertia: Mat3,
    /// Enclosed volume, m³.
    pub volume: f32,
}

/// Mass properties of the solid `mesh` bounds at `density` (kg/m³).
///
/// An inward-oriented mesh (negative signed volume) is read as the same solid. Returns `None`
/// when the enclosed volume is zero or not finite (an open sheet, a flat or degenerate mesh),
/// since such a mesh has no mass.
pub fn mass_properties(mesh: &TriMesh, density: f32) -> Option<MassProperties> {
    let positions = mesh.positions();
    // Canonical second-moment matrix of the unit tetrahedron (0, e₁, e₂, e₃), ∫ x xᵀ dV.
    let canonical = DMat3::from_cols_array(&[2.0, 1.0, 1.0, 1.0, 2.0, 1.0, 1.0, 1.0, 2.0]) / 120.0;
    let mut volume = 0.0f64;
    let mut first = DVec3::ZERO;
    let mut second = DMat3::ZERO;
    for face in mesh.faces() {
        let [a, b, c] = face.map(|i| positions[i as usize].as_dvec3());
        let edges = DMat3::from_cols(a, b, c);
        let det = edges.determinant();
        volume += det / 6.0;
        first += det / 24.0 * (a + b + c);
        second += edges * canonical * edges.transpose() * det;
    }
    if !(volume.is_finite() && volume.abs() > 0.0) {
        return None;
    }
    // An inside-out mesh gives every moment with the opposite sign.
    let sign = volume.signum();
    let (volume, first, second) = (volume * sign, first * sign, second * sign);
    let center = first / volume;
    let density = f64::from(density);
    // Second moment about the centre of mass, then I = tr(C)·𝟙 − C.
    let covariance =
        (second - DMat3::from_cols(center * center.x, center * center.y, center * center.z) * volume) * density;
    let inertia = DMat3::from_diagonal(DVec3::splat(covariance.x_axis.x + covariance.y_axis.y + covariance.z_axis.z))
        - covariance;
    let mass = volume * density;
    let properties = MassProperties {
        mass: mass as f32,
        center: center.as_vec3(),
        inertia: inertia.as_mat3(),
        volume: volume as f32,
    };
    (properties.mass.is_finite() && properties.mass > 0.0 && properties.inertia.is_finite()).then_some(properties)
}
