//! Fracture in a Rapier world, from the damage API's [`BodyFracture`]s: the broken collider
//! takes its rest (a tri-mesh rebuilt, a hull rebuilt with the rest's own mass properties), each
//! piece becomes a dynamic body at the collider's pose with a convex-hull collider carrying the
//! piece's mass properties and moving as the body's material moved, and the projectile that broke
//! it carries on with what the break left of its energy. Prepared (every shape built and
//! checked) before anything changes, then committed.

use dentbend::damage::{BodyFracture, PieceId, piece_hull_points};
use dentbend::mesh::{MassProperties, TriMesh};
use rapier3d::prelude::{
    ColliderBuilder, ColliderHandle, ColliderSet, MassProperties as RapierMass, RigidBodyBuilder, RigidBodyHandle,
    RigidBodySet, SharedShape,
};

use crate::AdapterError;
use crate::refit::{ShapeKind, trimesh_shape};

/// One piece that became a Rapier body.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PieceBody {
    /// The piece's id from the damage API (deterministic: a client replaying the same hits
    /// names its pieces alike).
    pub id: PieceId,
    /// Its new dynamic body.
    pub body: RigidBodyHandle,
    /// Its convex-hull collider (a projectile the adapter dents others with).
    pub collider: ColliderHandle,
}

/// A dentable collider that broke during a step.
#[derive(Debug, Clone)]
pub struct BrokenCollider {
    /// The collider that broke; it keeps its handle with its rest as its shape.
    pub collider: ColliderHandle,
    /// The fracture as the damage API made it: what broke it, why, its record, the rest and
    /// every piece (what [`ReplicationServer::message`](dentbend::record::replication::ReplicationServer::message)
    /// sends).
    pub fracture: BodyFracture<ColliderHandle>,
    /// Whether the pattern took the whole collider: it is disabled and forgotten, for the
    /// caller to remove ([`Adapter`](crate::Adapter) removes it, and its body when it has no
    /// other collider).
    pub whole: bool,
    /// The pieces that became bodies, in the fracture's order.
    pub pieces: Vec<PieceBody>,
    /// Pieces left out: slivers with no convex hull (their volume is lost).
    pub left_out: usize,
}

/// A fracture's Rapier edits, built and checked.
pub(crate) struct PreparedFracture {
    broken: PreparedBreak,
    rest: Option<(SharedShape, Option<RapierMass>)>,
    pieces: Vec<(PieceId, ColliderBuilder, TriMesh, glam::Vec3, glam::Vec3)>,
    projectile_velocity: Option<(glam::Vec3, glam::Vec3)>,
}

/// What a prepared fracture will report.
struct PreparedBreak {
    collider: ColliderHandle,
    whole: bool,
    left_out: usize,
}

/// Builds the edits of `fracture` of collider `handle` (of `kind`); nothing changes.
///
/// # Errors
/// [`AdapterError::UnknownCollider`], or [`AdapterError::Refit`] when the rest's shape cannot
/// be built.
pub(crate) fn prepare(
    colliders: &ColliderSet,
    kind: ShapeKind,
    fracture: &BodyFracture<ColliderHandle>,
) -> Result<PreparedFracture, AdapterError> {
    let handle = fracture.body;
    let collider = colliders.get(handle).ok_or(AdapterError::UnknownCollider(handle))?;
    let rest = match &fracture.rest {
        None => None,
        Some(rest) => {
            let shape = match kind {
                ShapeKind::TriMesh => trimesh_shape(handle, collider, rest)?,
                ShapeKind::Convex => crate::convex_shape(rest).ok_or_else(|| AdapterError::Refit {
                    collider: handle,
                    reason: "no convex hull of the fracture's rest".into(),
                })?,
            };
            // A hull spans the rest's bite: its mass is the rest's, not the hull's.
            let mass = match kind {
                ShapeKind::Convex => fracture.rest_mass.map(|m| rapier_mass(&m)),
                ShapeKind::TriMesh => None,
            };
            Some((shape, mass))
        }
    };
    let mut pieces = Vec::with_capacity(fracture.pieces.len());
    let mut left_out = 0;
    for piece in &fracture.pieces {
        match ColliderBuilder::convex_hull(&piece_hull_points(&piece.mesh, piece.mass.center)) {
            Some(builder) => pieces.push((
                piece.id,
                builder.mass_properties(rapier_mass(&piece.mass)),
                piece.mesh.clone(),
                piece.linear_velocity,
                piece.angular_velocity,
            )),
            None => left_out += 1,
        }
    }
    let broken = PreparedBreak { collider: handle, whole: fracture.rest.is_none(), left_out };
    Ok(PreparedFracture { broken, rest, pieces, projectile_velocity: fracture.projectile_velocity })
}

impl PreparedFracture {
    /// Applies the edits of `fracture` (the one it was prepared from): the rest's shape (or the
    /// collider disabled), a body and collider per piece at the collider's pose, the
    /// projectile's velocity. Returns what broke and each piece's collider with its mesh (for
    /// the caller to dent others with).
    pub(crate) fn commit(
        self,
        bodies: &mut RigidBodySet,
        colliders: &mut ColliderSet,
        fracture: BodyFracture<ColliderHandle>,
    ) -> (BrokenCollider, Vec<(ColliderHandle, TriMesh)>) {
        let Self { broken, rest, pieces, projectile_velocity } = self;
        let projectile = fracture.projectile;
        let PreparedBreak { collider, whole, left_out } = broken;
        let mut broken = BrokenCollider { collider, fracture, whole, pieces: Vec::new(), left_out };
        let Some(collider) = colliders.get_mut(broken.collider) else { return (broken, Vec::new()) };
        let pose = *collider.position();
        match rest {
            Some((shape, mass)) => {
                collider.set_shape(shape);
                if let Some(mass) = mass {
                    collider.set_mass_properties(mass);
                }
            }
            None => collider.set_enabled(false),
        }
        let mut surfaces = Vec::with_capacity(pieces.len());
        for (id, builder, mesh, linear, angular) in pieces {
            let body = bodies.insert(RigidBodyBuilder::dynamic().pose(pose).linvel(linear).angvel(angular));
            let collider = colliders.insert_with_parent(builder, body, bodies);
            broken.pieces.push(PieceBody { id, body, collider });
            surfaces.push((collider, mesh));
        }
        if let Some((linear, angular)) = projectile_velocity
            && let Some(body) = colliders.get(projectile).and_then(|c| c.parent())
            && let Some(rb) = bodies.get_mut(body)
            && rb.is_dynamic()
        {
            rb.set_linvel(linear, true);
            rb.set_angvel(angular, true);
        }
        (broken, surfaces)
    }
}

/// dentbend's mass properties (mesh coordinates) as Rapier's (collider frame: the same).
fn rapier_mass(m: &MassProperties) -> RapierMass {
    RapierMass::with_inertia_matrix(m.center, m.mass, m.inertia)
}
