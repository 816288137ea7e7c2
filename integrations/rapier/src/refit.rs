//! Collider refits after a dent: the one place the adapter changes a collider's shape, so a
//! faster refit (a partial BVH refit over the moved vertices) can replace it later.
//!
//! - Tri-mesh colliders are refitted in place ([`parry`'s `TriMesh::set_vertices`], which
//!   refits the BVH keeping its structure); build them with [`trimesh_collider`] so Rapier
//!   treats them as deformable.
//! - Convex colliders (dynamic bodies) get the convex hull of the dented vertices.

use dentbend::mesh::TriMesh;
use glam::Vec3;
use rapier3d::parry::shape::TriMeshFlags;
use rapier3d::prelude::{Collider, ColliderBuilder, ColliderHandle, SharedShape};

use crate::AdapterError;

/// How a dentable collider's shape follows its mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShapeKind {
    /// A tri-mesh with the mesh's vertices, refitted in place.
    TriMesh,
    /// A convex polyhedron, rebuilt as the hull of the mesh's vertices.
    Convex,
}

/// A refit computed and checked, not yet applied.
#[derive(Debug, Clone)]
pub enum Refit {
    /// New tri-mesh vertices (collider frame, m).
    Vertices(Vec<Vec3>),
    /// A new convex hull.
    Shape(SharedShape),
}

/// The kind of refit `collider`'s shape takes, if any.
pub fn shape_kind(collider: &Collider) -> Option<ShapeKind> {
    let shape = collider.shape();
    if shape.as_trimesh().is_some() {
        Some(ShapeKind::TriMesh)
    } else if shape.as_convex_polyhedron().is_some() {
        Some(ShapeKind::Convex)
    } else {
        None
    }
}

/// A collider builder for a deformable tri-mesh with `mesh`'s vertices and faces (collider
/// frame = the mesh's coordinates, m).
///
/// # Errors
/// [`AdapterError::Refit`] when parry rejects the mesh.
pub fn trimesh_collider(mesh: &TriMesh) -> Result<ColliderBuilder, AdapterError> {
    let flags = TriMeshFlags::DEFORMABLE;
    ColliderBuilder::trimesh_with_flags(mesh.positions().to_vec(), mesh.faces().to_vec(), flags).map_err(|e| {
        AdapterError::Refit { collider: ColliderHandle::invalid(), reason: format!("tri-mesh rejected: {e}") }
    })
}

/// A collider builder for the convex hull of `mesh`'s vertices (collider frame = the mesh's
/// coordinates, m).
///
/// # Errors
/// [`AdapterError::Refit`] for a flat or degenerate mesh.
pub fn convex_collider(mesh: &TriMesh) -> Result<ColliderBuilder, AdapterError> {
    ColliderBuilder::convex_hull(mesh.positions()).ok_or_else(|| AdapterError::Refit {
        collider: ColliderHandle::invalid(),
        reason: "no convex hull (flat or degenerate mesh)".into(),
    })
}

/// The refit that makes `collider` (handle `handle`, of `kind`) match `mesh`, whose vertices
/// `moved` changed (ascending); checked, nothing changed.
///
/// # Errors
/// [`AdapterError::Refit`]: the shape is not of `kind`, the vertex count differs, or the hull
/// fails.
pub fn prepare_refit(
    handle: ColliderHandle,
    collider: &Collider,
    kind: ShapeKind,
    mesh: &TriMesh,
    moved: &[u32],
) -> Result<Refit, AdapterError> {
    let bad = |reason: String| AdapterError::Refit { collider: handle, reason };
    if let Some(&last) = moved.last()
        && last as usize >= mesh.vertex_count()
    {
        return Err(bad(format!("moved vertex {last} of {}", mesh.vertex_count())));
    }
    match kind {
        ShapeKind::TriMesh => {
            let shape = collider.shape().as_trimesh().ok_or_else(|| bad("shape is not a tri-mesh".into()))?;
            if shape.vertices().len() != mesh.vertex_count() {
                return Err(bad(format!("{} vertices, the mesh has {}", shape.vertices().len(), mesh.vertex_count())));
            }
            Ok(Refit::Vertices(mesh.positions().to_vec()))
        }
        ShapeKind::Convex => {
            if collider.shape().as_convex_polyhedron().is_none() {
                return Err(bad("shape is not a convex polyhedron".into()));
            }
            SharedShape::convex_hull(mesh.positions())
                .map(Refit::Shape)
                .ok_or_else(|| bad("no convex hull of the dented mesh".into()))
        }
    }
}

impl Refit {
    /// Applies the refit to the collider it was prepared for.
    pub fn commit(self, collider: &mut Collider) {
        match self {
            Refit::Vertices(vertices) => {
                // Checked by `prepare_refit`: a tri-mesh with as many vertices.
                if let Some(mesh) = collider.shape_mut().as_trimesh_mut() {
                    mesh.set_vertices(&vertices);
                }
            }
            Refit::Shape(shape) => collider.set_shape(shape),
        }
    }
}

/// Refits `collider` to `mesh` at once ([`prepare_refit`] then [`Refit::commit`]).
///
/// # Errors
/// As [`prepare_refit`]; the collider is unchanged then.
pub fn refit_collider(
    handle: ColliderHandle,
    collider: &mut Collider,
    kind: ShapeKind,
    mesh: &TriMesh,
    moved: &[u32],
) -> Result<(), AdapterError> {
    prepare_refit(handle, collider, kind, mesh, moved)?.commit(collider);
    Ok(())
}
