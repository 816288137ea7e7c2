//! Collider refits after a dent: the one place the adapter changes a collider's shape.
//!
//! - Tri-mesh colliders are refitted in place over the moved vertices only
//!   ([`dentbend::collider::refit_trimesh`]: validated, then parry's `update_vertices`, which refits
//!   the tree keeping its structure); build them with [`trimesh_collider`] (deformable, no
//!   pseudo-normals, vertices in the mesh's order) so the refit stays cheap.
//! - Convex colliders (dynamic bodies) get the convex hull of the dented vertices
//!   ([`convex_shape`]: dentbend's hull, which costs half of parry's, handed to parry as a
//!   convex mesh).

use dentbend::collider::{refit_trimesh, validate_refit};
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
    /// The moved tri-mesh vertices (indices, ascending) and their new positions (collider
    /// frame, m).
    Vertices(Vec<u32>, Vec<Vec3>),
    /// A new shape: a convex hull or a rebuilt tri-mesh.
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
    convex_shape(mesh).map(ColliderBuilder::new).ok_or_else(|| AdapterError::Refit {
        collider: ColliderHandle::invalid(),
        reason: "no convex hull (flat or degenerate mesh)".into(),
    })
}

/// The convex polyhedron of `mesh`'s vertices ([`TriMesh::convex_hull`], then parry's
/// convex mesh, which merges coplanar faces); parry's own hull where that refuses it. `None`
/// for a flat or degenerate mesh. [`convex_collider`] builds with it and every refit of a
/// convex collider makes it: the same solid as parry's own hull in half the time, its faces
/// split and its vertices ordered differently.
pub fn convex_shape(mesh: &TriMesh) -> Option<SharedShape> {
    let ours =
        mesh.convex_hull().ok().and_then(|hull| SharedShape::convex_mesh(hull.positions().to_vec(), hull.faces()));
    ours.or_else(|| SharedShape::convex_hull(mesh.positions()))
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
            let positions: Vec<Vec3> = moved.iter().map(|&v| mesh.positions()[v as usize]).collect();
            validate_refit(shape.vertices().len(), moved, &positions).map_err(|e| bad(e.to_string()))?;
            Ok(Refit::Vertices(moved.to_vec(), positions))
        }
        ShapeKind::Convex => {
            if collider.shape().as_convex_polyhedron().is_none() {
                return Err(bad("shape is not a convex polyhedron".into()));
            }
            convex_shape(mesh).map(Refit::Shape).ok_or_else(|| bad("no convex hull of the dented mesh".into()))
        }
    }
}

impl Refit {
    /// Applies the refit to the collider it was prepared for.
    pub fn commit(self, collider: &mut Collider) {
        match self {
            Refit::Vertices(moved, positions) => {
                // Checked by `prepare_refit`: a tri-mesh with as many vertices, a valid update.
                if let Some(mesh) = collider.shape_mut().as_trimesh_mut() {
                    let _ = refit_trimesh(mesh, &moved, &positions);
                }
            }
            Refit::Shape(shape) => collider.set_shape(shape),
        }
    }
}

/// A new tri-mesh shape for `collider` from `mesh` (same flags as its shape now), for a dent
/// that refined the mesh ([`DentedTarget::topology_changed`](dentbend::damage::DentedTarget)):
/// its vertices and faces changed, so the shape is rebuilt instead of refitted.
///
/// # Errors
/// [`AdapterError::Refit`] when the collider is not a tri-mesh or parry refuses the mesh.
pub fn rebuild_trimesh(handle: ColliderHandle, collider: &Collider, mesh: &TriMesh) -> Result<Refit, AdapterError> {
    trimesh_shape(handle, collider, mesh).map(Refit::Shape)
}

/// A tri-mesh shape of `mesh` with the flags of `collider`'s tri-mesh.
///
/// # Errors
/// As [`rebuild_trimesh`].
pub(crate) fn trimesh_shape(
    handle: ColliderHandle,
    collider: &Collider,
    mesh: &TriMesh,
) -> Result<SharedShape, AdapterError> {
    let bad = |reason: String| AdapterError::Refit { collider: handle, reason };
    let shape = collider.shape().as_trimesh().ok_or_else(|| bad("shape is not a tri-mesh".into()))?;
    SharedShape::trimesh_with_flags(mesh.positions().to_vec(), mesh.faces().to_vec(), shape.flags())
        .map_err(|e| bad(format!("the new mesh: {e}")))
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
