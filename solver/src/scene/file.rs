//! The scene file's tables as serde structs. Every value a later check may refuse keeps its span
//! ([`Spanned`]), so that the error can point at it; unknown fields are refused while parsing.

use std::fmt;

use serde::Deserialize;
use serde::de::{self, Deserializer, Visitor};
use toml::Spanned;

use super::file_bend::BendFile;
use super::file_values::{Scale, Triple};
use crate::sim::{BodyKind, ColliderKind, WorldSettings};

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SceneFile {
    /// Scene name (default: the file's stem).
    pub name: Option<String>,
    /// Default number of frames to run.
    pub frames: Option<Spanned<u32>>,
    /// Free text.
    #[serde(default)]
    pub description: String,
    /// World settings; missing fields take [`WorldSettings::default`].
    pub world: Option<WorldSettings>,
    /// The camera (default: one framing every body).
    pub camera: Option<CameraFile>,
    /// The bodies, `[[body]]` tables.
    #[serde(default, rename = "body")]
    pub bodies: Vec<BodyFile>,
}

/// `[camera]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraFile {
    /// Eye position, m.
    pub eye: Spanned<Triple>,
    /// Point looked at, m.
    pub target: Spanned<Triple>,
    /// Up direction (default +y).
    pub up: Option<Spanned<Triple>>,
    /// Vertical field of view, degrees (default 30).
    pub fov_deg: Option<Spanned<f32>>,
}

/// One `[[body]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BodyFile {
    pub name: Spanned<String>,
    /// Built-in mesh name or path relative to the scene file.
    pub mesh: Spanned<String>,
    pub scale: Option<Spanned<Scale>>,
    pub kind: Option<Spanned<BodyKind>>,
    /// m.
    pub position: Option<Spanned<Triple>>,
    /// Axis-angle: direction = axis, length = angle in degrees.
    pub rotation: Option<Spanned<Triple>>,
    /// m/s.
    pub velocity: Option<Spanned<Triple>>,
    /// rad/s.
    pub angular_velocity: Option<Spanned<Triple>>,
    /// kg/m³.
    pub density: Option<Spanned<f32>>,
    /// kg.
    pub mass: Option<Spanned<f32>>,
    pub collider: Option<Spanned<ColliderKind>>,
    pub restitution: Option<Spanned<f32>>,
    pub friction: Option<Spanned<f32>>,
    /// Linear RGB in [0, 1].
    pub color: Option<Spanned<Triple>>,
    pub dent: Option<Spanned<DentFile>>,
    /// Present = the body breaks (prescored fracture).
    pub fracture: Option<Spanned<FractureFile>>,
    /// Present = a bending body instead of a rigid one.
    pub bend: Option<Spanned<BendFile>>,
}

/// `[body.dent]`: the material and the dent shape.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DentFile {
    /// m/s.
    pub threshold: Option<Spanned<f32>>,
    /// m per m/s.
    pub gain: Option<Spanned<f32>>,
    /// m.
    pub cap: Option<Spanned<f32>>,
    /// Pa.
    pub hardness: Option<Spanned<f32>>,
    pub move_projectile: Option<bool>,
    pub progressive: Option<bool>,
    /// m.
    pub sigma: Option<Spanned<f32>>,
    pub resolution: Option<Spanned<ResolutionSpec>>,
    pub heat_iters: Option<Spanned<u32>>,
    pub clamp_iters: Option<Spanned<u32>>,
    pub heat_rate: Option<Spanned<f32>>,
    pub attenuation: Option<Spanned<AttenuationSpec>>,
    /// For `attenuation = "linear"`: depth where the dent has faded, in dent distances.
    pub attenuation_scale: Option<Spanned<f32>>,
    pub min_cos: Option<Spanned<f32>>,
    /// 1/m.
    pub widen: Option<Spanned<f32>>,
    /// What the body is made of: decides `preserve_volume` when that is not given.
    pub material: Option<MaterialSpec>,
    /// Raise a rim that keeps the volume (`VolumeMode::Preserve`).
    pub preserve_volume: Option<bool>,
}

/// `material = "solid" | "sheet"`: a solid's dent pushes material aside (volume kept), a
/// sheet's thins it (volume lost, the paper's behaviour).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum MaterialSpec {
    Solid,
    Sheet,
}

/// `[body.fracture]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FractureFile {
    /// Voronoi cells of the pattern.
    pub cells: Option<Spanned<u32>>,
    /// Seed of the pattern's generator.
    pub seed: Option<Spanned<u64>>,
    /// m.
    pub radius: Spanned<f32>,
    /// J.
    pub toughness: Option<Spanned<f32>>,
    /// m.
    pub dent_limit: Option<Spanned<f32>>,
    /// kg/m³ (pieces of a static or kinematic body).
    pub density: Option<Spanned<f32>>,
    /// Most pieces one break may make.
    pub max_pieces: Option<Spanned<u32>>,
}

/// `attenuation = "logistic" | "linear" | "none"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum AttenuationSpec {
    Logistic,
    Linear,
    None,
}

/// `resolution = 100` (cells per side) or `resolution = "auto"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum ResolutionSpec {
    Auto,
    Fixed(u32),
}

impl<'de> Deserialize<'de> for ResolutionSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ResolutionVisitor;
        impl Visitor<'_> for ResolutionVisitor {
            type Value = ResolutionSpec;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number of cells per side or \"auto\"")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<ResolutionSpec, E> {
                u32::try_from(v)
                    .map(ResolutionSpec::Fixed)
                    .map_err(|_| E::invalid_value(de::Unexpected::Signed(v), &self))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<ResolutionSpec, E> {
                u32::try_from(v)
                    .map(ResolutionSpec::Fixed)
                    .map_err(|_| E::invalid_value(de::Unexpected::Unsigned(v), &self))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<ResolutionSpec, E> {
                match v {
                    "auto" => Ok(ResolutionSpec::Auto),
                    _ => Err(E::invalid_value(de::Unexpected::Str(v), &self)),
                }
            }
        }
        deserializer.deserialize_any(ResolutionVisitor)
    }
}
