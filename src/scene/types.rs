//! A ready-to-run scene and the camera that frames it.

use glam::Vec3;

use crate::render::Camera;
use crate::sim::{RigidBody, World};

/// Frames run when a scene file gives no `frames`.
pub const DEFAULT_FRAMES: u32 = 120;

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

/// A camera looking along `direction` (from the eye towards the scene; need not be unit) that
/// fits every body of `world` at its current pose, with +y up.
pub fn framing_camera(world: &World, direction: Vec3) -> Camera {
    Camera::framing(framing_bounds(world, |_| true), direction, Vec3::Y)
}

/// World bounds (m) of the bodies for which `keep` holds, at their current poses; a 2 m cube
/// about the origin when there are none.
pub(super) fn framing_bounds(world: &World, keep: impl Fn(&RigidBody) -> bool) -> (Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for body in world.bodies().iter().filter(|b| keep(b)) {
        let transform = body.transform();
        for &p in body.mesh().positions() {
            let p = transform.transform_point3(p);
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    if lo.is_finite() && hi.is_finite() { (lo, hi) } else { (Vec3::splat(-1.0), Vec3::splat(1.0)) }
}
