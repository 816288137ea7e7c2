//! A pinhole camera that frames meshes.

use glam::{Mat4, Vec3};

/// A perspective camera looking from `eye` at `target`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position, world units.
    pub eye: Vec3,
    /// Point looked at, world units.
    pub target: Vec3,
    /// Up direction (need not be unit or perpendicular to the view).
    pub up: Vec3,
    /// Vertical field of view, degrees.
    pub fov_y_deg: f32,
}

impl Camera {
    /// A camera looking along `direction` (from the eye towards the scene) that fits the
    /// bounding sphere of the box `(lo, hi)` in view, with `up` as the up direction.
    pub fn framing(bounds: (Vec3, Vec3), direction: Vec3, up: Vec3) -> Self {
        let (lo, hi) = bounds;
        let centre = 0.5 * (lo + hi);
        let radius = (0.5 * (hi - lo).length()).max(1e-6);
        let fov_y_deg: f32 = 30.0;
        let distance = radius / (0.5 * fov_y_deg.to_radians()).sin() * 1.05;
        let direction = direction.try_normalize().unwrap_or(-Vec3::Z);
        Self { eye: centre - direction * distance, target: centre, up, fov_y_deg }
    }

    /// World → clip matrix for an image of aspect `width / height`.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        let view = glam::camera::rh::view::look_at_mat4(self.eye, self.target, self.up);
        let distance = self.eye.distance(self.target).max(1e-6);
        let projection = glam::camera::rh::proj::directx::perspective(
            self.fov_y_deg.to_radians(),
            aspect,
            distance * 0.01,
            distance * 100.0,
        );
        projection * view
    }
}
