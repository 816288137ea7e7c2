//! The pieces of broken bodies as Avian bodies.

use avian3d::math::SymmetricTensor;
use avian3d::prelude::{
    AngularInertia, AngularVelocity, CenterOfMass, Collider, LinearVelocity, Mass, NoAutoAngularInertia,
    NoAutoCenterOfMass, NoAutoMass, RigidBody,
};
use bevy::prelude::*;
use dentbend::damage::piece_hull_points;

use crate::mesh_data::tri_mesh;
use crate::{BodyBroken, DentPiece, DentProjectile};

/// Each new [`DentPiece`] becomes a dynamic Avian body: the convex hull of its mesh (shrunk by
/// [`dentbend::damage::PIECE_HULL_SCALE`]) with the piece's own mass properties (not the
/// collider's), moving as it broke loose, and a [`DentProjectile`] (it dents what it hits).
pub(crate) fn give_bodies(
    mut commands: Commands,
    meshes: Res<Assets<Mesh>>,
    new: Query<(Entity, &DentPiece, &Mesh3d), Added<DentPiece>>,
) {
    for (entity, piece, mesh3d) in &new {
        let Some(tri) = meshes.get(&mesh3d.0).and_then(|m| tri_mesh(m).ok()) else { continue };
        let centre = piece.mass.center;
        let Some(collider) = Collider::convex_hull(&piece_hull_points(&tri, centre)) else {
            debug!("bevy_dentbend: piece {entity} has no convex hull (a sliver); it stays without a body");
            continue;
        };
        let inertia = AngularInertia::from_tensor(SymmetricTensor::from_mat3_unchecked(piece.mass.inertia));
        commands.entity(entity).insert((
            RigidBody::Dynamic,
            collider,
            (
                Mass(piece.mass.mass),
                inertia,
                CenterOfMass(centre),
                NoAutoMass,
                NoAutoAngularInertia,
                NoAutoCenterOfMass,
            ),
            LinearVelocity(piece.linear_velocity),
            AngularVelocity(piece.angular_velocity),
            DentProjectile,
        ));
    }
}

/// The projectile that broke a body carries on with what the break left of its velocity
/// ([`BodyBroken::projectile_velocity`]): Avian's step stopped it against the unbroken body.
pub(crate) fn give_way(
    mut broken: MessageReader<BodyBroken>,
    mut bodies: Query<(&RigidBody, &mut LinearVelocity, &mut AngularVelocity)>,
) {
    for b in broken.read() {
        if let Some((linear, angular)) = b.projectile_velocity
            && let Ok((body, mut v, mut w)) = bodies.get_mut(b.projectile)
            && body.is_dynamic()
        {
            (v.0, w.0) = (linear, angular);
        }
    }
}
