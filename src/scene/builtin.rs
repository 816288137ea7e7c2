//! The built-in scenes by name, [`load_sized`] for "a built-in name or a file", and the small
//! kit the scenes are built with.

use std::path::Path;

use glam::{Affine3A, Vec3};

use super::types::{fit_camera, framing_bounds};
use super::{Scene, SceneError, SceneSize, arm, bending_scenes, bunny_bones, figures, load_scene, rain, tetrahedra};
use crate::mesh::{self, TriMesh};
use crate::sim::{DentSettings, SimError, World, WorldSettings};

/// Names accepted by [`builtin_scene`], one per paper figure they reproduce:
///
/// | name          | figure | what                                                                  |
/// |---------------|--------|-----------------------------------------------------------------------|
/// | `pair`        | 1      | two dentable balls, `left` and `right`, collide head-on: equal dents  |
/// | `ball-block`  | 2      | balls dent two blocks, with and without attenuation (back face bulge) |
/// | `bunny-block` | 5      | bunnies dent four blocks of growing dent distance and σ               |
/// | `glancing`    | 8      | balls hit three blocks at 0°, 30° and 60° from the normal             |
/// | `resolution`  | 11     | the same ball impact with dent grids of 20, 50, 100 and 200 cells     |
/// | `rain`        | 10     | 1,507 dentable spheres rain on a dense bunny and other targets        |
/// | `plank`       | 14     | a ball hits a plank on two supports: a plastic joint appears there    |
/// | `spring`      | —      | a floating bar with an elastic joint is hit and springs back straight |
/// | `bunny-bones` | 12     | a four-bone bunny (head bone poking out of the neck): head, ear bend  |
/// | `tetrahedra`  | 13     | 400 tetrahedra of balls and struts fall on four frames and bend       |
/// | `arm`         | 15     | a long many-boned body, condensed; a hit bends four joints of its arm |
pub const BUILTIN_SCENES: &[&str] = &[
    "pair",
    "ball-block",
    "bunny-block",
    "glancing",
    "resolution",
    "rain",
    "plank",
    "spring",
    "bunny-bones",
    "tetrahedra",
    "arm",
];

/// Builds the built-in scene `name` (see [`BUILTIN_SCENES`]) at `size`.
///
/// # Errors
/// [`SceneError::UnknownScene`] for another name; [`SceneError::Builtin`] if a mesh or body is
/// refused (a bug).
///
/// # Example
/// ```
/// use dentbend::scene::{SceneSize, builtin_scene};
/// let scene = builtin_scene("pair", SceneSize::Demo)?;
/// assert!(scene.world.find("left").is_some() && scene.world.find("right").is_some());
/// # Ok::<(), dentbend::scene::SceneError>(())
/// ```
pub fn builtin_scene(name: &str, size: SceneSize) -> Result<Scene, SceneError> {
    let build = match name {
        "pair" => figures::pair,
        "ball-block" => figures::ball_block,
        "bunny-block" => figures::bunny_block,
        "glancing" => figures::glancing,
        "resolution" => figures::resolution,
        "rain" => rain::rain,
        "plank" => bending_scenes::plank,
        "spring" => bending_scenes::spring,
        "tetrahedra" => tetrahedra::tetrahedra,
        "bunny-bones" => bunny_bones::bunny_bones,
        "arm" => arm::arm,
        _ => return Err(SceneError::UnknownScene { name: name.into() }),
    };
    build(size).map_err(|source| SceneError::Builtin { scene: name.into(), source })
}

/// A built-in scene at full size, or the scene file at path `spec`; see [`load_sized`].
///
/// # Errors
/// As [`load_sized`].
pub fn load(spec: &str) -> Result<Scene, SceneError> {
    load_sized(spec, SceneSize::Full)
}

/// A built-in scene by name (at `size`; a name wins over a file of the same name) or the scene
/// file at path `spec` (`size` does not apply to files).
///
/// # Errors
/// [`SceneError::UnknownScene`] when `spec` is neither a built-in name nor a `.toml` path or an
/// existing file; otherwise as [`builtin_scene`] or [`load_scene`].
pub fn load_sized(spec: &str, size: SceneSize) -> Result<Scene, SceneError> {
    if BUILTIN_SCENES.contains(&spec) {
        return builtin_scene(spec, size);
    }
    let path = Path::new(spec);
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) || path.is_file() {
        return load_scene(path);
    }
    Err(SceneError::UnknownScene { name: spec.into() })
}

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
