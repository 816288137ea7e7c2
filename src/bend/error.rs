//! Errors raised while building skeletons, level sets, skinning weights and sub-bodies.

use crate::cpu::SkinError;
use crate::mesh::MeshError;

/// Everything that can go wrong on the geometry side of bending.
///
/// Every entry point validates its input first, so an error leaves the caller's skeleton, mesh
/// and weights unchanged. Messages name the offending bone by its index.
#[derive(Debug, thiserror::Error)]
pub enum BendError {
    /// A skeleton needs at least one bone.
    #[error("the skeleton has no bones")]
    NoBones,
    /// A bone endpoint has a NaN or infinite coordinate.
    #[error("bone {bone}: its {end} {value:?} has a non-finite coordinate")]
    NonFiniteBone {
        /// Index of the bone.
        bone: usize,
        /// `"head"` or `"tail"`.
        end: &'static str,
        /// The coordinates given, m.
        value: [f32; 3],
    },
    /// A bone is too short to define a direction.
    #[error("bone {bone}: its length {length} m is not above the minimum {minimum} m (head and tail coincide)")]
    ZeroLengthBone {
        /// Index of the bone.
        bone: usize,
        /// Its length, m.
        length: f32,
        /// The smallest length accepted, m.
        minimum: f32,
    },
    /// A bone names a parent that does not exist.
    #[error("bone {bone}: parent index {parent} is out of range (the skeleton has {count} bones)")]
    ParentOutOfRange {
        /// Index of the bone.
        bone: usize,
        /// The parent index given.
        parent: usize,
        /// Number of bones.
        count: usize,
    },
    /// Following parents from a bone comes back to it.
    #[error("bone {bone}: its parent chain forms a cycle ({})", format_cycle(.cycle))]
    Cycle {
        /// A bone on the cycle.
        bone: usize,
        /// The bones of the cycle in parent order, starting at `bone`.
        cycle: Vec<usize>,
    },
    /// More than one bone has no parent; a skeleton must be one connected tree.
    #[error("the skeleton has {} roots (bones {roots:?} have no parent); exactly one bone may have no parent", .roots.len())]
    MultipleRoots {
        /// The bones without a parent.
        roots: Vec<usize>,
    },
    /// A child's head (its joint) is far from its parent bone.
    #[error(
        "bone {bone}: its head is {gap} m from its parent bone {parent}, more than the {limit} m allowed (half its own length)"
    )]
    DetachedJoint {
        /// Index of the child bone.
        bone: usize,
        /// Index of its parent.
        parent: usize,
        /// Distance from the child's head to the parent segment, m.
        gap: f32,
        /// Largest distance accepted, m.
        limit: f32,
    },
    /// A bone lies entirely outside the mesh, farther than the tolerance from its surface.
    #[error(
        "bone {bone} lies entirely outside the mesh: it is {distance} m from the surface (tolerance {tolerance} m)"
    )]
    BoneOutsideMesh {
        /// Index of the bone.
        bone: usize,
        /// Distance from the bone to the surface (sampled along the bone), m.
        distance: f32,
        /// The tolerance, m.
        tolerance: f32,
    },
    /// A bone index passed to an operation does not exist.
    #[error("bone index {bone} is out of range (the skeleton has {count} bones)")]
    BoneOutOfRange {
        /// The index given.
        bone: usize,
        /// Number of bones.
        count: usize,
    },
    /// A split point projects too close to an end of the bone (or beyond it).
    #[error(
        "cannot split bone {bone} at t = {t} along it: the point must project between {min} and {max} of its length"
    )]
    SplitNearEnd {
        /// Index of the bone.
        bone: usize,
        /// Projection of the point onto the bone, as a fraction of its length from the head.
        t: f32,
        /// Smallest fraction accepted.
        min: f32,
        /// Largest fraction accepted.
        max: f32,
    },
    /// A numeric parameter is out of range or not finite.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// The value given, formatted.
        value: String,
        /// What is accepted.
        reason: &'static str,
    },
    /// The mesh is not closed: along some grid rows the winding number does not return to zero.
    #[error(
        "the mesh is not closed: the winding number does not return to zero along {open_rows} grid rows (they pass through holes; a level set needs a closed surface)"
    )]
    OpenMesh {
        /// Number of x-parallel grid rows through a hole.
        open_rows: usize,
    },
    /// The mesh encloses no voxel at the chosen resolution.
    #[error(
        "the mesh encloses no voxel centre at resolution {resolution}: it is too thin or flat; raise the resolution"
    )]
    EmptyInterior {
        /// The grid resolution used (cells along the longest side).
        resolution: u32,
    },
    /// Two inputs disagree in size (weights built for another mesh or skeleton).
    #[error("{what}: expected {expected}, got {actual}")]
    Mismatch {
        /// What was compared.
        what: &'static str,
        /// The size expected.
        expected: usize,
        /// The size given.
        actual: usize,
    },
    /// A mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Skinning refused its bones or influences.
    #[error(transparent)]
    Skin(#[from] SkinError),
}

fn format_cycle(cycle: &[usize]) -> String {
    let mut text: Vec<String> = cycle.iter().map(ToString::to_string).collect();
    if let Some(first) = cycle.first() {
        text.push(first.to_string());
    }
    text.join(" → ")
}
