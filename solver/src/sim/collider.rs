//! Collision shapes through parry3d, built from a body's mesh in body coordinates.

use std::sync::Arc;

use parry3d::shape::{SharedShape, TriMeshFlags};

use super::BodyKind;
use super::capsule_fit::capsule_shape;
use dentbend::collider::{VertexMap, refit_shared_trimesh};
use dentbend::mesh::TriMesh;

/// Which parry3d shape collides for a body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ColliderKind {
    /// Static and kinematic bodies: [`TriMesh`](Self::TriMesh); dynamic: [`ConvexHull`](Self::ConvexHull).
    #[default]
    Auto,
    /// A ball around the centre of mass through the farthest vertex (analytic: dents do not
    /// change it).
    Ball,
    /// The box of the mesh's bounds, centred on the centre of mass (analytic: dents do not
    /// change it).
    Cuboid,
    /// The convex hull of the vertices, rebuilt after every dent.
    ConvexHull,
    /// A capsule on the vertices' principal axis, as wide as the mesh and as long (its tips at
    /// the farthest vertices): struts, rods and limbs, at one or two contact points per pair
    /// (analytic: dents do not change it).
    Capsule,
    /// The triangle mesh itself (concave and static bodies), rebuilt after every dent.
    TriMesh,
}

impl ColliderKind {
    /// The concrete kind for a body of `kind` (resolves [`Auto`](Self::Auto)).
    pub fn resolve(self, kind: BodyKind) -> Self {
        match (self, kind) {
            (Self::Auto, BodyKind::Dynamic) => Self::ConvexHull,
            (Self::Auto, _) => Self::TriMesh,
            (other, _) => other,
        }
    }

    /// Whether the shape is rebuilt from the mesh after a dent.
    pub fn follows_mesh(self, kind: BodyKind) -> bool {
        matches!(self.resolve(kind), Self::ConvexHull | Self::TriMesh)
    }

    /// Moves a mesh collider's vertices from `before`'s to `after`'s (same faces, as after a
    /// dent) through [`refit_shared_trimesh`], translating vertex numbers with `map` (computed
    /// on first use and kept). Only the vertices whose position changed are written. Returns
    /// `false` when the shape is not a triangle mesh built from `before`, so the caller rebuilds
    /// it (and drops `map`).
    pub(crate) fn refit(
        shape: &mut SharedShape,
        map: &mut Option<Arc<VertexMap>>,
        before: &TriMesh,
        after: &TriMesh,
    ) -> bool {
        if before.faces() != after.faces() {
            return false;
        }
        let Some(trimesh) = shape.as_trimesh() else { return false };
        if map.is_none() {
            *map = VertexMap::new(trimesh, before.positions(), before.faces()).map(Arc::new);
        }
        let Some(vertex_map) = map.as_deref() else { return false };
        let (moved, positions) = vertex_map.moved_between(before.positions(), after.positions());
        refit_shared_trimesh(shape, &moved, &positions).is_ok()
    }

    /// Builds the shape of a body of `kind` with surface `mesh` (body coordinates).
    ///
    /// # Errors
    /// A sentence saying why parry3d refused the mesh.
    pub fn build_for(self, kind: BodyKind, mesh: &TriMesh) -> Result<SharedShape, String> {
        let positions = mesh.positions();
        match self.resolve(kind) {
            Self::Ball => {
                let radius = positions.iter().map(|p| p.length()).fold(0.0, f32::max);
                if radius > 0.0 {
                    Ok(SharedShape::ball(radius))
                } else {
                    Err("a ball collider needs a mesh of non-zero size".into())
                }
            }
            Self::Cuboid => {
                let (lo, hi) = mesh.bounds();
                let half = lo.abs().max(hi.abs());
                if half.min_element() > 0.0 {
                    Ok(SharedShape::cuboid(half.x, half.y, half.z))
                } else {
                    Err("a cuboid collider needs a mesh with extent along every axis".into())
                }
            }
            Self::Capsule => capsule_shape(mesh),
            Self::ConvexHull => SharedShape::convex_hull(positions)
                .ok_or_else(|| "the convex hull of the mesh is degenerate (flat or too few points)".into()),
            Self::TriMesh | Self::Auto => {
                // Deformable so a dent refits the tree instead of rebuilding it (vertices are
                // kept one-to-one with the mesh's, so no merging).
                let flags = TriMeshFlags::DEFORMABLE
                    | TriMeshFlags::DELETE_DEGENERATE_TRIANGLES
                    | TriMeshFlags::FIX_INTERNAL_EDGES;
                SharedShape::trimesh_with_flags(positions.to_vec(), mesh.faces().to_vec(), flags)
                    .map_err(|e| format!("parry3d refused the triangle mesh: {e:?}"))
            }
        }
    }
}
