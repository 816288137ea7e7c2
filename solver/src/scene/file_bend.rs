//! The `[body.bend]` table of a scene file as serde structs: the skeleton, the skinning weights,
//! the joints and dynamic articulation of a bending body. Values keep their spans for errors.

use std::fmt;

use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use toml::Spanned;

use super::file_values::Triple;

/// `[body.bend]`: present = the body bends (paper §4).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BendFile {
    /// `"auto"` or an array of bone tables.
    pub skeleton: Option<Spanned<SkeletonFile>>,
    /// With the automatic skeleton: number of bones along the principal axis.
    pub bones: Option<Spanned<usize>>,
    /// `[[body.bend.bone]]` tables: the bones, given.
    #[serde(rename = "bone")]
    pub bone_tables: Option<Spanned<Vec<Spanned<BoneFile>>>>,
    /// Level-set cells along the longest side.
    pub resolution: Option<Spanned<u32>>,
    /// Bones per vertex.
    pub influences: Option<Spanned<usize>>,
    /// Exponent of the inverse-distance weight kernel.
    pub falloff: Option<Spanned<f32>>,
    /// The joints at the skeleton's joints (default rigid).
    pub joint: Option<Spanned<JointFile>>,
    /// `[body.bend.dynamic]`: joints added where fast hits land.
    pub dynamic: Option<Spanned<DynamicFile>>,
}

/// `skeleton = "auto"` or `skeleton = [{ head = …, tail = … }, …]`.
#[derive(Debug)]
pub(super) enum SkeletonFile {
    Auto,
    Bones(Vec<Spanned<BoneFile>>),
}

/// One bone, in the mesh's model frame after the body's `scale`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BoneFile {
    /// Start of the bone (where it joins its parent), m.
    pub head: Spanned<Triple>,
    /// End of the bone, m.
    pub tail: Spanned<Triple>,
    /// Index of the parent bone (0-based, in the order written); none for the root.
    pub parent: Option<Spanned<usize>>,
    /// The joint where this bone hangs from its parent, when it is not `[body.bend] joint`'s kind.
    pub joint: Option<Spanned<JointFile>>,
}

/// A joint table: `kind` and the numbers that kind takes.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct JointFile {
    pub kind: Spanned<JointKindSpec>,
    /// Plastic: largest angular impulse per step before it bends, N·m·s.
    pub strength: Option<Spanned<f32>>,
    /// Plastic: constant damping of a bend, rad/s².
    pub damping_constant: Option<Spanned<f32>>,
    /// Plastic: proportional damping of a bend, 1/s.
    pub damping_proportional: Option<Spanned<f32>>,
    /// Elastic: N·m/rad; elastic-prismatic: N/m.
    pub stiffness: Option<Spanned<f32>>,
    /// Elastic: N·m·s/rad; elastic-prismatic: N·s/m.
    pub damping: Option<Spanned<f32>>,
    /// Elastic-prismatic: sliding direction, world axes at the start.
    pub axis: Option<Spanned<Triple>>,
}

/// `kind = "rigid" | "ball" | "plastic" | "elastic" | "elastic-prismatic"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(super) enum JointKindSpec {
    Rigid,
    Ball,
    Plastic,
    Elastic,
    ElasticPrismatic,
}

impl JointKindSpec {
    /// The name as written in a file.
    pub fn name(self) -> &'static str {
        match self {
            Self::Rigid => "rigid",
            Self::Ball => "ball",
            Self::Plastic => "plastic",
            Self::Elastic => "elastic",
            Self::ElasticPrismatic => "elastic-prismatic",
        }
    }

    /// The name with its indefinite article: "a plastic", "an elastic".
    pub fn with_article(self) -> String {
        let article = if matches!(self, Self::Elastic | Self::ElasticPrismatic) { "an" } else { "a" };
        format!("{article} {}", self.name())
    }
}

/// `[body.bend.dynamic]`: dynamic articulation.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DynamicFile {
    /// Closing normal speed above which a hit adds a joint, m/s.
    pub speed_threshold: Spanned<f32>,
    /// No split leaves a bone shorter than this, m.
    pub min_bone_length: Spanned<f32>,
    /// Most joints added (default 16).
    pub max_joints: Option<Spanned<usize>>,
    /// The joints added.
    pub joint: Spanned<JointFile>,
}

impl<'de> Deserialize<'de> for SkeletonFile {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct SkeletonVisitor;
        impl<'de> Visitor<'de> for SkeletonVisitor {
            type Value = SkeletonFile;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("\"auto\" or an array of bone tables ({ head = [x, y, z], tail = [x, y, z], parent = 0 })")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<SkeletonFile, E> {
                match v {
                    "auto" => Ok(SkeletonFile::Auto),
                    _ => Err(E::invalid_value(de::Unexpected::Str(v), &self)),
                }
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<SkeletonFile, A::Error> {
                let mut bones = Vec::new();
                while let Some(bone) = seq.next_element()? {
                    bones.push(bone);
                }
                Ok(SkeletonFile::Bones(bones))
            }
        }
        deserializer.deserialize_any(SkeletonVisitor)
    }
}
