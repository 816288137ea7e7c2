//! A bending body living in a [`World`]: one rigid sub-body per bone, joined at the skeleton's
//! joints, and its rest mesh skinned to the sub-bodies' poses every frame (paper Algorithm 2,
//! steps 1–3 and 13).

use std::sync::atomic::{AtomicU64, Ordering};

use glam::{Affine3A, Quat, Vec3};

use super::bendable::bend_error;
use super::{BendableDesc, DynamicArticulation};
use crate::sim::{BodyDesc, BodyKind, ColliderKind, DentSettings, SimError, SurfaceMaterial, World};
use dentbend::bend::{LevelSet, Rig, Skeleton, SkinWeights, SubBodies, WeightParams};
use dentbend::cpu::{self, SkinBone, SkinParams, Skinned};
use dentbend::mesh::TriMesh;

/// A bending body: its rest pose (mesh, skeleton, weights, sub-bodies) and the world bodies that
/// simulate its bones.
///
/// Bone k is simulated by the world body [`body_indices`](Self::body_indices)`[k]`, named
/// `<name>/bone<k>`, whose mesh is the bone's open sub-mesh ([`SubBodies::sub_mesh`]), whose
/// collider is the convex hull of it and whose mass properties are its level-set cells'; the
/// sub-bodies of one bending body do not collide with each other. The
/// model frame of every sub-body is the rest mesh's, so a bone's skinning matrix is its body's
/// [`model_transform`](crate::sim::RigidBody::model_transform) (model → world). Sub-body masses
/// and inertias are their voxel shares scaled so that they add up to the closed mesh's exact
/// mass (the voxel mass of a thin body is off by tens of percent at coarse resolutions).
#[derive(Debug, Clone)]
pub struct ArticulatedBody {
    pub(crate) name: String,
    /// Rest mesh, skeleton, weights and sub-bodies (its weight cache shared by copies of one
    /// body: see [`new_like`](Self::new_like)).
    pub(crate) rig: Rig,
    pub(crate) bodies: Vec<usize>,
    pub(crate) surface: SurfaceMaterial,
    /// Each sub-body's collider kind (convex hull or capsule, fitted to its part).
    pub(crate) collider: ColliderKind,
    pub(crate) color: [f32; 3],
    pub(crate) dynamic: Option<DynamicArticulation>,
    /// Joints added by dynamic articulation so far.
    pub(crate) added_joints: usize,
    /// The mesh's exact mass over the level set's voxel mass: sub-body masses and inertias are
    /// scaled by it, so that they add up to the mesh's mass even at coarse resolutions.
    pub(crate) mass_scale: f32,
    /// Denting behaviour of the whole body (its sub-bodies are not dentable themselves).
    pub(crate) dent: Option<DentSettings>,
    /// Revision of `rest_mesh` and `influences` (see [`rest_revision`](Self::rest_revision)):
    /// change them through `set_rest_mesh` and `set_influences`, which renew it.
    pub(crate) rest_revision: u64,
}

impl ArticulatedBody {
    /// Builds the body's skeleton, weights and sub-bodies and adds one world body per bone and one
    /// world joint (of [`desc.joint_kind`](BendableDesc::joint_kind)) per skeleton joint to `world`.
    ///
    /// # Errors
    /// As [`BendableDesc::validate`] and [`BendableDesc::build_skeleton`]; [`SimError::BadShape`]
    /// for an open mesh, an empty level set or a bone that owns no triangle or no inside cell at
    /// this resolution; [`SimError::Invalid`] for a sub-body name already taken. The world is
    /// unchanged on error.
    pub fn new(world: &mut World, desc: BendableDesc) -> Result<Self, SimError> {
        Self::at_rest(&desc)?.place(world, &desc)
    }

