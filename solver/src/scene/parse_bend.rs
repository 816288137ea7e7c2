//! `[[body]]` with `[body.bend]` → a [`BendableDesc`]: the body's pose, motion and material as
//! for a rigid body, the skeleton, weights, joints and dynamic articulation from the table, every
//! value checked where it is written. Bending errors are placed on the bone or field they name.

use std::ops::Range;

use glam::Vec3;
use toml::Spanned;

use super::SceneError;
use super::file::BodyFile;
use super::file_bend::{BendFile, BoneFile, DynamicFile, JointFile, JointKindSpec, SkeletonFile};
use super::parse_body::{MeshCache, body_desc, number, positive, sim_error};
use super::source::Source;
use crate::coupling::{BendableDesc, DynamicArticulation, JointOverride, SkeletonSpec};
use crate::sim::{BodyKind, JointKind, SimError};
use dentbend::bend::JointRule;
use dentbend::bend::{BendError, BoneDesc, MAX_AUTO_BONES, Skeleton, WeightParams, auto_skeleton};
use dentbend::mesh::TriMesh;

/// One `[[body]]` with a `[body.bend]` table → a bending body's description.
pub(super) fn bendable_desc(
    src: &Source<'_>,
    body: &BodyFile,
    bend: &Spanned<BendFile>,
    meshes: &mut MeshCache<'_>,
) -> Result<BendableDesc, SceneError> {
    let name = body.name.get_ref().as_str();
    refuse_rigid_only_fields(src, body, name)?;
    let rigid = body_desc(src, body, meshes)?;
    let mut desc = BendableDesc::new(name, rigid.mesh);
    desc.position = rigid.position;
    desc.orientation = rigid.orientation;
    desc.linear_velocity = rigid.linear_velocity;
    desc.angular_velocity = rigid.angular_velocity;
    desc.density = rigid.density;
    desc.surface = rigid.surface;
    desc.collider = rigid.collider;
    desc.color = rigid.color;

    let file = bend.get_ref();
    desc.weights = weight_params(src, name, bend)?;
    desc.skeleton = skeleton_spec(src, name, bend, &desc.mesh)?;
    if let Some(joint) = &file.joint {
        desc.joint = joint_kind(src, name, "bend.joint", joint)?;
    }
    desc.joint_overrides = joint_overrides(src, name, bend)?;
    if let Some(dynamic) = &file.dynamic {
        desc.dynamic = Some(dynamic_articulation(src, name, dynamic)?);
    }
    Ok(desc)
}

/// A refusal of [`Bending::add`](crate::coupling::Bending::add), placed on the field it names, or on
/// the `bend` table for the bending library's own errors.
pub(super) fn add_error(src: &Source<'_>, body: &BodyFile, bend: &Spanned<BendFile>, error: SimError) -> SceneError {
    let name = body.name.get_ref().as_str();
    match error {
        SimError::BadShape { reason, .. } => {
            let reason = reason.strip_prefix("bending: ").unwrap_or(&reason);
            src.error_at(bend.span(), Some(name), "bend", reason)
        }
        SimError::Invalid { what, value, reason } if !what.contains(": ") => {
            src.error_at(body.name.span(), Some(name), "name", format!("{value} {reason}"))
        }
        other => sim_error(src, body, other),
    }
}

/// `kind`, `mass`, `[body.dent]` and a collider other than a part's convex hull or capsule have no
/// meaning for a bending body.
fn refuse_rigid_only_fields(src: &Source<'_>, body: &BodyFile, name: &str) -> Result<(), SceneError> {
    if let Some(kind) = body.kind.as_ref().filter(|k| *k.get_ref() != BodyKind::Dynamic) {
        let message = "a bending body (with [body.bend]) must be \"dynamic\"";
        return Err(src.error_at(kind.span(), Some(name), "kind", message));
    }
    if let Some(collider) = body.collider.as_ref().filter(|c| !BendableDesc::fits_parts(*c.get_ref())) {
        let message = "a bending body's parts collide as convex hulls or capsules fitted to them: \
                       \"auto\", \"convex-hull\" or \"capsule\"";
        return Err(src.error_at(collider.span(), Some(name), "collider", message));
    }
    if let Some(mass) = &body.mass {
        let message = "a bending body's mass comes from its density: give density instead";
        return Err(src.error_at(mass.span(), Some(name), "mass", message));
    }
    if let Some(dent) = &body.dent {
        let message = "a bending body cannot also dent ([body.dent] with [body.bend] is not supported)";
        return Err(src.error_at(dent.span(), Some(name), "dent", message));
    }
    if let Some(fracture) = &body.fracture {
        let message = "a bending body cannot also break ([body.fracture] with [body.bend] is not supported)";
        return Err(src.error_at(fracture.span(), Some(name), "fracture", message));
    }
    Ok(())
}

