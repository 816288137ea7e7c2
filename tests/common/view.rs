//! The Z-buffer test fixture shared by tests/zbuffer.rs and tests/parity_zbuffer.rs: a grid
//! seen along a direction, its kernel parameters and its f64 geometry.

use dentbend::cpu::{GridUniform, ZbufferParams, zbuffer};
use dentbend::mesh;
use glam::{DVec3, Quat, Vec3};

/// A Z-buffer grid and dent distance, as the pipeline builds them.
#[derive(Debug, Clone, Copy)]
pub struct View {
    pub origin: Vec3,
    pub x: Vec3,
    pub y: Vec3,
    pub z: Vec3,
    pub h: f32,
    pub res: u32,
    pub d: f32,
}

impl View {
    /// Axes for viewing direction `dir` (`y = z × x`, so `z = x × y`), with `origin` at the depth
    /// of the most advanced vertex, laterally on the line through `centre`; the grid spans
    /// `2·half` world units.
    pub fn looking(dir: Vec3, positions: &[Vec3], centre: Vec3, half: f32, res: u32, d: f32) -> Self {
        let z = dir.normalize();
        let x = z.any_orthonormal_vector();
        let y = z.cross(x);
        let tip = positions.iter().map(|p| p.dot(z)).fold(f32::NEG_INFINITY, f32::max);
        let origin = centre + (tip - centre.dot(z)) * z;
        Self { origin, x, y, z, h: 2.0 * half / res as f32, res, d }
    }

    /// World axes, origin at the world origin: grid point (col, row) is world
    /// `(col − shift, row − shift)` with `shift = res/2 − ½`, and depth s is world z.
    pub fn world_aligned(res: u32, d: f32) -> Self {
        Self { origin: Vec3::ZERO, x: Vec3::X, y: Vec3::Y, z: Vec3::Z, h: 1.0, res, d }
    }

    /// The same view with everything turned by `q`.
    pub fn rotated(self, q: Quat) -> Self {
        Self { origin: q * self.origin, x: q * self.x, y: q * self.y, z: q * self.z, ..self }
    }

    pub fn params(&self, face_count: usize) -> ZbufferParams {
        ZbufferParams {
            grid: GridUniform {
                origin: self.origin.to_array(),
                cell_size: self.h,
                axis_x: self.x.to_array(),
                res: self.res,
                axis_y: self.y.to_array(),
                _pad0: 0,
                axis_z: self.z.to_array(),
                _pad1: 0,
            },
            dent_distance: self.d,
            face_count: face_count as u32,
            face_offset: 0,
            cell_offset: 0,
        }
    }

    pub fn profile(&self, positions: &[Vec3], faces: &[[u32; 3]]) -> Vec<f32> {
        let mut out = vec![f32::NAN; (self.res as usize).pow(2)];
        zbuffer(&self.params(faces.len()), positions, faces, &mut out);
        out
    }

    pub fn shift(&self) -> f64 {
        0.5 * self.res as f64 - 0.5
    }

    /// World point of grid point (col, row) at depth s, f64.
    pub fn world(&self, col: f64, row: f64, s: f64) -> DVec3 {
        let h = self.h as f64;
        self.origin.as_dvec3()
            + (col - self.shift()) * h * self.x.as_dvec3()
            + (row - self.shift()) * h * self.y.as_dvec3()
            + s * self.z.as_dvec3()
    }

    /// `(col, row, s)` of a world point, f64.
    pub fn grid(&self, p: Vec3) -> DVec3 {
        let r = p.as_dvec3() - self.origin.as_dvec3();
        let h = self.h as f64;
        DVec3::new(
            r.dot(self.x.as_dvec3()) / h + self.shift(),
            r.dot(self.y.as_dvec3()) / h + self.shift(),
            r.dot(self.z.as_dvec3()),
        )
    }

    /// World point of grid point (col, row) at depth s, f32 (for building inputs).
    pub fn point(&self, col: f32, row: f32, s: f32) -> Vec3 {
        self.world(col as f64, row as f64, s as f64).as_vec3()
    }
}

/// A built-in mesh's positions and faces.
pub fn builtin(name: &str) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mesh = mesh::builtin(name).expect("built-in mesh");
    (mesh.positions().to_vec(), mesh.faces().to_vec())
}

/// The part of polygon `poly` (grid space: col, row, s) inside the square of half-side `half`
/// around grid point (`col`, `row`), by Sutherland–Hodgman.
pub fn clip_to_cell(poly: &[DVec3], col: f64, row: f64, half: f64) -> Vec<DVec3> {
    let planes: [(DVec3, f64); 4] =
        [(DVec3::X, col - half), (-DVec3::X, -(col + half)), (DVec3::Y, row - half), (-DVec3::Y, -(row + half))];
    let mut poly = poly.to_vec();
    for (n, offset) in planes {
        let inside = |p: DVec3| p.x * n.x + p.y * n.y - offset;
        let mut out = Vec::with_capacity(poly.len() + 2);
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let (fa, fb) = (inside(a), inside(b));
            if fa >= 0.0 {
                out.push(a);
            }
            if (fa >= 0.0) != (fb >= 0.0) {
                out.push(a + (b - a) * (fa / (fa - fb)));
            }
        }
        poly = out;
        if poly.is_empty() {
            break;
        }
    }
    poly
}
