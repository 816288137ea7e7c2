//! Scene files: TOML text → checked [`Scene`]. Every refusal names the file, the line and column,
//! the body and the field (see the format in the [module docs](super)).

use std::collections::HashMap;
use std::path::Path;

use glam::Vec3;
use toml::Spanned;

use super::Camera;
use super::file::{CameraFile, SceneFile};
use super::file_values::Triple;
use super::parse_bend::{add_error as bend_add_error, bendable_desc};
use super::parse_body::{MeshCache, MeshResolver, body_desc, number, sim_error};
use super::source::Source;
use super::{DEFAULT_FRAMES, LoadOptions, Scene, SceneError, framing_camera};
use crate::coupling::Bending;
use crate::sim::{SimError, World};
use dentbend::mesh::MAX_COORDINATE;

/// Direction the default camera looks along: from the front (+z), a little above.
const DEFAULT_VIEW: Vec3 = Vec3::new(0.0, -0.45, -1.0);

/// Reads and builds the scene file at `path` (TOML, format in the [module docs](super)). Reads
/// the file and the mesh files it names; writes nothing.
///
/// # Errors
/// [`SceneError::Read`] when the file cannot be read, otherwise as [`parse_scene`].
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    load_scene_with(path, &LoadOptions::default())
}

/// [`load_scene`] with `options`: mesh paths trusted or confined, limits on bodies and size.
///
/// # Errors
/// [`SceneError::Read`] when the file cannot be read, is not a file or is larger than
/// `options.max_file_bytes`; otherwise as [`parse_scene_with`].
pub(crate) fn load_scene_with(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let read_error = |source| SceneError::Read { path: path.into(), source };
    let metadata = std::fs::metadata(path).map_err(read_error)?;
    if metadata.is_dir() {
        return Err(read_error(std::io::Error::other("it is a directory, not a scene file")));
    }
    if metadata.len() > options.max_file_bytes {
        return Err(read_error(std::io::Error::other(format!(
            "the file has {} bytes, more than the limit of {} for a scene file",
            metadata.len(),
            options.max_file_bytes
        ))));
    }
    let text = std::fs::read_to_string(path).map_err(read_error)?;
    parse_scene_with(&text, path, options)
}

/// Builds a scene from the TOML `text` of a scene file. `origin` is the file's path: it is
/// printed in error messages and mesh paths are relative to its folder.
///
/// # Errors
/// [`SceneError::Invalid`], `file:line:col: body "name": field: message`, for bad syntax, an
/// unknown field, a value of the wrong type, a NaN or infinite number, a non-positive mass,
/// density or scale, a missing or unreadable mesh file, bad dent parameters, a duplicate body
/// name, a body the simulation refuses (e.g. an open mesh for a dynamic body), a `[body.bend]`
/// with a field a bending body cannot have or a bad number, or a skeleton the bending library
/// refuses (placed on the bone).
///
/// # Example
/// ```
/// use std::path::Path;
/// let text = r#"
/// frames = 90
/// [[body]]
/// name = "ball"
/// mesh = "sphere"
/// position = [0, 2, 0]
/// velocity = [0, -5, 0]
/// [[body]]
/// name = "ground"
/// mesh = "block"
/// kind = "static"
/// [body.dent]
/// cap = 0.2
/// "#;
/// let scene = dentbend_solver::scene::parse_scene(text, Path::new("drop.toml"))?;
/// assert_eq!((scene.name.as_str(), scene.frames, scene.world.bodies().len()), ("drop", 90, 2));
///
/// let error = dentbend_solver::scene::parse_scene("[[body]]\nname = \"b\"\nmesh = \"sphere\"\nmass = -1\n", Path::new("bad.toml"))
///     .unwrap_err();
/// assert!(error.to_string().starts_with("bad.toml:4:8: body \"b\": mass:"));
/// # Ok::<(), dentbend_solver::scene::SceneError>(())
/// ```
pub fn parse_scene(text: &str, origin: &Path) -> Result<Scene, SceneError> {
    parse_scene_with(text, origin, &LoadOptions::default())
}

/// [`parse_scene`] with `options`: mesh paths confined to the file's folder (the default) or
/// trusted, and at most `options.max_bodies` bodies.
///
/// # Errors
/// As [`parse_scene`]; also for a mesh path that leaves the scene file's folder while confined,
/// and for more bodies than the limit.
pub(crate) fn parse_scene_with(text: &str, origin: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    build_scene(text, origin, options, None)
}

/// Builds a scene as [`parse_scene`] does, except that every mesh the file names is asked of
/// `resolve` (once per distinct `mesh` string) instead of being built in or read from disk: an
/// application can supply meshes of its own, and nothing is read. `origin` is only printed in
/// error messages.
///
/// # Errors
/// As [`parse_scene`]; a message from `resolve` is reported on the body's `mesh` field.
pub fn parse_scene_with_meshes(text: &str, origin: &Path, resolve: &mut MeshResolver<'_>) -> Result<Scene, SceneError> {
    build_scene(text, origin, &LoadOptions::default(), Some(resolve))
}

