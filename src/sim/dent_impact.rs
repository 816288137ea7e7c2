//! One collision's dent, whatever the dented surface is: whether a hit dents its target and how
//! deep ([`decide_dent`]), the part of the projectile that shapes it ([`projectile_near_impact`])
//! and the dent job in the target's mesh coordinates ([`dent_job`]). The [`Denter`](super::Denter)
//! dents plain bodies with them, and a bending body's sub-body hit dents its skinned mesh with
//! them (`bend::BendDenter`).

use glam::{Affine3A, Vec3};

use super::energy::energy_dent_distance;
use super::{BodyKind, CollisionEvent, DentRecord, DentSettings, SimError, World};
use crate::dent::{DentJob, DentParams, Impact};
use crate::mesh::TriMesh;

/// A surface as it dents others: a mesh and its mesh → world transform (rigid).
#[derive(Debug, Clone, Copy)]
pub struct DentSurface<'a> {
    /// The surface, in its own coordinates, m.
    pub mesh: &'a TriMesh,
    /// Mesh coordinates → world.
    pub to_world: Affine3A,
    /// Name of what dents with it (in [`DentRecord`]s).
    pub name: &'a str,
}

impl<'a> DentSurface<'a> {
    /// World body `index`'s own surface (its mesh at its body transform).
    pub fn of_body(world: &'a World, index: usize) -> Self {
        let body = &world.bodies()[index];
        Self { mesh: body.mesh(), to_world: body.transform(), name: &body.name }
    }

    /// `overrides`' surface for body `index` when it has one (a bending body's sub-body dents
    /// others with the whole skinned mesh), else the body's own.
    pub fn lookup(world: &'a World, index: usize, overrides: &[(usize, DentSurface<'a>)]) -> Self {
        overrides.iter().find(|(k, _)| *k == index).map_or_else(|| Self::of_body(world, index), |(_, s)| *s)
    }

    /// The surface in world coordinates.
    pub fn world_mesh(&self) -> TriMesh {
        let mut mesh = self.mesh.clone();
        // A rigid motion of a valid mesh stays finite; the transform cannot fail.
        let _ = mesh.transform(self.to_world);
        mesh
    }
}

/// What denting a step needs besides the world and the events.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepContext<'a> {
    /// Bodies that dent others with another surface than their own (a bending body's
    /// sub-bodies: the whole undented skinned mesh), by world index.
    pub surfaces: &'a [(usize, DentSurface<'a>)],
    /// Each body's rigid motion during the step (world at the contact → world now), by world
    /// index; bodies past the end did not move. See [`DentTarget::motion`].
    pub motions: &'a [Affine3A],
}

impl<'a> StepContext<'a> {
    /// The surface body `index` dents others with.
    pub fn surface(&self, world: &'a World, index: usize) -> DentSurface<'a> {
        DentSurface::lookup(world, index, self.surfaces)
    }

    /// Body `index`'s motion during the step.
    pub fn motion(&self, index: usize) -> Affine3A {
        self.motions.get(index).copied().unwrap_or(Affine3A::IDENTITY)
    }
}

/// A dentable surface that a collision hit.
#[derive(Debug, Clone, Copy)]
pub struct DentTarget<'a> {
    /// World body hit (the event's body; for the energy model's effective mass).
    pub body: usize,
    /// Name of the dented thing (in errors and [`DentRecord`]s).
    pub name: &'a str,
    /// How it dents.
    pub settings: &'a DentSettings,
    /// Coordinates of the mesh that is dented → world (rigid).
    pub to_world: Affine3A,
    /// Radius of a ball about the mesh's origin holding the mesh, m (bounds how far from the
    /// impact the projectile can matter).
    pub radius: f32,
    /// The target's rigid motion during the step that made the event (world at the contact →
    /// world now): the event's contact is carried along with it, so that a target that moved
    /// on after the contact (a plank pushed down by the ball) is dented where it was hit. The
    /// identity for a target that did not move.
    pub motion: Affine3A,
}