    /// Like [`new`](Self::new), but takes the rest state (skeleton, weights, sub-bodies) from
    /// `template` when it was made from the same mesh, skeleton, weight parameters and density
    /// and has not been split since: many copies of one body (the struts of Figure 13) then cost
    /// one weight computation.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn new_like(world: &mut World, desc: BendableDesc, template: &Self) -> Result<Self, SimError> {
        desc.validate()?;
        let same = template.added_joints == 0
            && template.rig.density() == desc.density
            && template.rig.cache().params() == desc.weights
            && *template.rig.rest() == desc.mesh
            && desc.build_skeleton()? == *template.rig.skeleton();
        if !same {
            return Self::new(world, desc);
        }
        let mut body = template.clone();
        body.name.clone_from(&desc.name);
        body.bodies.clear();
        body.surface = desc.surface;
        body.collider = desc.collider.resolve(BodyKind::Dynamic);
        body.color = desc.color;
        body.dynamic = desc.dynamic;
        body.dent.clone_from(&desc.dent);
        body.place(world, &desc)
    }

    /// The rest state of `desc`: skeleton, weights, sub-bodies (no world bodies yet).
    fn at_rest(desc: &BendableDesc) -> Result<Self, SimError> {
        desc.validate()?;
        let skeleton = desc.build_skeleton()?;
        let fail = |e| bend_error(&desc.name, e);
        let rig = Rig::new(desc.mesh.clone(), skeleton, desc.weights, desc.density).map_err(fail)?;
        let mut body = Self {
            name: desc.name.clone(),
            rig,
            bodies: Vec::new(),
            surface: desc.surface,
            collider: desc.collider.resolve(BodyKind::Dynamic),
            color: desc.color,
            dynamic: desc.dynamic,
            added_joints: 0,
            mass_scale: 1.0,
            dent: desc.dent.clone(),
            rest_revision: next_rest_revision(),
        };
        let exact = crate::sim::mass_properties(&desc.mesh, desc.density).map(|m| m.mass);
        let voxels = body.rig.sub_bodies().total().mass;
        if let Some(exact) = exact.filter(|&m| m.is_finite() && m > 0.0 && voxels > 0.0) {
            body.mass_scale = exact / voxels;
        }
        Ok(body)
    }

    /// Adds one world body per bone and one world joint per skeleton joint for `desc`'s pose
    /// and motion; the world is unchanged on error.
    fn place(mut self, world: &mut World, desc: &BendableDesc) -> Result<Self, SimError> {
        let rotation = desc.orientation.normalize();
        let pose = Affine3A::from_rotation_translation(rotation, desc.position);
        let centre = pose.transform_point3(self.rig.sub_bodies().total().center);
        let motion = RigidMotion { velocity: desc.linear_velocity, angular: desc.angular_velocity, centre };
        let descs = (0..self.rig.skeleton().len())
            .map(|bone| self.sub_body_desc(bone, (desc.position, rotation), motion))
            .collect::<Result<Vec<_>, _>>()?;
        if let Some(taken) = descs.iter().find(|d| world.find(&d.name).is_some()) {
            return Err(SimError::Invalid {
                what: format!("bendable body \"{}\"", desc.name),
                value: taken.name.clone(),
                reason: "names a sub-body like a body already in the world",
            });
        }
        let (bodies_before, joints_before) = (world.bodies().len(), world.joints().len());
        let added = (|| {
            for d in descs {
                self.bodies.push(world.add(d)?);
            }
            for joint in self.rig.skeleton().joints() {
                let anchor = pose.transform_point3(joint.point);
                let kind = desc.joint_kind(joint.child);
                world.add_joint(self.bodies[joint.parent], self.bodies[joint.child], anchor, kind)?;
            }
            ignore_own_collisions(world, &self.bodies)
        })();
        if let Err(e) = added {
            world.truncate(bodies_before, joints_before);
            return Err(e);
        }
        Ok(self)
    }

    /// The body's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The rest mesh, model frame, m.
    pub fn rest_mesh(&self) -> &TriMesh {
        self.rig.rest()
    }

    /// The skeleton now (grows by one bone per dynamic joint).
    pub fn skeleton(&self) -> &Skeleton {
        self.rig.skeleton()
    }

    /// The skinning weights now.
    pub fn weights(&self) -> &SkinWeights {
        self.rig.weights()
    }

    /// The sub-bodies now.
    pub fn sub_bodies(&self) -> &SubBodies {
        self.rig.sub_bodies()
    }

    /// The rig: rest mesh, skeleton, weights, sub-bodies.
    pub fn rig(&self) -> &Rig {
        &self.rig
    }

    /// The level set of the rest mesh (model frame) that the sub-bodies' cells come from.
    pub fn level_set(&self) -> &LevelSet {
        self.rig.cache().level_set()
    }

    /// Every bone's open sub-body surface ([`SubBodies::sub_mesh`]) in the model frame, m, in
    /// bone order.
    ///
    /// # Errors
    /// [`SimError::BadShape`] if a bone owns no triangle (never for a body built by
    /// [`new`](Self::new), which refuses that).
    pub fn sub_meshes(&self) -> Result<Vec<TriMesh>, SimError> {
        (0..self.rig.skeleton().len())
            .map(|bone| self.rig.part(bone))
            .collect::<Result<_, _>>()
            .map_err(|e| bend_error(&self.name, e))
    }

    /// The weight parameters (level-set resolution…).
    pub fn weight_params(&self) -> WeightParams {
        self.rig.cache().params()
    }

    /// Level-set cell size, m.
    pub fn cell_size(&self) -> f32 {
        self.rig.cache().level_set().cell_size()
    }

    /// World body index of each bone.
    pub fn body_indices(&self) -> &[usize] {
        &self.bodies
    }

    /// The bone simulated by world body `index`, if it is one of this body's.
    pub fn bone_of(&self, index: usize) -> Option<usize> {
        self.bodies.iter().position(|&b| b == index)
    }

    /// Dynamic articulation settings.
    pub fn dynamic(&self) -> Option<&DynamicArticulation> {
        self.dynamic.as_ref()
    }

    /// Colour for pictures.
    pub fn color(&self) -> [f32; 3] {
        self.color
    }

    /// Every bone's model → world transform now (its sub-body's model transform).
    ///
    /// # Errors
    /// [`SimError::Invalid`] if a sub-body is missing from `world` (another world).
    pub fn bone_transforms(&self, world: &World) -> Result<Vec<Affine3A>, SimError> {
        self.bodies
            .iter()
            .map(|&i| {
                world.bodies().get(i).map(|b| b.model_transform()).ok_or_else(|| SimError::Invalid {
                    what: format!("bendable body \"{}\": sub-body index", self.name),
                    value: i.to_string(),
                    reason: "is not a body of this world",
                })
            })
            .collect()
    }

    /// The rest mesh skinned to the sub-bodies' current poses ([`cpu::skin`](dentbend::cpu::skin)
    /// with bone matrices = model transforms), world coordinates, m.
    ///
    /// # Errors
    /// As [`bone_transforms`](Self::bone_transforms); [`SimError::BadShape`] if skinning fails.
    pub fn skinned_mesh(&self, world: &World) -> Result<TriMesh, SimError> {
        self.skin_rest(self.rig.rest(), &self.bone_transforms(world)?)
    }

    /// `rest` (a mesh with the rest mesh's vertices and faces) skinned with the weights to the
    /// bone matrices `bones` (model → the output's frame), m.
    ///
    /// # Errors
    /// [`SimError::BadShape`] if skinning fails (wrong vertex or bone count).
    pub(crate) fn skin_rest(&self, rest: &TriMesh, bones: &[Affine3A]) -> Result<TriMesh, SimError> {
        let bones: Vec<SkinBone> = bones.iter().copied().map(SkinBone::from_affine).collect();
        let mut out = Skinned::default();
        self.skin_rest_on_cpu(rest, &bones, &mut out)?;
        let mut mesh = rest.clone();
        mesh.set_positions(out.positions).map_err(|e| self.skin_error(e))?;
        Ok(mesh)
    }

    /// [`cpu::skin`] of `rest` (a mesh with the body's rest vertices, dented or not) with the
    /// body's influences and `bones` into `out` (resized to the vertex count).
    ///
    /// # Errors
    /// [`SimError::BadShape`] if skinning fails (wrong vertex or bone count).
    pub(crate) fn skin_rest_on_cpu(
        &self,
        rest: &TriMesh,
        bones: &[SkinBone],
        out: &mut Skinned,
    ) -> Result<(), SimError> {
        let n = rest.vertex_count();
        out.positions.resize(n, Vec3::ZERO);
        out.normals.resize(n, Vec3::ZERO);
        let params = SkinParams::new(n as u32, bones.len() as u32);
        let (positions, normals) = (rest.positions(), rest.normals());
        cpu::skin(&params, bones, positions, normals, self.influences(), &mut out.positions, &mut out.normals)
            .map_err(|e| self.skin_error(e))
    }

    /// A [`SimError::BadShape`] naming the body for a skinning failure.
    pub(crate) fn skin_error(&self, error: impl std::fmt::Display) -> SimError {
        SimError::BadShape { body: self.name().to_owned(), reason: format!("skinning: {error}") }
    }

    /// The world body of `bone` as its sub-body now, its model frame's origin at `pose.0` (world,
    /// m) turned by `pose.1`, moving with `motion`.
    pub(crate) fn sub_body_desc(
        &self,
        bone: usize,
        (origin, rotation): (Vec3, Quat),
        motion: RigidMotion,
    ) -> Result<BodyDesc, SimError> {
        let fail = |e| bend_error(&self.name, e);
        let mesh = self.rig.part(bone).map_err(fail)?;
        let mut mass =
            self.rig.sub_bodies().bodies().get(bone).and_then(|s| s.mass).ok_or_else(|| SimError::BadShape {
                body: self.name.clone(),
                reason: format!(
                    "bending: bone {bone} owns no inside cell of the level set (resolution {}): raise the resolution",
                    self.rig.cache().params().resolution
                ),
            })?;
        mass.mass *= self.mass_scale;
        mass.volume *= self.mass_scale;
        mass.inertia *= self.mass_scale;
        let centre = origin + rotation * mass.center;
        let mut desc = BodyDesc::new(format!("{}/bone{bone}", self.name), mesh)
            .with_mass_properties(mass)
            .collider(self.collider)
            .at(origin)
            .velocity(motion.at(centre));
        desc.orientation = rotation;
        desc.angular_velocity = motion.angular;
        desc.density = self.rig.density();
        desc.surface = self.surface;
        desc.color = self.color;
        Ok(desc)
    }
}

