//! Rigid bodies: what a user describes ([`BodyDesc`]) and what the world simulates
//! ([`RigidBody`]: pose of the centre of mass, velocities, mass properties, collider, mesh).

use std::sync::Arc;

use glam::{Affine3A, Mat3, Quat, Vec3};
use parry3d::shape::SharedShape;

use super::BodyKind;
use super::activity::Activity;
use super::cluster::Role;
use super::error::invalid;
use super::{ColliderKind, DentSettings, MassProperties, SimError, mass_properties};
use dentbend::collider::VertexMap;
use dentbend::dent::MAX_SPEED;
use dentbend::fracture::FractureSettings;
use dentbend::mesh::{MAX_COORDINATE, TriMesh};

/// Fastest spin a body may start with, rad/s (10⁴: about 1600 turns a second).
pub(crate) const MAX_ANGULAR_SPEED: f32 = 1.0e4;
/// Densest material a body may have, kg/m³ (10⁶: forty times osmium).
pub(crate) const MAX_DENSITY: f32 = 1.0e6;

/// Surface response of a body in collisions and contacts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceMaterial {
    /// Coefficient of restitution in [0, 1]; a pair uses the larger of its two.
    pub restitution: f32,
    /// Coulomb friction coefficient ≥ 0; a pair uses the geometric mean of its two.
    pub friction: f32,
}

impl Default for SurfaceMaterial {
    fn default() -> Self {
        Self { restitution: 0.3, friction: 0.5 }
    }
}

/// Everything needed to add a body to a [`World`](super::World).
///
/// `mesh` is in the body's model coordinates; `position` and `orientation` place the model
/// frame in the world (world point = position + orientation · model point).
#[derive(Debug, Clone)]
pub struct BodyDesc {
    /// Unique name, used in events, output files and summaries.
    pub name: String,
    /// The surface, closed for dynamic bodies (its volume gives the mass).
    pub mesh: TriMesh,
    /// Static, dynamic or kinematic.
    pub kind: BodyKind,
    /// Where the model frame's origin is, m.
    pub position: Vec3,
    /// Orientation of the model frame.
    pub orientation: Quat,
    /// Velocity of the centre of mass, m/s.
    pub linear_velocity: Vec3,
    /// Angular velocity, rad/s (world axes).
    pub angular_velocity: Vec3,
    /// Density, kg/m³ (dynamic bodies).
    pub density: f32,
    /// Collision shape.
    pub collider: ColliderKind,
    /// Restitution and friction.
    pub surface: SurfaceMaterial,
    /// How the body dents, or `None` for a body that keeps its shape.
    pub dent: Option<DentSettings>,
    /// When and how the body breaks (prescored fracture), or `None` for a body that does not.
    pub fracture: Option<FractureSettings>,
    /// Linear RGB colour for pictures.
    pub color: [f32; 3],
    /// Mass properties to use instead of the mesh's (dynamic bodies): a sub-body of a bending
    /// body has an open surface and gets its mass from its voxels. `center` is in model
    /// coordinates.
    pub mass_properties: Option<MassProperties>,
}

impl BodyDesc {
    /// A dynamic body of density 1000 kg/m³ at rest at the origin, collider chosen from its kind.
    pub fn new(name: impl Into<String>, mesh: TriMesh) -> Self {
        Self {
            name: name.into(),
            mesh,
            kind: BodyKind::Dynamic,
            position: Vec3::ZERO,
            orientation: Quat::IDENTITY,
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            density: 1000.0,
            collider: ColliderKind::Auto,
            surface: SurfaceMaterial::default(),
            dent: None,
            fracture: None,
            color: [0.7, 0.7, 0.72],
            mass_properties: None,
        }
    }

    /// Builder: mass properties given instead of computed from the (possibly open) mesh.
    pub fn with_mass_properties(mut self, properties: MassProperties) -> Self {
        self.mass_properties = Some(properties);
        self
    }

    /// Builder: the kind.
    pub fn kind(mut self, kind: BodyKind) -> Self {
        self.kind = kind;
        self
    }

    /// Builder: position of the model origin, m.
    pub fn at(mut self, position: Vec3) -> Self {
        self.position = position;
        self
    }

