//! The small kit the built-in scenes are built with: gravity, colours, a world, balls, dentable
//! settings, launches aimed at a point, frame counts by size, and a seeded generator.

use glam::{Affine3A, Vec3};

use super::types::{fit_camera, framing_bounds};
use super::{Scene, SceneSize};
use crate::sim::{DentSettings, SimError, World, WorldSettings};
use dentbend::mesh::{self, TriMesh};

/// Standard gravity, m/s² (y up).
pub(super) const GRAVITY: Vec3 = Vec3::new(0.0, -9.81, 0.0);

/// Colours (linear RGB) for the scenes' bodies.
pub(super) const STEEL: [f32; 3] = [0.62, 0.64, 0.68];
pub(super) const ORANGE: [f32; 3] = [0.85, 0.38, 0.12];
pub(super) const BLUE: [f32; 3] = [0.15, 0.35, 0.8];
pub(super) const GREEN: [f32; 3] = [0.25, 0.6, 0.3];
pub(super) const SAND: [f32; 3] = [0.8, 0.7, 0.5];
pub(super) const GROUND: [f32; 3] = [0.35, 0.35, 0.33];

/// A world with default settings but `gravity`, m/s².
pub(super) fn world(gravity: Vec3) -> Result<World, SimError> {
    World::new(WorldSettings { gravity, ..WorldSettings::default() })
}

/// An icosphere of `radius` (m) with `subdivisions` (20·4ⁿ triangles).
pub(super) fn ball(radius: f32, subdivisions: u32) -> Result<TriMesh, SimError> {
    Ok(mesh::icosphere(radius, subdivisions)?)
}

/// A built-in mesh scaled by `scale` along x, y, z.
pub(super) fn scaled(name: &str, scale: Vec3) -> Result<TriMesh, SimError> {
    let mut mesh = mesh::builtin(name)?;
    mesh.transform(Affine3A::from_scale(scale))?;
    Ok(mesh)
}

/// Dent settings: no dent below `threshold` m/s, then `gain` m per m/s, at most `cap` m;
/// Gaussian width `sigma` m (`None`: half the dent distance).
pub(super) fn dentable(threshold: f32, gain: f32, cap: f32, sigma: Option<f32>) -> DentSettings {
    let mut settings = DentSettings::new(threshold, gain, cap);
    settings.params.sigma = sigma;
    settings
}

/// Where a ballistic body must start, and how fast, to pass `point` with `velocity` (m/s) after
/// `lead` seconds under `gravity`.
pub(super) fn launch(point: Vec3, velocity: Vec3, gravity: Vec3, lead: f32) -> (Vec3, Vec3) {
    let start_velocity = velocity - gravity * lead;
    (point - start_velocity * lead - 0.5 * gravity * lead * lead, start_velocity)
}

/// The scene with a camera looking along `view` at every body for which `framed` holds.
pub(super) fn finish(
    name: &str,
    world: World,
    view: Vec3,
    framed: impl Fn(&str) -> bool,
    frames: u32,
    description: &str,
) -> Scene {
    let camera = fit_camera(framing_bounds(&world, |b| framed(&b.name)), view);
    Scene { name: name.into(), world, camera, frames, description: description.into(), bending: Default::default() }
}

/// A 64-bit linear congruential generator (Knuth's MMIX constants): the same cloud every run.
pub(super) struct Lcg(pub u64);

impl Lcg {
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [−1, 1).
    pub fn symmetric(&mut self) -> f32 {
        2.0 * self.unit() - 1.0
    }
}

/// `full` frames at full size, `demo` in the demo.
pub(super) fn frames(size: SceneSize, full: u32, demo: u32) -> u32 {
    match size {
        SceneSize::Full => full,
        SceneSize::Demo => demo,
    }
}
