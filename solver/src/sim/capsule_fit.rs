//! A capsule collider fitted to a mesh: the analytic stand-in for struts, rods and limbs, far
//! cheaper in the narrow phase than their convex hulls (one or two contact points per pair
//! instead of four or more, and no support-map search).

use glam::Vec3;
use parry3d::shape::SharedShape;

use dentbend::mesh::TriMesh;
use dentbend::mesh::vertex_principal_axis;

/// The segment and radius of the capsule fitted to a mesh's vertices `points` (m), `None` when
/// they lie on one line or one point.
///
/// The segment lies on the vertices' principal axis (largest spread about their mean); the
/// radius is the largest distance of a vertex from that axis, and the segment is as long as
/// the vertices' extent along the axis less one radius at each end (zero when the mesh is no
/// longer than it is wide), so the capsule's tips touch the farthest vertices. The corners of a
/// flat end (a cylinder's rim) stick out of the rounded tip by at most (√2 − 1) radius.
pub(crate) fn fit_capsule(points: &[Vec3]) -> Option<(Vec3, Vec3, f32)> {
    let (mean, axis) = vertex_principal_axis(points)?;
    let (mut low, mut high, mut radius) = (f32::INFINITY, f32::NEG_INFINITY, 0.0f32);
    for &p in points {
        let offset = p - mean;
        let along = offset.dot(axis);
        low = low.min(along);
        high = high.max(along);
        radius = radius.max((offset - axis * along).length());
    }
    if !(radius > 0.0 && radius.is_finite()) {
        return None;
    }
    let reach = (0.5 * (high - low) - radius).max(0.0);
    let middle = mean + axis * (0.5 * (low + high));
    Some((middle - axis * reach, middle + axis * reach, radius))
}

/// The fitted capsule as a parry3d shape (see [`fit_capsule`]).
pub(crate) fn capsule_shape(mesh: &TriMesh) -> Result<SharedShape, String> {
    let (a, b, radius) =
        fit_capsule(mesh.positions()).ok_or("a capsule collider needs a mesh with width across its longest axis")?;
    Ok(SharedShape::capsule(a, b, radius))
}

#[cfg(test)]
mod tests {
    use super::*;
    use dentbend::mesh;

    /// A cylinder of radius 0.025 m and length 0.48 m along y (the tetrahedra's strut): the
    /// capsule lies on its axis with its radius, and its tips reach its flat ends. Tolerance
    /// 1e-5 m: f32 round-off of coordinates below 1 m.
    #[test]
    fn a_cylinder_gets_the_capsule_along_its_axis() {
        let cylinder = mesh::cylinder(0.025, 0.48, 8, 8).unwrap();
        let (a, b, radius) = fit_capsule(cylinder.positions()).unwrap();
        assert!((radius - 0.025).abs() < 1e-5, "radius {radius}");
        let (low, high) = if a.y < b.y { (a, b) } else { (b, a) };
        assert!(low.x.abs() < 1e-5 && low.z.abs() < 1e-5 && high.x.abs() < 1e-5 && high.z.abs() < 1e-5);
        assert!((high.y - (0.24 - 0.025)).abs() < 1e-5, "upper end {high}");
        assert!((low.y + (0.24 - 0.025)).abs() < 1e-5, "lower end {low}");
    }

    /// A mesh as long as it is wide gets a zero-length segment: a ball through its farthest
    /// vertices from the axis.
    #[test]
    fn a_stubby_mesh_gets_a_ball() {
        let cube = mesh::subdivided_box(Vec3::new(1.0, 1.0, 1.2), [1, 1, 1]).unwrap();
        let (a, b, radius) = fit_capsule(cube.positions()).unwrap();
        assert!(a.distance(b) < 1e-6, "segment {a} – {b}");
        assert!((radius - 0.5f32.hypot(0.5)).abs() < 1e-5, "radius {radius}");
    }

    /// Points on one line, or one point, have no width: no capsule.
    #[test]
    fn vertices_on_a_line_fit_no_capsule() {
        assert!(fit_capsule(&[Vec3::ZERO, Vec3::X, Vec3::X * 2.0]).is_none());
        assert!(fit_capsule(&[Vec3::ONE; 4]).is_none());
        assert!(fit_capsule(&[]).is_none());
    }
}
