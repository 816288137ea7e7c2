//! How a bendable body is described (paper §4): its rest mesh and pose, its skeleton (given or
//! automatic), how its skinning weights and sub-bodies are computed, the joints that hold its
//! bones together and, optionally, the dynamic articulation that adds joints where it is hit
//! (paper §4.2).

use glam::{Quat, Vec3};

use super::JointOverride;
use super::joint_override;
use crate::sim::{ColliderKind, DentSettings, JointKind, SimError, SurfaceMaterial};
use dentbend::bend::{BoneDesc, Skeleton, WeightParams, auto_skeleton};
use dentbend::mesh::TriMesh;

/// Where a bendable body's skeleton comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum SkeletonSpec {
    /// Bones given in the mesh's model frame (m), validated by [`Skeleton::new`] and checked to
    /// lie inside the mesh ([`Skeleton::check_against`]).
    Bones(Vec<BoneDesc>),
    /// A chain of `bones` equal bones along the mesh's principal axis ([`auto_skeleton`]).
    Auto {
        /// Number of bones, 1..=[`MAX_AUTO_BONES`](dentbend::bend::MAX_AUTO_BONES).
        bones: usize,
    },
}

/// Dynamic articulation (paper §4.2, Algorithm 2 steps 4–12): a hit whose closing normal speed
/// exceeds `speed_threshold` splits the nearest bone where the hit projects onto it and joins
/// the two halves there with a joint of kind `joint`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DynamicArticulation {
    /// Closing normal speed above which a hit adds a joint, m/s (finite, ≥ 0).
    pub speed_threshold: f32,
    /// Kind of the joints added (usually a plastic [`JointKind::Bend`]).
    pub joint: JointKind,
    /// No split leaves a bone shorter than this, m (finite, > 0): hits closer than this to a
    /// joint or a bone's end add nothing.
    pub min_bone_length: f32,
    /// Most joints the body gains this way (its bones grow by one per joint).
    pub max_joints: usize,
}

impl DynamicArticulation {
    /// Splits above `speed_threshold` m/s with joints of kind `joint`, bones at least
    /// `min_bone_length` m, at most 16 new joints.
    pub fn new(speed_threshold: f32, joint: JointKind, min_bone_length: f32) -> Self {
        Self { speed_threshold, joint, min_bone_length, max_joints: 16 }
    }
}

/// A bendable body: simulated as one rigid sub-body per bone (named `<name>/bone<k>`), joined by
/// joints of kind `joint` (or their override's) at the skeleton's joints, and drawn as its rest
/// mesh skinned to the sub-bodies' poses.
#[derive(Debug, Clone)]
pub struct BendableDesc {
    /// Unique name (the skinned mesh is written under it).
    pub name: String,
    /// The rest mesh in its model frame (closed), m.
    pub mesh: TriMesh,
    /// Where the model frame's origin starts, world, m.
    pub position: Vec3,
    /// Orientation of the model frame (unit after normalisation).
    pub orientation: Quat,
    /// Velocity of the whole body's centre of mass, m/s.
    pub linear_velocity: Vec3,
    /// Angular velocity of the whole body, rad/s, world axes.
    pub angular_velocity: Vec3,
    /// The skeleton.
    pub skeleton: SkeletonSpec,
    /// Level-set resolution, influences per vertex and falloff of the skinning weights.
    pub weights: WeightParams,
    /// Density, kg/m³ (finite, > 0); the sub-bodies' masses come from the level set's cells.
    pub density: f32,
    /// Restitution and friction of every sub-body.
    pub surface: SurfaceMaterial,
    /// Each sub-body's collider, fitted to its part of the mesh: [`ColliderKind::ConvexHull`]
    /// (also for [`Auto`](ColliderKind::Auto)) or [`ColliderKind::Capsule`] (rods and struts:
    /// one or two contact points per pair).
    pub collider: ColliderKind,
    /// Linear RGB colour for pictures.
    pub color: [f32; 3],
    /// Kind of the joints at the skeleton's joints, but those in `joint_overrides`.
    pub joint: JointKind,
    /// Joints given their own kind, by child bone (see [`joint_kind`](Self::joint_kind)).
    pub joint_overrides: Vec<JointOverride>,
    /// Dynamic articulation, `None` for none.
    pub dynamic: Option<DynamicArticulation>,
    /// Denting behaviour, `None` when the body does not dent: a hit on a sub-body dents the
    /// skinned mesh and the dent is mapped back to the rest mesh (see `bend::BendDenter`).
    pub dent: Option<DentSettings>,
}

impl BendableDesc {
    /// Kind of the joint at bone `child`'s head: its override, or [`joint`](Self::joint).
    pub fn joint_kind(&self, child: usize) -> JointKind {
        joint_override::kind_of(&self.joint_overrides, self.joint, child)
    }