impl<'a> DentTarget<'a> {
    /// World body `index` as a target: its own mesh in body coordinates; `None` unless dentable.
    pub fn of_body(world: &'a World, index: usize) -> Option<Self> {
        let body = &world.bodies()[index];
        let settings = body.dent.as_ref()?;
        let radius = body.shape().compute_local_bounding_sphere().radius;
        Some(Self {
            body: index,
            name: &body.name,
            settings,
            to_world: body.transform(),
            radius,
            motion: Affine3A::IDENTITY,
        })
    }
}

/// A dent decided from a collision, world coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DecidedDent {
    /// World body hit.
    pub target: usize,
    /// World body that hit it.
    pub projectile: usize,
    /// The contact, normal into the target, projectile's velocity relative to the target.
    pub impact: Impact,
    /// Dent distance earned, m.
    pub dent_distance: f32,
}

impl DecidedDent {
    /// The record of this dent of `target` by `projectile` (names) made with `dent_distance` (m)
    /// at `step`.
    pub fn record(&self, target: &str, projectile: &str, dent_distance: f32, step: u64) -> DentRecord {
        DentRecord {
            step,
            target: target.to_owned(),
            projectile: projectile.to_owned(),
            point: self.impact.point,
            normal: self.impact.normal,
            relative_velocity: self.impact.relative_velocity,
            dent_distance,
        }
    }

    /// Moves a dynamic projectile into the dent (by the dent distance along the normal) when
    /// `settings` ask for it.
    pub fn move_projectile(&self, world: &mut World, settings: &DentSettings) {
        let projectile = &mut world.bodies_mut()[self.projectile];
        if settings.move_projectile && projectile.kind == BodyKind::Dynamic {
            projectile.position += self.impact.unit_normal() * self.dent_distance;
        }
    }
}

/// Whether `target` (body a or b of `event`) dents from `event`, whose other body dents it with
/// `projectile`: its normal speed is above the threshold (or, with a hardness, the energy lost
/// makes a dent), and how deep. The impact is the event's contact carried by `target.motion`.
///
/// # Errors
/// [`SimError::Invalid`] when `target.body` is neither body of the event; [`SimError::Dent`]
/// (naming the target) for a bad impact or projectile.
pub fn decide_dent(
    world: &World,
    event: &CollisionEvent,
    target: &DentTarget<'_>,
    projectile: &DentSurface<'_>,
) -> Result<Option<DecidedDent>, SimError> {
    let (sign, other) = match target.body {
        b if b == event.a => (1.0f32, event.b),
        b if b == event.b => (-1.0, event.a),
        b => return Err(SimError::Invalid { what: "dent target".into(), value: b.to_string(), reason: "is not hit" }),
    };
    let settings = target.settings;
    // Into the target, and the projectile's velocity relative to it, carried with the target.
    let motion = target.motion;
    let impact = Impact {
        point: motion.transform_point3(event.point),
        normal: motion.transform_vector3(-sign * event.normal),
        relative_velocity: motion.transform_vector3(sign * event.relative_velocity),
    };
    let dent_error = |error| SimError::Dent { body: target.name.to_owned(), error };
    let Some(mut distance) = settings.material.dent_distance(&impact).map_err(dent_error)? else {
        return Ok(None);
    };
    if let Some(hardness) = settings.hardness {
        let lost = normal_energy_lost(world, event, target.body, other);
        let params = DentParams { dent_distance: settings.material.cap, ..settings.params.clone() };
        distance =
            energy_dent_distance(&projectile.world_mesh(), &impact, &params, hardness, lost).map_err(dent_error)?;
        if distance <= 0.0 {
            return Ok(None);
        }
    }
    Ok(Some(DecidedDent { target: target.body, projectile: other, impact, dent_distance: distance }))
}

