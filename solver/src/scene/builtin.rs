//! The built-in scenes by name, and [`load_sized`] for "a built-in name or a file".

use std::path::Path;

use super::{
    LoadOptions, Scene, SceneError, SceneSize, arm, bending_scenes, bunny_bones, figures, load_scene_with, rain,
    tetrahedra, wall,
};

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
/// | `wall`        | 3      | balls dent a prescored wall one after another until it breaks         |
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
    "wall",
];

/// Builds the built-in scene `name` (see [`BUILTIN_SCENES`]) at `size`.
///
/// # Errors
/// [`SceneError::UnknownScene`] for another name; [`SceneError::Builtin`] if a mesh or body is
/// refused (a bug).
///
/// # Example
/// ```
/// use dentbend_solver::scene::{SceneSize, builtin_scene};
/// let scene = builtin_scene("pair", SceneSize::Demo)?;
/// assert!(scene.world.find("left").is_some() && scene.world.find("right").is_some());
/// # Ok::<(), dentbend_solver::scene::SceneError>(())
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
        "wall" => wall::wall,
        _ => return Err(unknown(name)),
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
/// existing file; otherwise as [`builtin_scene`] or [`load_scene`](super::load_scene).
pub fn load_sized(spec: &str, size: SceneSize) -> Result<Scene, SceneError> {
    load_with(spec, &LoadOptions::sized(size))
}

/// [`load_sized`] with `options` (size, where a scene file's mesh paths may lead, limits).
///
/// # Errors
/// As [`load_sized`], with `load_scene_with`'s for files.
pub fn load_with(spec: &str, options: &LoadOptions) -> Result<Scene, SceneError> {
    if BUILTIN_SCENES.contains(&spec) {
        return builtin_scene(spec, options.size);
    }
    let path = Path::new(spec);
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) || path.is_file() {
        return load_scene_with(path, options);
    }
    Err(unknown(spec))
}

/// [`SceneError::UnknownScene`] for `name`, listing the built-in scenes.
fn unknown(name: &str) -> SceneError {
    SceneError::UnknownScene { name: name.into(), builtins: BUILTIN_SCENES.join(", ") }
}
