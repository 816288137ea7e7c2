//! The pieces of broken bodies as the engine's bodies.

use bevy::prelude::*;
use dentbend::damage::piece_hull_points;

use super::Engine;
use crate::mesh_data::tri_mesh;
use crate::{DentPiece, DentProjectile};

/// Each new [`DentPiece`] becomes a dynamic body of the engine ([`Engine::piece_body`]) over
/// the convex hull of its mesh (shrunk by [`dentbend::damage::PIECE_HULL_SCALE`]), and a
/// [`DentProjectile`] (it dents what it hits).
pub(crate) fn give_bodies<E: Engine>(
    mut commands: Commands,
    meshes: Res<Assets<Mesh>>,
    new: Query<(Entity, &DentPiece, &Mesh3d), Added<DentPiece>>,
) {
    for (entity, piece, mesh3d) in &new {
        let Some(tri) = meshes.get(&mesh3d.0).and_then(|m| tri_mesh(m).ok()) else { continue };
        match E::piece_body(&piece_hull_points(&tri, piece.mass.center), piece) {
            Some(body) => {
                commands.entity(entity).insert((body, DentProjectile));
            }
            None => debug!("bevy_dentbend: piece {entity} has no convex hull (a sliver); it stays without a body"),
        }
    }
}