/// `resolution`, `influences` and `falloff`, checked by [`WeightParams::validate`].
fn weight_params(src: &Source<'_>, body: &str, bend: &Spanned<BendFile>) -> Result<WeightParams, SceneError> {
    let file = bend.get_ref();
    let defaults = WeightParams::default();
    let params = WeightParams {
        resolution: file.resolution.as_ref().map_or(defaults.resolution, |r| *r.get_ref()),
        influences: file.influences.as_ref().map_or(defaults.influences, |i| *i.get_ref()),
        falloff: file.falloff.as_ref().map_or(defaults.falloff, |f| *f.get_ref()),
    };
    params.validate().map_err(|error| {
        let (field, span) = match &error {
            BendError::InvalidParameter { name: "resolution", .. } => ("resolution", span_of(&file.resolution)),
            BendError::InvalidParameter { name: "influences", .. } => ("influences", span_of(&file.influences)),
            BendError::InvalidParameter { name: "falloff", .. } => ("falloff", span_of(&file.falloff)),
            _ => ("", None),
        };
        let message = match &error {
            BendError::InvalidParameter { value, reason, .. } => format!("{value} {reason}"),
            other => other.to_string(),
        };
        src.error_at(
            span.unwrap_or_else(|| bend.span()),
            Some(body),
            format!("bend.{field}").trim_end_matches('.'),
            message,
        )
    })?;
    Ok(params)
}

fn span_of<T>(value: &Option<Spanned<T>>) -> Option<Range<usize>> {
    value.as_ref().map(Spanned::span)
}

/// `skeleton = "auto"` with `bones`, `skeleton = [ … ]` or `[[body.bend.bone]]` tables (default:
/// one automatic bone). Given bones are validated and checked against the (scaled) mesh here, so
/// that an error points at the bone.
fn skeleton_spec(
    src: &Source<'_>,
    body: &str,
    bend: &Spanned<BendFile>,
    mesh: &TriMesh,
) -> Result<SkeletonSpec, SceneError> {
    let file = bend.get_ref();
    let given = match (&file.skeleton, &file.bone_tables) {
        (Some(skeleton), Some(tables)) => {
            let message = match skeleton.get_ref() {
                SkeletonFile::Auto => "[[body.bend.bone]] tables give the bones: leave out skeleton = \"auto\"",
                SkeletonFile::Bones(_) => "give the bones either in skeleton = [ … ] or as [[body.bend.bone]] tables",
            };
            return Err(src.error_at(tables.span(), Some(body), "bend.bone", message));
        }
        (Some(skeleton), None) => match skeleton.get_ref() {
            SkeletonFile::Auto => None,
            SkeletonFile::Bones(bones) => Some(("bend.skeleton", skeleton.span(), bones)),
        },
        (None, Some(tables)) => Some(("bend.bone", tables.span(), tables.get_ref())),
        (None, None) => None,
    };
    let Some((field, span, bones)) = given else {
        let count = file.bones.as_ref().map_or(1, |b| *b.get_ref());
        if !(1..=MAX_AUTO_BONES).contains(&count) {
            let at = span_of(&file.bones).unwrap_or_else(|| bend.span());
            let message = format!("{count} must be in 1..={MAX_AUTO_BONES}");
            return Err(src.error_at(at, Some(body), "bend.bones", message));
        }
        auto_skeleton(mesh, count).map_err(|e| {
            let at = span_of(&file.skeleton).or_else(|| span_of(&file.bones)).unwrap_or_else(|| bend.span());
            src.error_at(at, Some(body), "bend.skeleton", e.to_string())
        })?;
        return Ok(SkeletonSpec::Auto { bones: count });
    };
    if let Some(count) = &file.bones {
        let message = "only applies with skeleton = \"auto\" (the bones are given)";
        return Err(src.error_at(count.span(), Some(body), "bend.bones", message));
    }
    let descs: Vec<BoneDesc> = bones
        .iter()
        .map(|b| {
            let b = b.get_ref();
            let point = |p: &Spanned<super::file_values::Triple>| Vec3::from_array(p.get_ref().0);
            BoneDesc::new(point(&b.head), point(&b.tail), b.parent.as_ref().map(|p| *p.get_ref()))
        })
        .collect();
    let skeleton = Skeleton::new(descs.clone()).map_err(|e| bone_error(src, body, field, span.clone(), bones, e))?;
    skeleton.check_against(mesh).map_err(|e| bone_error(src, body, field, span, bones, e))?;
    Ok(SkeletonSpec::Bones(descs))
}