    /// Builder: linear velocity, m/s.
    pub fn velocity(mut self, velocity: Vec3) -> Self {
        self.linear_velocity = velocity;
        self
    }

    /// Builder: collider kind.
    pub fn collider(mut self, collider: ColliderKind) -> Self {
        self.collider = collider;
        self
    }

    /// Builder: breaks as `settings` say (see [`dentbend::fracture`]).
    pub fn breakable(mut self, settings: FractureSettings) -> Self {
        self.fracture = Some(settings);
        self
    }

    /// Builder: dentable with `settings`.
    pub fn dentable(mut self, settings: DentSettings) -> Self {
        self.dent = Some(settings);
        self
    }

    /// Checks every number; the mesh was validated when it was built.
    fn validate(&self) -> Result<(), SimError> {
        let field = |what: &str| format!("body \"{}\": {what}", self.name);
        if self.name.is_empty() {
            return Err(invalid("body name", &self.name, "must not be empty"));
        }
        for (what, v, limit, rule) in [
            ("position", self.position, MAX_COORDINATE, "must be finite and within ±1e6 m along each axis"),
            ("linear_velocity", self.linear_velocity, MAX_SPEED, "must be finite and at most 1e5 m/s"),
            ("angular_velocity", self.angular_velocity, MAX_ANGULAR_SPEED, "must be finite and at most 1e4 rad/s"),
        ] {
            let magnitude = if what == "position" { v.abs().max_element() } else { v.length() };
            if !(v.is_finite() && magnitude <= limit) {
                return Err(invalid(field(what), v, rule));
            }
        }
        if !self.orientation.is_finite() || self.orientation.length_squared() < 1e-12 {
            return Err(invalid(field("orientation"), self.orientation, "must be a finite non-zero quaternion"));
        }
        if self.kind == BodyKind::Dynamic
            && !(self.density.is_finite() && self.density > 0.0 && self.density <= MAX_DENSITY)
        {
            return Err(invalid(field("density"), self.density, "must be finite, > 0 and at most 1e6 kg/m³"));
        }
        let SurfaceMaterial { restitution, friction } = self.surface;
        if !(0.0..=1.0).contains(&restitution) {
            return Err(invalid(field("restitution"), restitution, "must be in [0, 1]"));
        }
        if !(friction.is_finite() && friction >= 0.0) {
            return Err(invalid(field("friction"), friction, "must be finite and >= 0"));
        }
        if let Some(dent) = &self.dent {
            dent.validate().map_err(|error| SimError::Dent { body: self.name.clone(), error })?;
        }
        if let Some(fracture) = &self.fracture {
            fracture.validate().map_err(|error| SimError::Fracture { body: self.name.clone(), error })?;
        }
        if !self.color.iter().all(|c| c.is_finite()) {
            return Err(invalid(field("color"), self.color, "must be finite"));
        }
        if let Some(p) = &self.mass_properties {
            if !(p.mass.is_finite() && p.mass > 0.0) {
                return Err(invalid(field("mass"), p.mass, "must be finite and > 0"));
            }
            if !p.center.is_finite() || !p.inertia.is_finite() {
                return Err(invalid(field("mass properties"), p.center, "must be finite"));
            }
        }
        Ok(())
    }
}

