//! Dentable entities' `Collider`s follow their dented meshes.

use bevy::prelude::*;
use bevy_rapier3d::prelude::Collider;
use bevy_rapier3d::rapier::prelude::SharedShape;
use dentbend::TriMesh;
use dentbend::glam::Affine3A;
use dentbend_rapier::dentbend::collider::refit_shared_trimesh;

use crate::{DentWorld, MeshDented};

/// Refits (tri-mesh with the same vertices), rebuilds (refined tri-mesh, or another vertex
/// numbering) or re-hulls (convex) each dented entity's collider (on the entity itself, or on
/// the entity its collider sits on, in that entity's coordinates).
pub(crate) fn refit_colliders(
    mut dented: MessageReader<MeshDented>,
    world: Res<DentWorld>,
    mut colliders: Query<&mut Collider>,
) {
    for d in dented.read() {
        let (entity, to_collider) = world.collider_of(d.entity);
        let (Some(mesh), Ok(mut collider)) = (world.mesh(d.entity), colliders.get_mut(entity)) else { continue };
        // bevy_rapier3d scales a scaled entity's collider itself: it takes the mesh without the
        // scale, rebuilt whole (its scaled copy is not the one to refit).
        let scale = world.scale(d.entity);
        let placed;
        let mesh = if to_collider == Affine3A::IDENTITY && scale.is_none() {
            mesh
        } else {
            let mut moved = mesh.clone();
            if moved.transform(to_collider * Affine3A::from_scale(scale.unwrap_or(Vec3::ONE).recip())).is_err() {
                continue;
            }
            placed = moved;
            &placed
        };
        let rebuilt;
        let d = if scale.is_some() {
            rebuilt = MeshDented { topology_changed: true, ..d.clone() };
            &rebuilt
        } else {
            d
        };
        match refitted(&collider.raw, mesh, d) {
            Ok(shape) => *collider = Collider::from(shape),
            Err(reason) => warn!("bevy_dentbend: {}'s collider keeps its shape: {reason}", d.entity),
        }
    }
}

/// The shape `raw` becomes after dent `d` left `mesh`.
fn refitted(raw: &SharedShape, mesh: &TriMesh, d: &MeshDented) -> Result<SharedShape, String> {
    if let Some(trimesh) = raw.as_trimesh() {
        if !d.topology_changed && trimesh.vertices().len() == mesh.vertex_count() {
            let mut shape = raw.clone();
            let positions: Vec<Vec3> =
                d.moved.iter().filter_map(|&v| mesh.positions().get(v as usize).copied()).collect();
            refit_shared_trimesh(&mut shape, &d.moved, &positions).map_err(|e| e.to_string())?;
            return Ok(shape);
        }
        return SharedShape::trimesh_with_flags(mesh.positions().to_vec(), mesh.faces().to_vec(), trimesh.flags())
            .map_err(|e| format!("the dented tri-mesh was refused: {e}"));
    }
    if raw.as_convex_polyhedron().is_some() {
        return SharedShape::convex_hull(mesh.positions()).ok_or_else(|| "no convex hull of the dented mesh".into());
    }
    Err("only tri-mesh and convex colliders follow their dents".into())
}