/// A skeleton error placed on the bone (and the end or parent) it names.
fn bone_error(
    src: &Source<'_>,
    body: &str,
    field: &str,
    all: Range<usize>,
    bones: &[Spanned<BoneFile>],
    error: BendError,
) -> SceneError {
    let bone_span = |k: usize| bones.get(k).map(Spanned::span);
    let parent_span = |k: usize| bones.get(k).and_then(|b| b.get_ref().parent.as_ref()).map(Spanned::span);
    let (at, bone, part) = match &error {
        BendError::NonFiniteBone { bone, end, .. } => {
            let end_span = bones
                .get(*bone)
                .map(|b| if *end == "head" { b.get_ref().head.span() } else { b.get_ref().tail.span() });
            (end_span, Some(*bone), Some(*end))
        }
        BendError::ParentOutOfRange { bone, .. }
        | BendError::Cycle { bone, .. }
        | BendError::DetachedJoint { bone, .. } => (parent_span(*bone), Some(*bone), Some("parent")),
        BendError::ZeroLengthBone { bone, .. } | BendError::BoneOutsideMesh { bone, .. } => {
            (bone_span(*bone), Some(*bone), None)
        }
        BendError::MultipleRoots { roots } => (roots.get(1).and_then(|&k| bone_span(k)), None, None),
        _ => (None, None, None),
    };
    let mut field = field.to_owned();
    if let Some(bone) = bone {
        field += &format!("[{bone}]");
    }
    if let Some(part) = part {
        field += &format!(".{part}");
    }
    src.error_at(at.unwrap_or(all), Some(body), &field, error.to_string())
}

/// The `joint` tables of given bones → the joints with their own kind (bone k's table is the
/// joint at its head); the root bone hangs from no joint and may not have one.
fn joint_overrides(src: &Source<'_>, body: &str, bend: &Spanned<BendFile>) -> Result<Vec<JointOverride>, SceneError> {
    let file = bend.get_ref();
    let (field, bones) = match (&file.skeleton, &file.bone_tables) {
        (Some(skeleton), _) => match skeleton.get_ref() {
            SkeletonFile::Bones(bones) => ("bend.skeleton", bones.as_slice()),
            SkeletonFile::Auto => return Ok(Vec::new()),
        },
        (None, Some(tables)) => ("bend.bone", tables.get_ref().as_slice()),
        (None, None) => return Ok(Vec::new()),
    };
    let mut overrides = Vec::new();
    for (child, bone) in bones.iter().enumerate() {
        let Some(joint) = &bone.get_ref().joint else { continue };
        let prefix = format!("{field}[{child}].joint");
        if bone.get_ref().parent.is_none() {
            let message = "the root bone hangs from no joint: give `joint` on a bone with a `parent`";
            return Err(src.error_at(joint.span(), Some(body), &prefix, message));
        }
        overrides.push(JointOverride { child, joint: joint_kind(src, body, &prefix, joint)? });
    }
    Ok(overrides)
}