    /// A body at rest at the origin: density 1000 kg/m³, a one-bone automatic skeleton, default
    /// weights, convex-hull colliders, rigid joints, no dynamic articulation and no denting.
    pub fn new(name: impl Into<String>, mesh: TriMesh) -> Self {
        Self {
            name: name.into(),
            mesh,
            position: Vec3::ZERO,
            orientation: Quat::IDENTITY,
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            skeleton: SkeletonSpec::Auto { bones: 1 },
            weights: WeightParams::default(),
            density: 1000.0,
            surface: SurfaceMaterial::default(),
            collider: ColliderKind::ConvexHull,
            color: [0.7, 0.7, 0.72],
            joint: JointKind::Rigid,
            joint_overrides: Vec::new(),
            dynamic: None,
            dent: None,
        }
    }

    /// Whether sub-bodies can collide as `collider` fitted to their parts: a convex hull (also
    /// [`Auto`](ColliderKind::Auto)) or a capsule.
    pub fn fits_parts(collider: ColliderKind) -> bool {
        matches!(collider, ColliderKind::Auto | ColliderKind::ConvexHull | ColliderKind::Capsule)
    }

    /// Checks every number (not the skeleton, see [`build_skeleton`](Self::build_skeleton)).
    ///
    /// # Errors
    /// [`SimError::Invalid`] naming the first bad field; [`SimError::Dent`] for bad dent
    /// settings (as a [`BodyDesc`](crate::sim::BodyDesc)'s).
    pub fn validate(&self) -> Result<(), SimError> {
        let field = |what: &str| format!("bendable body \"{}\": {what}", self.name);
        let invalid =
            |what: &str, value: String, reason: &'static str| SimError::Invalid { what: field(what), value, reason };
        if self.name.is_empty() {
            return Err(invalid("name", "\"\"".into(), "must not be empty"));
        }
        for (what, v) in [
            ("position", self.position),
            ("velocity", self.linear_velocity),
            ("angular_velocity", self.angular_velocity),
        ] {
            if !v.is_finite() {
                return Err(invalid(what, format!("{v:?}"), "must be finite"));
            }
        }
        if !self.orientation.is_finite() || self.orientation.length_squared() < 1e-12 {
            return Err(invalid("orientation", format!("{:?}", self.orientation), "must be finite and non-zero"));
        }
        if !(self.density.is_finite() && self.density > 0.0) {
            return Err(invalid("density", self.density.to_string(), "must be finite and > 0"));
        }
        if !Self::fits_parts(self.collider) {
            let reason = "a sub-body collides with its part's convex hull or a capsule fitted to it";
            return Err(invalid("collider", format!("{:?}", self.collider), reason));
        }
        self.weights.validate().map_err(|e| bend_error(&self.name, e))?;
        self.joint.validate().map_err(|e| invalid("joint", e.to_string(), "is not a valid joint"))?;
        joint_override::validate(&self.joint_overrides, &self.name)?;
        if let Some(d) = &self.dynamic {
            if !(d.speed_threshold.is_finite() && d.speed_threshold >= 0.0) {
                return Err(invalid("speed_threshold", d.speed_threshold.to_string(), "must be finite and >= 0"));
            }
            if !(d.min_bone_length.is_finite() && d.min_bone_length > 0.0) {
                return Err(invalid("min_bone_length", d.min_bone_length.to_string(), "must be finite and > 0"));
            }
            d.joint.validate().map_err(|e| invalid("dynamic joint", e.to_string(), "is not a valid joint"))?;
        }
        if let Some(dent) = &self.dent {
            dent.validate().map_err(|error| SimError::Dent { body: self.name.clone(), error })?;
        }
        Ok(())
    }

    /// The skeleton this description asks for, checked against the mesh and the joint overrides.
    ///
    /// # Errors
    /// As [`Skeleton::new`], [`auto_skeleton`] and [`Skeleton::check_against`] (NaN, zero-length
    /// bones, cycles, several roots, bones outside the mesh), as [`SimError::BadShape`];
    /// [`SimError::Invalid`] for a joint override whose child is not a bone with a parent.
    pub fn build_skeleton(&self) -> Result<Skeleton, SimError> {
        let skeleton = match &self.skeleton {
            SkeletonSpec::Bones(bones) => Skeleton::new(bones.clone()),
            SkeletonSpec::Auto { bones } => auto_skeleton(&self.mesh, *bones),
        }
        .map_err(|e| bend_error(&self.name, e))?;
        skeleton.check_against(&self.mesh).map_err(|e| bend_error(&self.name, e))?;
        joint_override::check_against(&self.joint_overrides, &skeleton, &self.name)?;
        Ok(skeleton)
    }
}

/// A bending error of body `name` as a [`SimError::BadShape`] ("body "plank": bending: …").
pub(crate) fn bend_error(name: &str, error: dentbend::bend::BendError) -> SimError {
    SimError::BadShape { body: name.into(), reason: format!("bending: {error}") }
}
