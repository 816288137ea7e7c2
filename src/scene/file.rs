//! The scene file's tables as serde structs. Every value a later check may refuse keeps its span
//! ([`Spanned`]), so that the error can point at it; unknown fields are refused while parsing.

use std::fmt;

use serde::Deserialize;
use serde::de::{self, Deserializer, IgnoredAny, SeqAccess, Visitor};
use toml::Spanned;

use super::file_bend::BendFile;
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
}

/// `attenuation = "logistic" | "linear" | "none"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum AttenuationSpec {
    Logistic,
    Linear,
    None,
}

/// An `[x, y, z]` array of exactly three numbers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Triple(pub [f32; 3]);

/// `scale = 2` or `scale = [1, 0.5, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Scale(pub [f32; 3]);

/// `resolution = 100` (cells per side) or `resolution = "auto"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum ResolutionSpec {
    Auto,
    Fixed(u32),
}

/// Reads exactly three numbers from `seq` (serde's arrays ignore extra elements in TOML).
fn three<'de, A: SeqAccess<'de>>(mut seq: A, expected: &dyn de::Expected) -> Result<[f32; 3], A::Error> {
    let mut out = [0.0f32; 3];
    for (i, slot) in out.iter_mut().enumerate() {
        *slot = seq.next_element()?.ok_or_else(|| de::Error::invalid_length(i, expected))?;
    }
    let mut count = 3;
    while seq.next_element::<IgnoredAny>()?.is_some() {
        count += 1;
    }
    if count > 3 {
        return Err(de::Error::invalid_length(count, expected));
    }
    Ok(out)
}

impl<'de> Deserialize<'de> for Triple {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct TripleVisitor;
        impl<'de> Visitor<'de> for TripleVisitor {
            type Value = Triple;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("an [x, y, z] array of three numbers")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Triple, A::Error> {
                three(seq, &self).map(Triple)
            }
        }
        deserializer.deserialize_seq(TripleVisitor)
    }
}

impl<'de> Deserialize<'de> for Scale {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ScaleVisitor;
        impl<'de> Visitor<'de> for ScaleVisitor {
            type Value = Scale;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number or an [x, y, z] array of three numbers")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Scale, E> {
                Ok(Scale([v as f32; 3]))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Scale, E> {
                Ok(Scale([v as f32; 3]))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Scale, E> {
                Ok(Scale([v as f32; 3]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Scale, A::Error> {
                three(seq, &self).map(Scale)
            }
        }
        deserializer.deserialize_any(ScaleVisitor)
    }
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
