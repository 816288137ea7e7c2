//! Dentable entities' `Collider`s follow their dented meshes.

use std::borrow::Cow;

use bevy::prelude::*;
use dentbend::TriMesh;
use dentbend::collider::refit_shared_trimesh;
use dentbend::glam::Affine3A;
use parry3d::shape::SharedShape;

use super::Engine;
use crate::{DentWorld, MeshDented};

/// Refits (tri-mesh with the same vertices), rebuilds (refined tri-mesh, or another vertex
/// numbering) or re-hulls (convex) each dented entity's collider (on the entity itself, or on
/// the entity its collider sits on, in that entity's coordinates).
pub(crate) fn refit_colliders<E: Engine>(
    mut dented: MessageReader<MeshDented>,
    world: Res<DentWorld>,
    mut colliders: Query<&mut E::Collider>,
) {
    for d in dented.read() {
        let (entity, to_collider) = world.collider_of(d.entity);
        let (Some(mesh), Ok(mut collider)) = (world.mesh(d.entity), colliders.get_mut(entity)) else { continue };
        // The engine scales a scaled entity's collider itself: it takes the mesh without the
        // scale, rebuilt whole (its scaled copy is not the one to refit).
        let scale = world.scale(d.entity);
        let to_shape = to_collider * Affine3A::from_scale(scale.unwrap_or(Vec3::ONE).recip());
        let mesh = if to_shape == Affine3A::IDENTITY {
            Cow::Borrowed(mesh)
        } else {
            let mut placed = mesh.clone();
            if placed.transform(to_shape).is_err() {
                continue;
            }
            Cow::Owned(placed)
        };
        match refitted(E::shape(&collider), &mesh, &d.moved, d.topology_changed || scale.is_some()) {
            Ok(shape) => E::set_shape(&mut collider, shape),
            Err(reason) => warn!("bevy_dentbend: {}'s collider keeps its shape: {reason}", d.entity),
        }
    }
}

/// The shape `raw` becomes now that the vertices `moved` of `mesh` moved; a tri-mesh is rebuilt
/// when `rebuild` (the faces changed, or `raw` is a scaled copy).
fn refitted(raw: &SharedShape, mesh: &TriMesh, moved: &[u32], rebuild: bool) -> Result<SharedShape, String> {
    if let Some(trimesh) = raw.as_trimesh() {
        if !rebuild && trimesh.vertices().len() == mesh.vertex_count() {
            let mut shape = raw.clone();
            let positions: Vec<Vec3> =
                moved.iter().filter_map(|&v| mesh.positions().get(v as usize).copied()).collect();
            refit_shared_trimesh(&mut shape, moved, &positions).map_err(|e| e.to_string())?;
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
