//! Seeded random hits on a mesh's surface for the soak: a point drawn uniformly by area (a
//! triangle with probability proportional to its area, then a uniform point in it), the surface
//! normal there, and a direction inside a cone about the inward normal.

use dentbend::TriMesh;
use dentbend::glam::Vec3;

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny seeded generator; the same seed gives the same
/// sequence on every platform.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator whose sequence is fixed by `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1), 53 random bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// A point on a surface and its unit outward normal there.
#[derive(Debug, Clone, Copy)]
pub struct SurfacePoint {
    /// The point, mesh coordinates.
    pub point: Vec3,
    /// Unit outward normal: the vertex normals interpolated at the point (the face's own normal
    /// where they cancel).
    pub normal: Vec3,
}

/// A point drawn uniformly by area over `mesh`'s surface as it is now; `None` when the surface
/// has no area.
pub fn sample_surface(mesh: &TriMesh, rng: &mut Rng) -> Option<SurfacePoint> {
    let positions = mesh.positions();
    let area = |f: &[u32; 3]| {
        let [a, b, c] = f.map(|v| positions[v as usize].as_dvec3());
        0.5 * (b - a).cross(c - a).length()
    };
    let mut cumulative = Vec::with_capacity(mesh.face_count());
    let mut total = 0.0;
    for face in mesh.faces() {
        total += area(face);
        cumulative.push(total);
    }
    if !(total > 0.0 && total.is_finite()) {
        return None;
    }
    let pick = rng.unit() * total;
    // The first triangle whose running total passes `pick`: a zero-area one never is.
    let index = cumulative.partition_point(|&c| c <= pick).min(cumulative.len() - 1);
    let face = mesh.faces()[index];
    // A uniform point in the triangle: fold the unit square's upper half onto the lower one.
    let (mut u, mut v) = (rng.unit() as f32, rng.unit() as f32);
    if u + v > 1.0 {
        (u, v) = (1.0 - u, 1.0 - v);
    }
    let weights = [1.0 - u - v, u, v];
    let [a, b, c] = face.map(|i| positions[i as usize]);
    let point = a * weights[0] + b * weights[1] + c * weights[2];
    let smooth: Vec3 = face.iter().zip(weights).map(|(&i, w)| mesh.normals()[i as usize] * w).sum();
    let normal = smooth.try_normalize().or_else(|| (b - a).cross(c - a).try_normalize())?;
    Some(SurfacePoint { point, normal })
}

/// A unit direction drawn uniformly from the cone of half-angle `half_angle` (radians) about
/// unit `axis`.
pub fn direction_in_cone(axis: Vec3, half_angle: f32, rng: &mut Rng) -> Vec3 {
    let cos_theta = 1.0 - rng.unit() as f32 * (1.0 - half_angle.cos());
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * rng.unit() as f32;
    let (x, y) = axis.any_orthonormal_pair();
    (axis * cos_theta + (x * phi.cos() + y * phi.sin()) * sin_theta).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles of areas 3/4 and 1/4 sharing an edge: sampling by area must land in the big
    /// one about 3/4 of the time, within 5 standard deviations of a binomial count over 20,000
    /// draws (σ ≈ 61).
    #[test]
    fn picks_triangles_by_area() {
        let positions = vec![Vec3::ZERO, Vec3::new(1.5, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(2.0, 0.0, 0.0)];
        let mesh = TriMesh::new(positions, vec![[0, 1, 2], [1, 3, 2]]).unwrap();
        let mut rng = Rng::new(7);
        let draws = 20_000;
        let big = (0..draws)
            .filter(|_| {
                let p = sample_surface(&mesh, &mut rng).unwrap().point;
                // The big triangle is the side of the shared edge x + 1.5 y = 1.5 holding the origin.
                p.x + 1.5 * p.y < 1.5
            })
            .count();
        let expected = 0.75 * draws as f64;
        let sigma = (draws as f64 * 0.75 * 0.25).sqrt();
        assert!((big as f64 - expected).abs() < 5.0 * sigma, "{big} of {draws} in the big triangle");
    }

    /// Every direction lies inside the cone, and the cone is filled: some come within 1° of its rim.
    #[test]
    fn directions_stay_in_the_cone() {
        let axis = Vec3::new(0.3, -1.0, 0.2).normalize();
        let half = 30f32.to_radians();
        let mut rng = Rng::new(3);
        let mut widest = 0f32;
        for _ in 0..10_000 {
            let d = direction_in_cone(axis, half, &mut rng);
            assert!((d.length() - 1.0).abs() < 1e-5);
            let angle = d.dot(axis).clamp(-1.0, 1.0).acos();
            assert!(angle <= half + 1e-4, "{} degrees", angle.to_degrees());
            widest = widest.max(angle);
        }
        assert!(widest > half - 1f32.to_radians(), "widest {} degrees", widest.to_degrees());
    }
}
