//! A ready-to-run scene and the camera that frames it.

use glam::Vec3;

use super::Camera;
use crate::coupling::Bending;
use crate::sim::{RigidBody, World};

/// Frames run when a scene file gives no `frames`.
pub(crate) const DEFAULT_FRAMES: u32 = 120;

/// A world with its bodies, a camera that shows it, and how long to run it.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Short name: the built-in scene's name or the scene file's `name` (default: its stem).
    pub name: String,
    /// The bodies and the settings that step them, at time 0.
    pub world: World,
    /// A camera that shows the interesting part.
    pub camera: Camera,
    /// Default number of frames to run; one frame is one world step of
    /// `world.settings().dt` seconds.
    pub frames: u32,
    /// One or two sentences: what the scene shows (and which paper figure it reproduces).
    pub description: String,
    /// The bending bodies (their sub-bodies are in `world`); empty for most scenes. Hand it to
    /// [`Simulation::with_bending`](crate::coupling::Simulation::with_bending).
    pub bending: Bending,
}

/// How big a built-in scene is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SceneSize {
    /// The paper's sizes (meshes and body counts of its figures).
    #[default]
    Full,
    /// Smaller meshes and fewer bodies, so that each scene runs in a few seconds on a laptop
    /// (`dentbend demo`).
    Demo,
}

/// Width over height of the pictures the default cameras are framed for (`dentbend run`'s
/// default 960 × 640).
pub(crate) const FRAMING_ASPECT: f32 = 1.5;

/// A camera looking along `direction` (from the eye towards the scene; need not be unit) that
/// fits every body of `world` at its current pose in a [`FRAMING_ASPECT`] picture, +y up.
pub(crate) fn framing_camera(world: &World, direction: Vec3) -> Camera {
    fit_camera(framing_bounds(world, |_| true), direction)
}

/// A camera with a 30° vertical field of view looking along `direction` at the centre of the box
/// `(lo, hi)` (m), just far enough that all eight corners fall inside a [`FRAMING_ASPECT`]
/// picture with a 5 % margin. Tighter than [`Camera::framing`], which fits the bounding sphere.
pub(crate) fn fit_camera(bounds: (Vec3, Vec3), direction: Vec3) -> Camera {
    let fov_y_deg: f32 = 30.0;
    let (lo, hi) = bounds;
    let centre = 0.5 * (lo + hi);
    let forward = direction.try_normalize().unwrap_or(Vec3::NEG_Z);
    let up = if forward.cross(Vec3::Y).length_squared() > 1e-6 { Vec3::Y } else { Vec3::Z };
    let right = forward.cross(up).normalize();
    let true_up = right.cross(forward);
    let tan_y = (0.5 * fov_y_deg.to_radians()).tan() / 1.05;
    let tan_x = tan_y * FRAMING_ASPECT;
    let mut distance: f32 = 1e-3;
    for k in 0..8 {
        let corner = Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        ) - centre;
        // Depth of the corner is distance + its offset along the view direction.
        let along = corner.dot(forward);
        distance = distance.max(corner.dot(right).abs() / tan_x - along).max(corner.dot(true_up).abs() / tan_y - along);
    }
    // Keep the near plane (1 % of the distance) clear of the box.
    let radius = 0.5 * (hi - lo).length();
    let distance = distance.max(1.02 * radius);
    Camera { eye: centre - forward * distance, target: centre, up, fov_y_deg }
}

/// World bounds (m) of the bodies for which `keep` holds, at their current poses; a 2 m cube
/// about the origin when there are none.
pub(super) fn framing_bounds(world: &World, keep: impl Fn(&RigidBody) -> bool) -> (Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for body in world.bodies().iter().filter(|b| !b.is_cluster_proxy() && keep(b)) {
        let transform = body.transform();
        for &p in body.mesh().positions() {
            let p = transform.transform_point3(p);
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    if lo.is_finite() && hi.is_finite() { (lo, hi) } else { (Vec3::splat(-1.0), Vec3::splat(1.0)) }
}
