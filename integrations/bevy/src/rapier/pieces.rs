//! The pieces of broken bodies as bevy_rapier3d bodies.

use bevy::prelude::*;
use bevy_rapier3d::prelude::{Collider, ColliderMassProperties, MassProperties, RigidBody, Velocity};
use bevy_rapier3d::rapier::prelude::MassProperties as RapierMass;

use dentbend::damage::piece_hull_points;

use crate::mesh_data::tri_mesh;
use crate::{BodyBroken, DentPiece, DentProjectile};

/// Each new [`DentPiece`] becomes a dynamic body: the convex hull of its mesh (shrunk by
/// [`dentbend::damage::PIECE_HULL_SCALE`]) with the piece's own mass properties, moving as it
/// broke loose, and a [`DentProjectile`] (it dents what it hits).
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
        let mass = RapierMass::with_inertia_matrix(centre, piece.mass.mass, piece.mass.inertia);
        commands.entity(entity).insert((
            RigidBody::Dynamic,
            collider,
            ColliderMassProperties::MassProperties(MassProperties::from_rapier(mass)),
            Velocity { linear: piece.linear_velocity, angular: piece.angular_velocity },
            DentProjectile,
        ));
    }
}

/// The projectile that broke a body carries on with what the break left of its velocity
/// ([`BodyBroken::projectile_velocity`]): Rapier's step stopped it against the unbroken body.
pub(crate) fn give_way(mut broken: MessageReader<BodyBroken>, mut bodies: Query<(&RigidBody, &mut Velocity)>) {
    for b in broken.read() {
        if let Some((linear, angular)) = b.projectile_velocity
            && let Ok((body, mut velocity)) = bodies.get_mut(b.projectile)
            && *body == RigidBody::Dynamic
        {
            *velocity = Velocity { linear, angular };
        }
    }
}
