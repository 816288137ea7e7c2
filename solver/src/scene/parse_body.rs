//! One `[[body]]` table of a scene file → a body description, every value checked where it is
//! written (errors placed on the field), and the mesh cache and value checks the bendable
//! bodies' tables share.

use std::collections::HashMap;
use std::ops::Range;
use std::path::PathBuf;

use glam::{Affine3A, Quat, Vec3};
use toml::Spanned;

use super::file::{AttenuationSpec, BodyFile, DentFile, MaterialSpec, ResolutionSpec};
use super::file_values::Triple;
use super::source::Source;
use super::{MeshPaths, SceneError};
use crate::sim::{BodyDesc, DentSettings, MAX_ANGULAR_SPEED, SimError, SurfaceMaterial};
use dentbend::dent::{Attenuation, DentError, MAX_SPEED, Resolution, VolumeMode};
use dentbend::mesh::resolve_inside;
use dentbend::mesh::{self, MAX_COORDINATE, TriMesh};

/// Dent threshold when `[body.dent]` gives none, m/s.
pub(crate) const DEFAULT_DENT_THRESHOLD: f32 = 1.0;
/// Dent gain when `[body.dent]` gives none, m per m/s above the threshold.
pub(crate) const DEFAULT_DENT_GAIN: f32 = 0.04;
/// Dent cap when `[body.dent]` gives none, m.
pub(crate) const DEFAULT_DENT_CAP: f32 = 0.3;

/// A mesh supplier for [`parse_scene_with_meshes`](super::parse_scene_with_meshes): given a body's `mesh` string as written, its
/// mesh, or a message saying why there is none.
pub type MeshResolver<'r> = dyn FnMut(&str) -> Result<TriMesh, String> + 'r;

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

impl<'r> MeshCache<'r> {
    /// Nothing loaded yet: relative paths start at `folder`, may leave it as `paths` says;
    /// `resolve` (when given) supplies every mesh instead of built-ins and files.
    pub(super) fn new(folder: PathBuf, paths: MeshPaths, resolve: Option<&'r mut MeshResolver<'r>>) -> Self {
        Self { folder, paths, loaded: HashMap::new(), resolve }
    }
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
            mesh::load(&path).map_err(|e| fail(e.to_string()))?
        };
        self.loaded.insert(name.clone(), mesh.clone());
        Ok(mesh)
    }
}

/// The range a vector field must lie in besides being finite.
#[derive(Debug, Clone, Copy)]
pub(super) enum Bound {
    /// Any finite vector.
    Finite,
    /// Every component within ± the limit, with its unit for the message.
    Axis(f32, &'static str),
    /// Length at most the limit, with its unit for the message.
    Length(f32, &'static str),
}

/// A checked vector field: finite and within `bound`, or an error at its span.
pub(super) fn vector(
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