/// A body in the world. Its mesh is stored in body coordinates: the centre of mass at the origin,
/// axes those of the model frame, so world point = `position` + `orientation` · body point.
#[derive(Debug, Clone)]
pub struct RigidBody {
    /// Unique name.
    pub name: String,
    /// Static, dynamic or kinematic.
    pub kind: BodyKind,
    /// World position of the centre of mass (the model origin for static and kinematic bodies), m.
    pub position: Vec3,
    /// Orientation (unit).
    pub orientation: Quat,
    /// Velocity of the centre of mass, m/s.
    pub linear_velocity: Vec3,
    /// Angular velocity, rad/s, world axes.
    pub angular_velocity: Vec3,
    /// Restitution and friction.
    pub surface: SurfaceMaterial,
    /// Denting behaviour, `None` when the body does not dent.
    pub dent: Option<DentSettings>,
    /// Fracture behaviour, `None` when the body does not break.
    pub fracture: Option<FractureSettings>,
    /// Linear RGB colour for pictures.
    pub color: [f32; 3],
    /// Mass, kg (∞ for static and kinematic bodies).
    pub mass: f32,
    /// Inertia tensor about the centre of mass in body axes, kg·m².
    pub inertia: Mat3,
    pub(crate) inverse_mass: f32,
    pub(crate) inverse_inertia: Mat3,
    /// The model origin in body coordinates (minus the centre of mass in model coordinates), m.
    pub(crate) model_offset: Vec3,
    /// Shared, so that copying a world (a staged edit, a snapshot) does not copy meshes.
    pub(crate) mesh: Arc<TriMesh>,
    pub(crate) collider_kind: ColliderKind,
    pub(crate) shape: SharedShape,
    /// For a triangle-mesh collider, which mesh vertex each collider vertex follows (parry may
    /// renumber them); filled on the first refit, dropped when the collider is rebuilt.
    pub(crate) collider_map: Option<Arc<VertexMap>>,
    /// Sleep bookkeeping.
    pub(crate) activity: Activity,
    /// Simulated on its own, condensed into a rigid cluster, or a cluster's proxy.
    pub(crate) role: Role,
}

impl RigidBody {
    /// Builds a body from its description: mass properties from the mesh and density (dynamic
    /// bodies), mesh moved to body coordinates, collider built.
    ///
    /// # Errors
    /// [`SimError::Invalid`] for a bad number, [`SimError::BadShape`] for a dynamic body whose
    /// mesh encloses no volume or a collider that cannot be built.
    pub fn new(desc: BodyDesc) -> Result<Self, SimError> {
        desc.validate()?;
        let orientation = desc.orientation.normalize();
        let (mass, inertia, center) = if desc.kind == BodyKind::Dynamic {
            let props = match desc.mass_properties {
                Some(given) => given,
                None => mass_properties(&desc.mesh, desc.density).ok_or_else(|| SimError::BadShape {
                    body: desc.name.clone(),
                    reason: "a dynamic body's mesh must be closed and enclose a volume".into(),
                })?,
            };
            (props.mass, props.inertia, props.center)
        } else {
            (f32::INFINITY, Mat3::ZERO, Vec3::ZERO)
        };
        let mut mesh = desc.mesh;
        if center != Vec3::ZERO {
            mesh.transform(Affine3A::from_translation(-center))?;
        }
        let shape = desc
            .collider
            .build_for(desc.kind, &mesh)
            .map_err(|reason| SimError::BadShape { body: desc.name.clone(), reason })?;
        let (inverse_mass, inverse_inertia) = if desc.kind == BodyKind::Dynamic {
            let inverse = inertia.inverse();
            if !inverse.is_finite() {
                return Err(SimError::BadShape { body: desc.name, reason: "inertia tensor is singular".into() });
            }
            (1.0 / mass, inverse)
        } else {
            (0.0, Mat3::ZERO)
        };
        Ok(Self {
            name: desc.name,
            kind: desc.kind,
            position: desc.position + orientation * center,
            orientation,
            linear_velocity: if desc.kind == BodyKind::Static { Vec3::ZERO } else { desc.linear_velocity },
            angular_velocity: if desc.kind == BodyKind::Static { Vec3::ZERO } else { desc.angular_velocity },
            surface: desc.surface,
            dent: desc.dent,
            fracture: desc.fracture,
            color: desc.color,
            mass,
            inertia,
            inverse_mass,
            inverse_inertia,
            model_offset: -center,
            mesh: Arc::new(mesh),
            collider_kind: desc.collider,
            shape,
            collider_map: None,
            activity: Activity::default(),
            role: Role::Free,
        })
    }

    /// The surface in body coordinates (centre of mass at the origin).
    pub fn mesh(&self) -> &TriMesh {
        &self.mesh
    }

    /// Body → world transform.
    pub fn transform(&self) -> Affine3A {
        Affine3A::from_rotation_translation(self.orientation, self.position)
    }