/// [`parse_scene_with`], with meshes from `resolve` when it is given.
fn build_scene<'r>(
    text: &str,
    origin: &Path,
    options: &LoadOptions,
    resolve: Option<&'r mut MeshResolver<'r>>,
) -> Result<Scene, SceneError> {
    let src = Source::new(text, origin);
    if text.len() as u64 > options.max_file_bytes {
        return Err(src.error_at(
            0..0,
            None,
            "file",
            format!("{} bytes is more than the limit of {}", text.len(), options.max_file_bytes),
        ));
    }
    let file: SceneFile = toml::from_str(text).map_err(|e| src.toml_error(&e))?;
    if file.bodies.len() > options.max_bodies {
        let span = file.bodies[options.max_bodies].name.span();
        let message = format!("{} bodies is more than the limit of {}", file.bodies.len(), options.max_bodies);
        return Err(src.error_at(span, None, "body", message));
    }
    let settings = file.world.unwrap_or_default();
    let mut world = World::new(settings).map_err(|e| world_error(&src, e))?;

    let folder = origin.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut meshes = MeshCache::new(folder, options.mesh_paths, resolve);
    let mut names: HashMap<&str, usize> = HashMap::new();
    let mut bending = Bending::new();
    for body in &file.bodies {
        let name = body.name.get_ref().as_str();
        if name.trim().is_empty() {
            return Err(src.error_at(body.name.span(), None, "name", "must not be empty"));
        }
        if let Some(&first) = names.get(name) {
            let (line, _) = src.line_col(first);
            let message = format!("duplicate body name \"{name}\" (first used on line {line})");
            return Err(src.error_at(body.name.span(), Some(name), "name", message));
        }
        names.insert(name, body.name.span().start);
        if let Some(bend) = &body.bend {
            let desc = bendable_desc(&src, body, bend, &mut meshes)?;
            bending.add(&mut world, desc).map_err(|e| bend_add_error(&src, body, bend, e))?;
        } else {
            let desc = body_desc(&src, body, &mut meshes)?;
            world.add(desc).map_err(|e| sim_error(&src, body, e))?;
        }
    }

    let camera = match &file.camera {
        Some(camera) => camera_from(&src, camera)?,
        None => framing_camera(&world, DEFAULT_VIEW),
    };
    let frames = match &file.frames {
        Some(f) if *f.get_ref() == 0 => return Err(src.error_at(f.span(), None, "frames", "must be at least 1")),
        Some(f) => *f.get_ref(),
        None => DEFAULT_FRAMES,
    };
    let stem = origin.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scene".into());
    Ok(Scene { name: file.name.unwrap_or(stem), world, camera, frames, description: file.description, bending })
}

/// `[camera]` → a camera, every value checked.
fn camera_from(src: &Source<'_>, camera: &CameraFile) -> Result<Camera, SceneError> {
    let point = |field: &str, v: &Spanned<Triple>| -> Result<Vec3, SceneError> {
        let p = Vec3::from_array(v.get_ref().0);
        if p.is_finite() && p.abs().max_element() <= MAX_COORDINATE {
            Ok(p)
        } else {
            Err(src.error_at(v.span(), None, field, format!("{p} must be finite and within ±1e6 m")))
        }
    };
    let eye = point("camera.eye", &camera.eye)?;
    let target = point("camera.target", &camera.target)?;
    if eye.distance(target) < 1e-6 {
        return Err(src.error_at(camera.target.span(), None, "camera.target", "must differ from camera.eye"));
    }
    let up = match &camera.up {
        Some(up) => point("camera.up", up)?,
        None => Vec3::Y,
    };
    if up.cross(target - eye).length_squared() < 1e-12 {
        let span = camera.up.as_ref().map_or(camera.eye.span(), Spanned::span);
        return Err(src.error_at(span, None, "camera.up", "must not be zero or parallel to the view direction"));
    }
    let fov =
        number(src, None, "camera.fov_deg", &camera.fov_deg, |f| f > 0.0 && f < 180.0, "degrees must be in (0, 180)")?;
    Ok(Camera { eye, target, up, fov_y_deg: fov.unwrap_or(30.0) })
}

/// A bad `[world]` setting, placed on its key.
fn world_error(src: &Source<'_>, error: SimError) -> SceneError {
    let (key, message) = match &error {
        SimError::Invalid { what, value, reason } => (what.clone(), format!("{value} {reason}")),
        other => (String::new(), other.to_string()),
    };
    let at = src.find_key("world", &key).or_else(|| src.find_header("world")).unwrap_or(0);
    let field = if key.is_empty() { "world".to_owned() } else { format!("world.{key}") };
    src.error_at(at..at, None, &field, message)
}
