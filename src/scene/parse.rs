//! Scene files: TOML text → checked [`Scene`]. Every refusal names the file, the line and column,
//! the body and the field (see the format in the [module docs](super)).

use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use glam::{Affine3A, Quat, Vec3};
use toml::Spanned;

use super::Camera;
use super::file::{AttenuationSpec, BodyFile, CameraFile, DentFile, MaterialSpec, ResolutionSpec, SceneFile};
use super::file_values::Triple;
use super::parse_bend::{add_error as bend_add_error, bendable_desc};
use super::source::Source;
use super::{DEFAULT_FRAMES, LoadOptions, MeshPaths, Scene, SceneError, framing_camera};
use crate::coupling::Bending;
use crate::dent::{Attenuation, DentError, MAX_SPEED, Resolution, VolumeMode};
use crate::mesh::confined::resolve_inside;
use crate::mesh::{self, MAX_COORDINATE, TriMesh};
use crate::sim::{BodyDesc, DentSettings, MAX_ANGULAR_SPEED, SimError, SurfaceMaterial, World};

/// Dent threshold when `[body.dent]` gives none, m/s.
pub const DEFAULT_DENT_THRESHOLD: f32 = 1.0;
/// Dent gain when `[body.dent]` gives none, m per m/s above the threshold.
pub const DEFAULT_DENT_GAIN: f32 = 0.04;
/// Dent cap when `[body.dent]` gives none, m.
pub const DEFAULT_DENT_CAP: f32 = 0.3;

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
pub fn load_scene_with(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
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
/// let scene = dentbend::scene::parse_scene(text, Path::new("drop.toml"))?;
/// assert_eq!((scene.name.as_str(), scene.frames, scene.world.bodies().len()), ("drop", 90, 2));
///
/// let error = dentbend::scene::parse_scene("[[body]]\nname = \"b\"\nmesh = \"sphere\"\nmass = -1\n", Path::new("bad.toml"))
///     .unwrap_err();
/// assert!(error.to_string().starts_with("bad.toml:4:8: body \"b\": mass:"));
/// # Ok::<(), dentbend::scene::SceneError>(())
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
pub fn parse_scene_with(text: &str, origin: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    build_scene(text, origin, options, None)
}

/// A mesh supplier for [`parse_scene_with_meshes`]: given a body's `mesh` string as written, its
/// mesh, or a message saying why there is none.
pub type MeshResolver<'r> = dyn FnMut(&str) -> Result<TriMesh, String> + 'r;

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
    let mut meshes = MeshCache { folder, paths: options.mesh_paths, loaded: HashMap::new(), resolve };
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

/// Meshes by spec, loaded once each.
pub(super) struct MeshCache<'r> {
    /// The scene file's folder: relative mesh paths start here.
    folder: PathBuf,
    /// Whether mesh paths may leave `folder`.
    paths: MeshPaths,
    loaded: HashMap<String, TriMesh>,
    /// The caller's mesh supplier, used instead of built-ins and files when given.
    resolve: Option<&'r mut MeshResolver<'r>>,
}

impl MeshCache<'_> {
    /// The mesh for a built-in name or a path relative to the scene file.
    fn get(&mut self, src: &Source<'_>, body: &str, spec: &Spanned<String>) -> Result<TriMesh, SceneError> {
        let name = spec.get_ref();
        if let Some(mesh) = self.loaded.get(name) {
            return Ok(mesh.clone());
        }
        let fail = |message: String| src.error_at(spec.span(), Some(body), "mesh", message);
        let mesh = if let Some(resolve) = &mut self.resolve {
            resolve(name).map_err(fail)?
        } else if mesh::BUILTIN_NAMES.contains(&name.as_str()) {
            mesh::builtin(name).map_err(|e| fail(e.to_string()))?
        } else {
            let path = self.folder.join(name);
            if path.is_dir() {
                return Err(fail(format!("{} is a directory, not a mesh file", path.display())));
            }
            if !path.is_file() {
                let builtins = mesh::BUILTIN_NAMES.join(", ");
                return Err(fail(format!(
                    "mesh file {} not found (a mesh is a built-in name: {builtins}; or a mesh file path \
                     relative to the scene file)",
                    path.display()
                )));
            }
            let path = match self.paths {
                MeshPaths::Trusted => path,
                MeshPaths::Confined => resolve_inside(&self.folder, name).map_err(|e| {
                    fail(format!("{e} (to read files elsewhere, load the scene with trusted mesh paths: `--trust-paths` on the command line)"))
                })?,
            };
            let path_text = path.to_str().ok_or_else(|| fail(format!("mesh path {} is not UTF-8", path.display())))?;
            mesh::load(path_text).map_err(|e| fail(e.to_string()))?
        };
        self.loaded.insert(name.clone(), mesh.clone());
        Ok(mesh)
    }
}