    /// Model → world transform: where the body's model frame (the coordinates its mesh was
    /// given in) is now.
    pub fn model_transform(&self) -> Affine3A {
        self.transform() * Affine3A::from_translation(self.model_offset)
    }

    /// The surface as it dents others: its mesh at its body transform.
    pub fn surface(&self) -> dentbend::dent::Surface<'_> {
        dentbend::dent::Surface { mesh: self.mesh(), to_world: self.transform() }
    }

    /// The surface in world coordinates.
    pub fn world_mesh(&self) -> TriMesh {
        let mut mesh = (*self.mesh).clone();
        // A rigid motion of a valid mesh stays finite; the transform cannot fail.
        let _ = mesh.transform(self.transform());
        mesh
    }

    /// World velocity of the body point now at world position `point`, m/s.
    pub fn velocity_at(&self, point: Vec3) -> Vec3 {
        self.linear_velocity + self.angular_velocity.cross(point - self.position)
    }

    /// Inverse inertia tensor in world axes, 1/(kg·m²) (zero for static and kinematic bodies).
    pub fn inverse_inertia_world(&self) -> Mat3 {
        let rotation = Mat3::from_quat(self.orientation);
        rotation * self.inverse_inertia * rotation.transpose()
    }

    /// Kinetic energy, J (0 for static and kinematic bodies).
    pub fn kinetic_energy(&self) -> f32 {
        self.kinetic_energy_at(self.linear_velocity, self.angular_velocity)
    }

    /// Kinetic energy the body would have at velocities `linear` (m/s) and `angular` (rad/s,
    /// world axes) in its current orientation, J (0 for static and kinematic bodies).
    pub(crate) fn kinetic_energy_at(&self, linear: Vec3, angular: Vec3) -> f32 {
        if self.kind != BodyKind::Dynamic {
            return 0.0;
        }
        let rotation = Mat3::from_quat(self.orientation);
        let inertia_world = rotation * self.inertia * rotation.transpose();
        0.5 * self.mass * linear.length_squared() + 0.5 * angular.dot(inertia_world * angular)
    }

    /// Linear momentum, kg·m/s (0 for static and kinematic bodies).
    pub fn momentum(&self) -> Vec3 {
        if self.kind == BodyKind::Dynamic { self.mass * self.linear_velocity } else { Vec3::ZERO }
    }

    /// Whether the body is asleep (still for a while; woken by contacts with moving bodies).
    pub fn is_asleep(&self) -> bool {
        self.activity.asleep
    }

    /// Whether the body is condensed into a rigid cluster ([`World::condense`](super::World::condense)):
    /// its pose and velocities then follow the cluster's, and setting them has no effect.
    pub fn is_condensed(&self) -> bool {
        matches!(self.role, Role::Member(_))
    }

    /// Whether the body is a cluster's stand-in (or a spare one): simulated for its members, never
    /// drawn or written.
    pub fn is_cluster_proxy(&self) -> bool {
        matches!(self.role, Role::Proxy(_) | Role::Spare)
    }

    /// Whether the step moves this body itself (a free body or an active cluster's proxy).
    pub(crate) fn is_simulated(&self) -> bool {
        matches!(self.role, Role::Free | Role::Proxy(_))
    }

    /// The collider, for queries.
    pub fn shape(&self) -> &SharedShape {
        &self.shape
    }

    /// Replaces the surface (body coordinates) after a dent: a triangle-mesh collider is refitted
    /// where the vertices moved, other mesh colliders are rebuilt.
    pub(crate) fn set_mesh(&mut self, mesh: TriMesh) -> Result<(), SimError> {
        let kind = self.collider_kind.resolve(self.kind);
        let refitted = kind == ColliderKind::TriMesh
            && ColliderKind::refit(&mut self.shape, &mut self.collider_map, &self.mesh, &mesh);
        if self.collider_kind.follows_mesh(self.kind) && !refitted {
            self.collider_map = None;
            self.shape = self
                .collider_kind
                .build_for(self.kind, &mesh)
                .map_err(|reason| SimError::BadShape { body: self.name.clone(), reason })?;
        }
        self.mesh = Arc::new(mesh);
        Ok(())
    }
}