/// A rigid motion: `velocity` (m/s) of the point `centre` (world, m) and `angular` velocity
/// (rad/s, world axes).
#[derive(Debug, Clone, Copy)]
pub(crate) struct RigidMotion {
    pub velocity: Vec3,
    pub angular: Vec3,
    pub centre: Vec3,
}

impl RigidMotion {
    /// Velocity of world point `point` under this motion, m/s (v + ω × r).
    pub fn at(&self, point: Vec3) -> Vec3 {
        self.velocity + self.angular.cross(point - self.centre)
    }
}

/// Stops every two of one bending body's sub-bodies (world indices `bodies`) from colliding with
/// each other: their convex-hull colliders overlap where they meet (the bunny's ears, its body
/// and head), and a body does not collide with itself.
pub(crate) fn ignore_own_collisions(world: &mut World, bodies: &[usize]) -> Result<(), SimError> {
    for (k, &a) in bodies.iter().enumerate() {
        for &b in &bodies[k + 1..] {
            world.ignore_collisions(a, b)?;
        }
    }
    Ok(())
}

/// A revision no body has had yet in this process: numbers come from one process-wide counter,
/// so two bodies share a revision only when one is a copy of the other with the same rest data.
pub(crate) fn next_rest_revision() -> u64 {
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}
