//! Principal axes of a mesh: the direction of largest second moment of its solid (or of its
//! vertices), for automatic skeletons and fitted capsule colliders.

use glam::{DMat3, DVec3, Vec3};

use super::{TriMesh, mass_properties};

/// Centroid and unit principal axis of the solid (or of the vertices when the mesh encloses no
/// volume); `None` when the vertices coincide.
pub(crate) fn principal_axis(mesh: &TriMesh) -> Option<(Vec3, Vec3)> {
    let (centre, covariance) = match mass_properties(mesh, 1.0) {
        Some(m) => {
            // Second moment about the centre from the inertia tensor: C = tr(I)/2·𝟙 − I.
            let inertia = m.inertia.as_dmat3();
            let trace = inertia.x_axis.x + inertia.y_axis.y + inertia.z_axis.z;
            (m.center, DMat3::from_diagonal(DVec3::splat(trace / 2.0)) - inertia)
        }
        None => vertex_covariance(mesh.positions()),
    };
    let axis = dominant_axis(covariance)?;
    let flip = axis.to_array().iter().copied().max_by(|a, b| a.abs().total_cmp(&b.abs())).unwrap_or(1.0) < 0.0;
    let axis = if flip { -axis } else { axis };
    Some((centre, axis.as_vec3()))
}

/// The mean of `points` (m) and the unit direction of their largest spread about it (either
/// sign), `None` when there are none or they coincide: the axis a capsule or a limb fitted to
/// them lies on.
pub fn vertex_principal_axis(points: &[Vec3]) -> Option<(Vec3, Vec3)> {
    if points.is_empty() {
        return None;
    }
    let (mean, covariance) = vertex_covariance(points);
    Some((mean, dominant_axis(covariance)?.as_vec3()))
}

/// Unit eigenvector of the largest eigenvalue of `covariance` (either sign), `None` when that
/// eigenvalue is not positive (no spread).
pub(crate) fn dominant_axis(covariance: DMat3) -> Option<DVec3> {
    let (values, vectors) = symmetric_eigen(covariance);
    let largest = (0..3).max_by(|&a, &b| values[a].total_cmp(&values[b]))?;
    if values[largest].is_nan() || values[largest] <= 0.0 {
        return None;
    }
    Some(vectors.col(largest).normalize())
}

/// Mean of the points and their covariance about it, m and m².
pub(crate) fn vertex_covariance(points: &[Vec3]) -> (Vec3, DMat3) {
    let n = points.len() as f64;
    let mean = points.iter().map(|p| p.as_dvec3()).sum::<DVec3>() / n;
    let mut c = DMat3::ZERO;
    for p in points {
        let d = p.as_dvec3() - mean;
        c += DMat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    (mean.as_vec3(), c / n)
}

/// Eigenvalues and eigenvectors (columns) of a symmetric 3×3 matrix, by cyclic Jacobi rotations.
pub(crate) fn symmetric_eigen(m: DMat3) -> ([f64; 3], DMat3) {
    let mut a = m.to_cols_array_2d();
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..32 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        let scale = a[0][0].powi(2) + a[1][1].powi(2) + a[2][2].powi(2);
        if off <= 1e-30 * scale.max(f64::MIN_POSITIVE) {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() <= f64::MIN_POSITIVE {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let (c, s) = (1.0 / (t * t + 1.0).sqrt(), t / (t * t + 1.0).sqrt());
            // a ← Jᵀ a J with J the rotation in the (p, q) plane; a is stored by columns.
            let (column_p, column_q) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * column_p[k] - s * column_q[k]);
            a[q] = std::array::from_fn(|k| s * column_p[k] + c * column_q[k]);
            for column in &mut a {
                let (x, y) = (column[p], column[q]);
                column[p] = c * x - s * y;
                column[q] = s * x + c * y;
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    // v holds the rotation by rows of the column-major layout: column j of the eigenvector
    // matrix is (v[0][j], v[1][j], v[2][j]).
    let vectors = DMat3::from_cols(
        DVec3::new(v[0][0], v[1][0], v[2][0]),
        DVec3::new(v[0][1], v[1][1], v[2][1]),
        DVec3::new(v[0][2], v[1][2], v[2][2]),
    );
    ([a[0][0], a[1][1], a[2][2]], vectors)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_decomposition_reconstructs() {
        let m = DMat3::from_cols_array(&[4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 1.0]);
        let (values, vectors) = symmetric_eigen(m);
        for (j, &value) in values.iter().enumerate() {
            let v = vectors.col(j);
            let residual = (m * v - v * value).length();
            assert!(residual < 1e-10, "column {j}: residual {residual}");
            assert!((v.length() - 1.0).abs() < 1e-12);
        }
    }
}
