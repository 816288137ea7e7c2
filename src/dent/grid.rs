//! The dent frame and the square cell grids the dent stages live on (ARCHITECTURE.md §3).

use glam::Vec3;
use serde::Serialize;

use super::Impact;

/// A square grid of `res × res` cells lying in the plane through `origin` spanned by `axis_x`
/// and `axis_y`; `axis_z` is its depth direction. Stored row-major, `[row = y][col = x]`; cell
/// (row j, col i) is centred at `origin + (i + ½ − res/2)·h·axis_x + (j + ½ − res/2)·h·axis_y`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Grid {
    /// Centre of the grid, world units.
    pub origin: Vec3,
    /// Unit direction of increasing column.
    pub axis_x: Vec3,
    /// Unit direction of increasing row (`axis_z × axis_x`).
    pub axis_y: Vec3,
    /// Unit depth direction (`axis_x × axis_y`).
    pub axis_z: Vec3,
    /// Side of one cell, world units.
    pub cell_size: f32,
    /// Cells per side.
    pub res: u32,
}

impl Grid {
    /// Number of cells, `res²`.
    pub fn cell_count(&self) -> usize {
        (self.res as usize).pow(2)
    }

    /// Side of the whole grid, world units.
    pub fn extent(&self) -> f32 {
        self.cell_size * self.res as f32
    }

    /// World position of the centre of cell (`row`, `col`).
    pub fn cell_centre(&self, row: u32, col: u32) -> Vec3 {
        let half = 0.5 * self.res as f32;
        self.origin
            + (col as f32 + 0.5 - half) * self.cell_size * self.axis_x
            + (row as f32 + 0.5 - half) * self.cell_size * self.axis_y
    }

    /// Continuous grid coordinates of a world point: `(col, row, depth)`, where integer `col`,
    /// `row` are cell centres and `depth` is `(p − origin)·axis_z` in world units.
    pub fn grid_coords(&self, p: Vec3) -> Vec3 {
        let r = p - self.origin;
        let shift = 0.5 * self.res as f32 - 0.5;
        Vec3::new(
            r.dot(self.axis_x) / self.cell_size + shift,
            r.dot(self.axis_y) / self.cell_size + shift,
            r.dot(self.axis_z),
        )
    }

    kernels_fn! {
        /// The GPU-layout copy of this grid.
        fn uniform(&self) -> crate::cpu::GridUniform {
            crate::cpu::GridUniform {
                origin: self.origin.to_array(),
                cell_size: self.cell_size,
                axis_x: self.axis_x.to_array(),
                res: self.res,
                axis_y: self.axis_y.to_array(),
                _pad0: 0,
                axis_z: self.axis_z.to_array(),
                _pad1: 0,
            }
        }
    }
}

/// The orthonormal directions of one impact (paper §3.3, ARCHITECTURE.md §4), with θ clamped so that
/// `cos θ ≥ min_cos`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DentFrame {
    /// n̂: the denting normal, into the target.
    pub normal: Vec3,
    /// t̂: in-plane direction of the relative velocity. Head-on it is `n̂ × e`, with `e` the
    /// world axis least aligned with n̂ (x, then y, then z on ties), so n̂ and −n̂ get opposite
    /// tangents and the same bitangent.
    pub tangent: Vec3,
    /// n̂ × t̂: the in-plane direction across the velocity.
    pub bitangent: Vec3,
    /// cos θ after clamping, θ the angle between the relative velocity and n̂.
    pub cos_theta: f32,
    /// sin θ after clamping.
    pub sin_theta: f32,
}

impl DentFrame {
    /// The frame of a validated impact.
    pub fn new(impact: &Impact, min_cos: f32) -> Self {
        let normal = impact.unit_normal();
        let view = impact.view_direction();
        let in_plane = view - view.dot(normal) * normal;
        let tangent = if in_plane.length() > 1e-5 { in_plane.normalize() } else { perpendicular(normal) };
        let cos_theta = view.dot(normal).clamp(min_cos, 1.0);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        Self { normal, tangent, bitangent: normal.cross(tangent), cos_theta, sin_theta }
    }

    /// θ after clamping, degrees.
    pub fn theta_deg(&self) -> f32 {
        self.sin_theta.atan2(self.cos_theta).to_degrees()
    }

    /// Viewing direction of the Z-buffer: the (clamped) relative velocity direction.
    pub fn view(&self) -> Vec3 {
        self.cos_theta * self.normal + self.sin_theta * self.tangent
    }

    /// Z-buffer grid axes `(x, y, z)`: perpendicular to the velocity, `y` shared with the
    /// collision plane, so a plane point at `u·t̂` projects to `x = u·cos θ`.
    pub fn zbuffer_axes(&self) -> (Vec3, Vec3, Vec3) {
        let x = self.cos_theta * self.tangent - self.sin_theta * self.normal;
        (x, self.bitangent, self.view())
    }

    /// Dent-map grid axes `(t̂, n̂ × t̂, n̂)` on the collision plane.
    pub fn plane_axes(&self) -> (Vec3, Vec3, Vec3) {
        (self.tangent, self.bitangent, self.normal)
    }
}

/// A unit vector perpendicular to `n`, chosen so that `perpendicular(−n) = −perpendicular(n)`:
/// head-on frames of the two bodies of a pair are then mirror images (paper Figure 1).
fn perpendicular(n: Vec3) -> Vec3 {
    let a = n.abs();
    let reference = if a.x <= a.y && a.x <= a.z {
        Vec3::X
    } else if a.y <= a.z {
        Vec3::Y
    } else {
        Vec3::Z
    };
    n.cross(reference).normalize()
}
