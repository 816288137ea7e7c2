//! Breakable dentable bodies: a plan's fractures become the broken entity's new mesh (its rest)
//! and one entity per piece, with a [`DentPiece`] a physics engine makes a body of.

use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use dentbend::damage::BodyFracture;

use crate::fracture_attributes::{Broken, carry_attributes};
use crate::mesh_data::bevy_mesh;
use crate::scale::for_asset;
use crate::{BodyBroken, DentPiece, DentStats, DentWorld, MeshDented};

/// What breaking bodies needs: commands to spawn pieces, the broken bodies' materials, and its
/// message.
#[derive(SystemParam)]
pub(crate) struct Breaking<'w, 's> {
    commands: Commands<'w, 's>,
    materials: Query<'w, 's, &'static MeshMaterial3d<StandardMaterial>>,
    broken: MessageWriter<'w, BodyBroken>,
}

/// Applies `fractures` (after the plan's dents): each broken entity's mesh asset becomes its
/// rest (a body the pattern took whole is despawned), and each piece a new entity at the
/// body's pose with its mesh, the body's material and a [`DentPiece`]. The rest and the pieces
/// keep the asset's UVs and other attributes ([`carry_attributes`]).
pub(crate) fn break_bodies(
    world: &mut DentWorld,
    fractures: Vec<BodyFracture<Entity>>,
    out: &mut Breaking,
    (meshes, dented, stats): (&mut Assets<Mesh>, &mut MessageWriter<MeshDented>, &mut DentStats),
) {
    for fracture in fractures {
        let entity = fracture.body;
        let Some(pose) = world.targets.pose(entity) else { continue };
        let transform = Transform::from_matrix(Mat4::from(pose));
        let material = out.materials.get(entity).ok().cloned();
        let scale = world.bodies.get(&entity).and_then(|b| b.scale);
        // The asset as it broke, for its attributes: only while it is the broken mesh vertex
        // for vertex (the GPU path's main-world copy can lag behind).
        let asset = world
            .bodies
            .get(&entity)
            .and_then(|b| meshes.get(&b.mesh))
            .filter(|a| a.count_vertices() == fracture.broken_mesh.vertex_count())
            .cloned();
        let body_scale = scale.unwrap_or(Vec3::ONE);
        let broken = asset.as_ref().map(|a| Broken::new(a, fracture.broken_mesh.faces(), body_scale));
        let with_attributes = |mesh: &dentbend::TriMesh, origins: &[_], scale: Vec3| {
            let mut made = bevy_mesh(mesh);
            if let Some(broken) = broken {
                carry_attributes(&mut made, &broken.scaled(scale), origins);
            }
            made
        };
        world.records.fractured(&fracture, world.step);
        world.targets.apply_fracture(&fracture);
        let whole = fracture.rest.is_none();
        match &fracture.rest {
            Some(rest) => {
                if let Some(body) = world.bodies.get(&entity)
                    && let Some(mut asset) = meshes.get_mut(&body.mesh)
                {
                    // The asset holds the mesh without its entity's scale, which Bevy applies.
                    match for_asset(rest, body.scale) {
                        Ok(mesh) => *asset = with_attributes(&mesh, &fracture.rest_origins, Vec3::ONE),
                        Err(e) => error!("bevy_dentbend: {entity}'s rest could not be unscaled ({e})"),
                    }
                }
                let moved = (0..rest.vertex_count() as u32).collect();
                dented.write(MeshDented { entity, moved, topology_changed: true });
            }
            None => {
                world.remove(entity);
                out.commands.entity(entity).try_despawn();
            }
        }
        let mut pieces = Vec::with_capacity(fracture.pieces.len());
        for piece in &fracture.pieces {
            let mesh = meshes.add(with_attributes(&piece.mesh, &piece.origins, body_scale));
            let component = DentPiece {
                from: entity,
                id: piece.id,
                mass: piece.mass,
                linear_velocity: piece.linear_velocity,
                angular_velocity: piece.angular_velocity,
            };
            let mut spawned = out.commands.spawn((Mesh3d(mesh), transform, component));
            if let Some(material) = &material {
                spawned.insert(material.clone());
            }
            pieces.push(spawned.id());
        }
        stats.fractures += 1;
        stats.pieces += pieces.len() as u64;
        info!("bevy_dentbend: {entity} broke ({:?}) into {} pieces", fracture.cause, pieces.len());
        out.broken.write(BodyBroken {
            entity,
            projectile: fracture.projectile,
            cause: fracture.cause,
            pieces,
            whole,
            projectile_velocity: fracture.projectile_velocity,
        });
    }
}