/// A joint table → a [`JointKind`]: every number the kind takes is required, numbers of other
/// kinds are refused, and the values are checked by [`JointKind::validate`].
fn joint_kind(src: &Source<'_>, body: &str, prefix: &str, joint: &Spanned<JointFile>) -> Result<JointKind, SceneError> {
    let file = joint.get_ref();
    let kind = *file.kind.get_ref();
    let numbers = [
        ("strength", &file.strength),
        ("damping_constant", &file.damping_constant),
        ("damping_proportional", &file.damping_proportional),
        ("stiffness", &file.stiffness),
        ("damping", &file.damping),
    ];
    let takes: &[&str] = match kind {
        JointKindSpec::Rigid | JointKindSpec::Ball => &[],
        JointKindSpec::Plastic => &["strength", "damping_constant", "damping_proportional"],
        JointKindSpec::Elastic => &["stiffness", "damping"],
        JointKindSpec::ElasticPrismatic => &["axis", "stiffness", "damping"],
    };
    let axis_span = span_of(&file.axis);
    let present = numbers.iter().map(|(name, v)| (*name, span_of(v))).chain([("axis", axis_span.clone())]);
    for (name, span) in present {
        if let Some(span) = span.filter(|_| !takes.contains(&name)) {
            let message = format!("does not apply to {} joint", kind.with_article());
            return Err(src.error_at(span, Some(body), &format!("{prefix}.{name}"), message));
        }
    }
    let need = |name: &str, v: &Option<Spanned<f32>>| {
        v.as_ref().map(|v| *v.get_ref()).ok_or_else(|| missing(src, body, prefix, joint, kind, name))
    };
    let result = match kind {
        JointKindSpec::Rigid => JointKind::Rigid,
        JointKindSpec::Ball => JointKind::Ball,
        JointKindSpec::Plastic => JointKind::Bend(JointRule::Plastic {
            strength: need("strength", &file.strength)?,
            damping_constant: need("damping_constant", &file.damping_constant)?,
            damping_proportional: need("damping_proportional", &file.damping_proportional)?,
        }),
        JointKindSpec::Elastic => JointKind::Bend(JointRule::Elastic {
            stiffness: need("stiffness", &file.stiffness)?,
            damping: need("damping", &file.damping)?,
        }),
        JointKindSpec::ElasticPrismatic => JointKind::ElasticPrismatic {
            axis: file
                .axis
                .as_ref()
                .map(|a| Vec3::from_array(a.get_ref().0))
                .ok_or_else(|| missing(src, body, prefix, joint, kind, "axis"))?,
            stiffness: need("stiffness", &file.stiffness)?,
            damping: need("damping", &file.damping)?,
        },
    };
    result.validate().map_err(|error| {
        let (what, message) = match &error {
            SimError::Invalid { what, value, reason } => (what.as_str(), format!("{value} {reason}")),
            other => ("", other.to_string()),
        };
        let name = what.strip_prefix("joint ").unwrap_or(what);
        let span = if name == "axis" {
            axis_span.clone()
        } else {
            numbers.iter().find(|(n, _)| *n == name).and_then(|(_, v)| span_of(v))
        };
        src.error_at(span.unwrap_or_else(|| joint.span()), Some(body), &format!("{prefix}.{name}"), message)
    })?;
    Ok(result)
}

/// A number a joint kind needs that the table leaves out, placed on its `kind`.
fn missing(
    src: &Source<'_>,
    body: &str,
    prefix: &str,
    joint: &Spanned<JointFile>,
    kind: JointKindSpec,
    name: &str,
) -> SceneError {
    let message = format!("{} joint needs `{name}`", kind.with_article());
    src.error_at(joint.get_ref().kind.span(), Some(body), &format!("{prefix}.{name}"), message)
}

/// `[body.bend.dynamic]` → dynamic articulation, every value checked.
fn dynamic_articulation(
    src: &Source<'_>,
    body: &str,
    dynamic: &Spanned<DynamicFile>,
) -> Result<DynamicArticulation, SceneError> {
    let file = dynamic.get_ref();
    let check = |field: &str, value: &Spanned<f32>, ok: fn(f32) -> bool, rule: &str| {
        number(src, Some(body), field, &Some(value.clone()), ok, rule).map(|v| v.unwrap_or_default())
    };
    let speed = check(
        "bend.dynamic.speed_threshold",
        &file.speed_threshold,
        |v| v.is_finite() && v >= 0.0,
        "m/s must be finite and >= 0",
    )?;
    let min_length =
        check("bend.dynamic.min_bone_length", &file.min_bone_length, positive, "m must be finite and > 0")?;
    let joint = joint_kind(src, body, "bend.dynamic.joint", &file.joint)?;
    let mut articulation = DynamicArticulation::new(speed, joint, min_length);
    articulation.max_joints = match &file.max_joints {
        Some(m) if !(1..=MAX_AUTO_BONES).contains(m.get_ref()) => {
            let message = format!(
                "{} must be in 1..={MAX_AUTO_BONES} (leave out [body.bend.dynamic] for no dynamic joints)",
                m.get_ref()
            );
            return Err(src.error_at(m.span(), Some(body), "bend.dynamic.max_joints", message));
        }
        Some(m) => *m.get_ref(),
        None => articulation.max_joints,
    };
    Ok(articulation)
}