/// The range a vector field must lie in besides being finite.
#[derive(Debug, Clone, Copy)]
enum Bound {
    /// Any finite vector.
    Finite,
    /// Every component within ± the limit, with its unit for the message.
    Axis(f32, &'static str),
    /// Length at most the limit, with its unit for the message.
    Length(f32, &'static str),
}

/// A checked vector field: finite and within `bound`, or an error at its span.
fn vector(
    src: &Source<'_>,
    body: &str,
    field: &str,
    value: &Option<Spanned<Triple>>,
    bound: Bound,
) -> Result<Option<Vec3>, SceneError> {
    let Some(v) = value else { return Ok(None) };
    let array = v.get_ref().0;
    let fail = |message: String| Err(src.error_at(v.span(), Some(body), field, message));
    if !array.iter().all(|x| x.is_finite()) {
        return fail(format!("{array:?} must be finite (no nan or inf)"));
    }
    let vector = Vec3::from_array(array);
    match bound {
        Bound::Axis(limit, unit) if vector.abs().max_element() > limit => {
            fail(format!("{array:?} lies beyond ±{limit:e} {unit}, the supported range"))
        }
        Bound::Length(limit, unit) if vector.length() > limit => {
            fail(format!("{array:?} is longer than {limit:e} {unit}, the supported range"))
        }
        _ => Ok(Some(vector)),
    }
}

/// A checked number field: `ok(value)` must hold, or an error at its span saying `rule`.
pub(super) fn number(
    src: &Source<'_>,
    body: Option<&str>,
    field: &str,
    value: &Option<Spanned<f32>>,
    ok: impl Fn(f32) -> bool,
    rule: &str,
) -> Result<Option<f32>, SceneError> {
    match value {
        Some(v) if !ok(*v.get_ref()) => Err(src.error_at(v.span(), body, field, format!("{} {rule}", v.get_ref()))),
        Some(v) => Ok(Some(*v.get_ref())),
        None => Ok(None),
    }
}

pub(super) fn positive(x: f32) -> bool {
    x.is_finite() && x > 0.0
}

/// One `[[body]]` → a body description, every value checked where it is written.
pub(super) fn body_desc(src: &Source<'_>, body: &BodyFile, meshes: &mut MeshCache<'_>) -> Result<BodyDesc, SceneError> {
    let name = body.name.get_ref().as_str();
    let mut mesh = meshes.get(src, name, &body.mesh)?;
    if let Some(scale) = &body.scale {
        let s = scale.get_ref().0;
        if !s.iter().all(|&x| positive(x)) {
            let message = format!("{s:?} must be finite and > 0 along every axis");
            return Err(src.error_at(scale.span(), Some(name), "scale", message));
        }
        mesh.transform(Affine3A::from_scale(Vec3::from_array(s)))
            .map_err(|e| src.error_at(scale.span(), Some(name), "scale", e.to_string()))?;
    }
    let mut desc = BodyDesc::new(name, mesh);
    desc.kind = body.kind.as_ref().map(|k| *k.get_ref()).unwrap_or_default();
    desc.collider = body.collider.as_ref().map(|c| *c.get_ref()).unwrap_or_default();
    desc.position =
        vector(src, name, "position", &body.position, Bound::Axis(MAX_COORDINATE, "m"))?.unwrap_or(Vec3::ZERO);
    if let Some(rotation) = vector(src, name, "rotation", &body.rotation, Bound::Axis(1.0e6, "degrees"))? {
        desc.orientation = Quat::from_scaled_axis(rotation * (std::f32::consts::PI / 180.0));
    }
    desc.linear_velocity =
        vector(src, name, "velocity", &body.velocity, Bound::Length(MAX_SPEED, "m/s"))?.unwrap_or(Vec3::ZERO);
    let spin = Bound::Length(MAX_ANGULAR_SPEED, "rad/s");
    desc.angular_velocity = vector(src, name, "angular_velocity", &body.angular_velocity, spin)?.unwrap_or(Vec3::ZERO);
    if let Some(color) = vector(src, name, "color", &body.color, Bound::Finite)? {
        desc.color = color.to_array();
    }

    let density = number(src, Some(name), "density", &body.density, positive, "kg/m³ must be finite and > 0")?;
    let mass = number(src, Some(name), "mass", &body.mass, positive, "kg must be finite and > 0")?;
    desc.density = match (density, mass, &body.mass) {
        (Some(_), Some(_), Some(m)) => {
            return Err(src.error_at(m.span(), Some(name), "mass", "give density or mass, not both"));
        }
        (_, Some(mass), Some(m)) => {
            let volume = desc.mesh.volume().abs();
            if !positive(volume) {
                let message = "cannot turn a mass into a density: the mesh encloses no volume";
                return Err(src.error_at(m.span(), Some(name), "mass", message));
            }
            mass / volume
        }
        (density, ..) => density.unwrap_or(desc.density),
    };

    let defaults = SurfaceMaterial::default();
    let restitution =
        number(src, Some(name), "restitution", &body.restitution, |r| (0.0..=1.0).contains(&r), "must be in [0, 1]")?;
    let friction =
        number(src, Some(name), "friction", &body.friction, |f| f.is_finite() && f >= 0.0, "must be finite and >= 0")?;
    desc.surface = SurfaceMaterial {
        restitution: restitution.unwrap_or(defaults.restitution),
        friction: friction.unwrap_or(defaults.friction),
    };
    if let Some(dent) = &body.dent {
        desc.dent = Some(dent_settings(src, name, dent)?);
    }
    if let Some(fracture) = &body.fracture {
        let settings = super::file_fracture::fracture_settings(fracture, desc.density);
        desc.fracture = Some(settings.map_err(|e| src.error_at(e.span, Some(name), &e.field, e.message))?);
    }
    Ok(desc)
}

/// `[body.dent]` → dent settings, checked by [`DentSettings::validate`] with the error placed on
/// the field it names.
fn dent_settings(src: &Source<'_>, body: &str, dent: &Spanned<DentFile>) -> Result<DentSettings, SceneError> {
    let file = dent.get_ref();
    let value = |field: &Option<Spanned<f32>>, default: f32| field.as_ref().map_or(default, |v| *v.get_ref());
    let cap = value(&file.cap, DEFAULT_DENT_CAP);
    let mut settings =
        DentSettings::new(value(&file.threshold, DEFAULT_DENT_THRESHOLD), value(&file.gain, DEFAULT_DENT_GAIN), cap);
    settings.hardness = file.hardness.as_ref().map(|h| *h.get_ref());
    settings.move_projectile = file.move_projectile.unwrap_or(false);
    settings.progressive = file.progressive.unwrap_or(false);
    let params = &mut settings.params;
    params.sigma = file.sigma.as_ref().map(|s| *s.get_ref());
    if let Some(resolution) = &file.resolution {
        params.resolution = match resolution.get_ref() {
            ResolutionSpec::Auto => Resolution::default(),
            ResolutionSpec::Fixed(n) => Resolution::Fixed(*n),
        };
    }
    params.heat_iters = file.heat_iters.as_ref().map_or(params.heat_iters, |v| *v.get_ref());
    params.clamp_iters = file.clamp_iters.as_ref().map_or(params.clamp_iters, |v| *v.get_ref());
    params.heat_rate = value(&file.heat_rate, params.heat_rate);
    params.min_cos = value(&file.min_cos, params.min_cos);
    params.widen = value(&file.widen, params.widen);
    // An explicit `preserve_volume` wins; otherwise a solid keeps its volume, and a sheet, or a
    // body that does not say, loses it as in the paper.
    let solid = file.material == Some(MaterialSpec::Solid);
    if file.preserve_volume.unwrap_or(solid) {
        params.volume = VolumeMode::Preserve;
    }
    let attenuation = file.attenuation.as_ref().map(|a| *a.get_ref());
    if let Some(scale) = &file.attenuation_scale
        && attenuation != Some(AttenuationSpec::Linear)
    {
        let message = "only applies with attenuation = \"linear\"";
        return Err(src.error_at(scale.span(), Some(body), "dent.attenuation_scale", message));
    }
    params.attenuation = match attenuation {
        None | Some(AttenuationSpec::Logistic) => Attenuation::Logistic,
        Some(AttenuationSpec::Linear) => Attenuation::Linear { scale: value(&file.attenuation_scale, 1.0) },
        Some(AttenuationSpec::None) => Attenuation::None,
    };
    settings.validate().map_err(|error| dent_error(src, body, dent, error))?;
    Ok(settings)
}

/// A dent-parameter error placed on the field it names (or on the `dent` table).
fn dent_error(src: &Source<'_>, body: &str, dent: &Spanned<DentFile>, error: DentError) -> SceneError {
    let file = dent.get_ref();
    let span = |v: &Option<Spanned<f32>>| v.as_ref().map(Spanned::span);
    let (field, at): (&str, Option<Range<usize>>) = match &error {
        DentError::InvalidParameter { name, .. } => match *name {
            "threshold" => ("threshold", span(&file.threshold)),
            "gain" => ("gain", span(&file.gain)),
            "cap" | "dent_distance" => ("cap", span(&file.cap)),
            "hardness" => ("hardness", span(&file.hardness)),
            "sigma" => ("sigma", span(&file.sigma)),
            "resolution" => ("resolution", file.resolution.as_ref().map(Spanned::span)),
            "heat_iters" => ("heat_iters", file.heat_iters.as_ref().map(Spanned::span)),
            "clamp_iters" => ("clamp_iters", file.clamp_iters.as_ref().map(Spanned::span)),
            "heat_rate" => ("heat_rate", span(&file.heat_rate)),
            "min_cos" => ("min_cos", span(&file.min_cos)),
            "widen" => ("widen", span(&file.widen)),
            "attenuation.scale" => ("attenuation_scale", span(&file.attenuation_scale)),
            other => (other, None),
        },
        _ => ("", None),
    };
    let message = match &error {
        DentError::InvalidParameter { value, reason, .. } => format!("{value} {reason}"),
        other => other.to_string(),
    };
    src.error_at(at.unwrap_or_else(|| dent.span()), Some(body), format!("dent.{field}").trim_end_matches('.'), message)
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

/// A body the world refused, placed on the field the refusal names (or on the body's name).
pub(super) fn sim_error(src: &Source<'_>, body: &BodyFile, error: SimError) -> SceneError {
    let name = body.name.get_ref().as_str();
    let (field, message) = match &error {
        SimError::Invalid { what, value, reason } => {
            let field = what.rsplit(": ").next().unwrap_or(what);
            (if field == "linear_velocity" { "velocity" } else { field }.to_owned(), format!("{value} {reason}"))
        }
        SimError::BadShape { reason, .. } => ("mesh".to_owned(), reason.clone()),
        SimError::Dent { error, .. } => ("dent".to_owned(), error.to_string()),
        other => (String::new(), other.to_string()),
    };
    let span = match field.as_str() {
        "mesh" => Some(body.mesh.span()),
        "velocity" => body.velocity.as_ref().map(Spanned::span),
        "angular_velocity" => body.angular_velocity.as_ref().map(Spanned::span),
        "position" => body.position.as_ref().map(Spanned::span),
        "rotation" | "orientation" => body.rotation.as_ref().map(Spanned::span),
        "density" => body.density.as_ref().or(body.mass.as_ref()).map(Spanned::span),
        "restitution" => body.restitution.as_ref().map(Spanned::span),
        "friction" => body.friction.as_ref().map(Spanned::span),
        "color" => body.color.as_ref().map(Spanned::span),
        "dent" => body.dent.as_ref().map(Spanned::span),
        _ => None,
    };
    src.error_at(span.unwrap_or_else(|| body.name.span()), Some(name), &field, message)
}