/// Kinetic energy the collision removes along the normal, J: ½·m_eff·v_n²·(1 − e²), with m_eff
/// the pair's effective mass along the normal at the contact point (rotation included).
fn normal_energy_lost(world: &World, event: &CollisionEvent, target: usize, projectile: usize) -> f32 {
    let inverse = |k: usize| {
        let body = &world.bodies()[k];
        if body.kind != BodyKind::Dynamic {
            return 0.0;
        }
        let rn = (event.point - body.position).cross(event.normal);
        body.inverse_mass + (body.inverse_inertia_world() * rn).dot(rn)
    };
    let k = inverse(target) + inverse(projectile);
    if k <= 0.0 {
        return 0.0;
    }
    let (a, b) = (&world.bodies()[target].surface, &world.bodies()[projectile].surface);
    let e = a.restitution.max(b.restitution);
    0.5 / k * event.normal_speed.powi(2) * (1.0 - e * e)
}

/// The part of `projectile` that can shape `dent`, in the target's mesh coordinates: triangles
/// with a corner within reach of the impact point (twice the target's radius plus the cap and
/// four σ). Far parts of a large projectile (a bunny landing on a small ball) cannot touch the
/// target, and leaving them out keeps the dent's depth origin at the part that hit instead of
/// the projectile's farthest point. `None` when nothing is that close.
pub fn projectile_near_impact(
    target: &DentTarget<'_>,
    dent: &DecidedDent,
    projectile: &DentSurface<'_>,
) -> Option<TriMesh> {
    let centre = projectile.to_world.inverse().transform_point3(dent.impact.point);
    let mut mesh = crop_to_ball(projectile.mesh, centre, reach(target, dent))?;
    // A rigid motion of a valid mesh stays finite.
    let _ = mesh.transform(target.to_world.inverse() * projectile.to_world);
    Some(mesh)
}

/// How far from the impact point the projectile can matter, m: the target's size (its dent
/// cannot be wider), plus the deepest dent and the Gaussian tails.
fn reach(target: &DentTarget<'_>, dent: &DecidedDent) -> f32 {
    let cap = target.settings.material.cap.max(dent.dent_distance);
    let sigma = target.settings.params.sigma.unwrap_or(0.5 * cap);
    2.0 * target.radius + cap + 4.0 * sigma
}

/// The triangles of `mesh` with a corner within `radius` of `centre`, vertices renumbered;
/// the whole mesh (cloned) when all of it is that close.
fn crop_to_ball(mesh: &TriMesh, centre: Vec3, radius: f32) -> Option<TriMesh> {
    let near: Vec<bool> = mesh.positions().iter().map(|p| p.distance_squared(centre) <= radius * radius).collect();
    if near.iter().all(|&n| n) {
        return Some(mesh.clone());
    }
    let mut index = vec![u32::MAX; mesh.vertex_count()];
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for face in mesh.faces() {
        if !face.iter().any(|&v| near[v as usize]) {
            continue;
        }
        faces.push(face.map(|v| {
            if index[v as usize] == u32::MAX {
                index[v as usize] = positions.len() as u32;
                positions.push(mesh.positions()[v as usize]);
            }
            index[v as usize]
        }));
    }
    TriMesh::new(positions, faces).ok()
}

/// The job of `dent` (its distance: `dent_distance`, m) in the target's mesh coordinates, with
/// `projectile` already there (from [`projectile_near_impact`]), against batch target `slot`.
pub fn dent_job<'a>(
    target: &DentTarget<'_>,
    dent: &DecidedDent,
    dent_distance: f32,
    projectile: &'a TriMesh,
    slot: usize,
) -> DentJob<'a> {
    let to_mesh = target.to_world.inverse();
    let impact = Impact {
        point: to_mesh.transform_point3(dent.impact.point),
        normal: to_mesh.transform_vector3(dent.impact.normal),
        relative_velocity: to_mesh.transform_vector3(dent.impact.relative_velocity),
    };
    DentJob { target: slot, projectile, impact, params: DentParams { dent_distance, ..target.settings.params.clone() } }
}
