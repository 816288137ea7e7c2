//! Refitting a parry3d triangle-mesh collider after a dent moved some of its vertices, for shapes
//! the caller owns (dentbend's own world uses it too).
//!
//! # Vertex numbering
//!
//! Flag [`MERGE_DUPLICATE_VERTICES`](TriMeshFlags::MERGE_DUPLICATE_VERTICES) (which
//! [`FIX_INTERNAL_EDGES`](TriMeshFlags::FIX_INTERNAL_EDGES) implies) makes parry renumber the
//! vertices in order of first use by the triangles and weld equal positions, so the shape's vertex
//! indices are not the source mesh's. [`VertexMap`] translates between the two.

use glam::Vec3;
use parry3d::shape::{SharedShape, TriMesh, TriMeshFlags};
use rustc_hash::FxHashMap;

/// Why a collider refit was refused; the shape is unchanged then.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RefitError {
    /// `moved` and `positions` differ in length.
    #[error("{moved} moved vertex indices but {positions} positions")]
    LengthMismatch {
        /// Length of the index list.
        moved: usize,
        /// Length of the position list.
        positions: usize,
    },
    /// A moved index names no vertex of the shape.
    #[error("moved entry {entry}: vertex {index} does not exist (the shape has {vertex_count} vertices)")]
    UnknownVertex {
        /// Position of the offending entry in `moved`.
        entry: usize,
        /// The index given.
        index: u32,
        /// The shape's vertex count.
        vertex_count: usize,
    },
    /// The same vertex is listed twice.
    #[error("moved entry {entry}: vertex {index} is listed twice")]
    DuplicateVertex {
        /// Position of the second occurrence in `moved`.
        entry: usize,
        /// The repeated index.
        index: u32,
    },
    /// A new position has a NaN or infinite coordinate.
    #[error("moved entry {entry}: the new position of vertex {index} is not finite: {position}")]
    NonFinite {
        /// Position of the offending entry in `moved`.
        entry: usize,
        /// The vertex.
        index: u32,
        /// The position given, world units.
        position: Vec3,
    },
    /// The shape is not a triangle mesh.
    #[error("the collider is not a triangle mesh")]
    NotTriMesh,
}

/// What a refit did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RefitStats {
    /// Vertices moved (the length of the update).
    pub moved_vertices: usize,
    /// Triangle leaves whose bounding box parry refitted: every triangle when anything moved
    /// (parry3d 0.31 refits the whole tree, see [`refit_trimesh`]), 0 otherwise.
    pub refitted_leaves: usize,
    /// Whether the mesh's pseudo-normals were recomputed (it has some and anything moved).
    pub pseudo_normals_recomputed: bool,
}

/// Checks an update of `vertex_count` vertices: same lengths, indices in range and distinct,
/// finite positions.
///
/// # Errors
/// The first [`RefitError`] found, in entry order.
pub fn validate_refit(vertex_count: usize, moved: &[u32], positions: &[Vec3]) -> Result<(), RefitError> {
    if moved.len() != positions.len() {
        return Err(RefitError::LengthMismatch { moved: moved.len(), positions: positions.len() });
    }
    let mut seen = vec![0u64; vertex_count.div_ceil(64)];
    for (entry, (&index, &position)) in moved.iter().zip(positions).enumerate() {
        let i = index as usize;
        if i >= vertex_count {
            return Err(RefitError::UnknownVertex { entry, index, vertex_count });
        }
        let (word, bit) = (i / 64, 1u64 << (i % 64));
        if seen[word] & bit != 0 {
            return Err(RefitError::DuplicateVertex { entry, index });
        }
        seen[word] |= bit;
        if !position.is_finite() {
            return Err(RefitError::NonFinite { entry, index, position });
        }
    }
    Ok(())
}

/// Moves vertices `moved` (the shape's own indices, see [`VertexMap`]) of `shape` to `positions`
/// (body coordinates, world units; `positions[k]` is the new place of `moved[k]`) and refits the
/// collider: leaf boxes, their ancestors and the pseudo-normals, if the mesh has any.
///
/// An empty `moved` changes nothing and costs nothing. Vertices of a mesh built with a merging
/// flag are numbered by parry, not like the source mesh: see [`VertexMap`].
///
/// # What parry3d 0.31 allows
///
/// parry3d's [`TriMesh`] keeps its vertices, BVH and pseudo-normals private. Its public update
/// paths are [`TriMesh::set_vertices`] and [`TriMesh::update_vertices`], and both refit *every*
/// leaf and recompute *every* pseudo-normal (with hash maps over all edges) when the mesh has any
/// (flags [`ORIENTED`](TriMeshFlags::ORIENTED) or
/// [`FIX_INTERNAL_EDGES`](TriMeshFlags::FIX_INTERNAL_EDGES)). The tree itself
/// ([`parry3d::partitioning::Bvh`]) has a public partial refit (`insert_or_update_partially` +
/// `refit_partial`), but the mesh only lends it out read-only ([`TriMesh::bvh`]), so a refit of
/// only the changed leaves and their ancestors cannot be written against parry's public API.
///
/// This function therefore validates the update, skips it when nothing moved, and otherwise
/// takes the cheapest public route, [`TriMesh::update_vertices`], writing only the moved
/// vertices. The result is exact: the leaves, the ancestors and the pseudo-normals are those of a
/// fresh build on the new vertices (the tree's *structure* stays the one built first).
///
/// Cost on a 24,960-triangle sphere, one core (bench `collider_refit`): about 0.4 ms without
/// pseudo-normals and 4.7 ms with them ([`FIX_INTERNAL_EDGES`](TriMeshFlags::FIX_INTERNAL_EDGES),
/// as dentbend's world builds its mesh colliders), against 14 ms for a rebuild. Most of the
/// 4.7 ms is parry's recomputation of every pseudo-normal, which only parry can make partial.
///
/// # Errors
/// [`RefitError`] for lengths that differ, an unknown or repeated index, or a NaN/∞ position;
/// the shape is unchanged then.
///
/// # Example
/// ```
/// use dentbend::glam::Vec3;
/// use dentbend::collider::refit_trimesh;
/// use parry3d::shape::TriMesh;
/// let mut shape = TriMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]).unwrap();
/// refit_trimesh(&mut shape, &[2], &[Vec3::new(0.0, 1.0, 2.0)])?;
/// assert_eq!(shape.local_aabb().maxs, Vec3::new(1.0, 1.0, 2.0));
/// assert!(refit_trimesh(&mut shape, &[3], &[Vec3::ONE]).is_err());
/// # Ok::<(), dentbend::collider::RefitError>(())
/// ```
pub fn refit_trimesh(shape: &mut TriMesh, moved: &[u32], positions: &[Vec3]) -> Result<RefitStats, RefitError> {
    validate_refit(shape.vertices().len(), moved, positions)?;
    if moved.is_empty() {
        return Ok(RefitStats::default());
    }
    shape.update_vertices(|vertices| {
        for (&index, &position) in moved.iter().zip(positions) {
            vertices[index as usize] = position;
        }
    });
    Ok(RefitStats {
        moved_vertices: moved.len(),
        refitted_leaves: shape.num_triangles(),
        pseudo_normals_recomputed: shape.pseudo_normals().is_some(),
    })
}

/// [`refit_trimesh`] on a shared shape. The update is validated before the shape is touched; a
/// shape whose `Arc` is shared is cloned first (copy on write), so other holders keep the old one.
///
/// # Errors
/// [`RefitError::NotTriMesh`] for any other shape, else as [`refit_trimesh`]; the shape is
/// unchanged then.
pub fn refit_shared_trimesh(
    shape: &mut SharedShape,
    moved: &[u32],
    positions: &[Vec3],
) -> Result<RefitStats, RefitError> {
    let vertex_count = shape.as_trimesh().ok_or(RefitError::NotTriMesh)?.vertices().len();
    validate_refit(vertex_count, moved, positions)?;
    if moved.is_empty() {
        return Ok(RefitStats::default());
    }
    let trimesh = shape.make_mut().as_trimesh_mut().ok_or(RefitError::NotTriMesh)?;
    refit_trimesh(trimesh, moved, positions)
}

/// For each vertex of a parry [`TriMesh`] built from a source mesh, the source vertex it came from.
///
/// Without merging flags this is the identity; with
/// [`MERGE_DUPLICATE_VERTICES`](TriMeshFlags::MERGE_DUPLICATE_VERTICES) parry numbers vertices in
/// order of first use by the faces and welds equal positions: the shape's vertex `j` then comes
/// from the first source vertex (in face order) at its position. After a dent that pulls welded
/// source vertices apart, the shape follows that first one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VertexMap {
    source_of: Vec<u32>,
}

impl VertexMap {
    /// The map of `shape`, built from source `positions` and `faces` (as they were when the shape
    /// was built, or last refitted). `None` when `shape` does not come from them (its vertices
    /// are not the ones parry's numbering would give), so the caller rebuilds the shape.
    pub fn new(shape: &TriMesh, positions: &[Vec3], faces: &[[u32; 3]]) -> Option<Self> {
        let vertices = shape.vertices();
        let source_of: Vec<u32> = if vertices == positions {
            (0..positions.len() as u32).collect()
        } else if shape.flags().contains(TriMeshFlags::MERGE_DUPLICATE_VERTICES) {
            first_use_order(positions, faces)?
        } else {
            return None;
        };
        let matches = source_of.len() == vertices.len()
            && source_of.iter().zip(vertices).all(|(&s, v)| positions.get(s as usize) == Some(v));
        matches.then_some(Self { source_of })
    }

    /// The source vertex of every shape vertex.
    pub fn source_of(&self) -> &[u32] {
        &self.source_of
    }

    /// The update for [`refit_trimesh`] that moves the shape to source positions `after`, given
    /// the source positions `before` (both indexed like the source mesh): the shape's vertices
    /// whose source moved, and their new positions.
    pub fn moved_between(&self, before: &[Vec3], after: &[Vec3]) -> (Vec<u32>, Vec<Vec3>) {
        let mut moved = Vec::new();
        let mut positions = Vec::new();
        for (j, &s) in self.source_of.iter().enumerate() {
            let s = s as usize;
            if let (Some(&a), Some(&b)) = (before.get(s), after.get(s))
                && a.to_array().map(f32::to_bits) != b.to_array().map(f32::to_bits)
            {
                moved.push(j as u32);
                positions.push(b);
            }
        }
        (moved, positions)
    }
}

/// parry's merged numbering: source vertices in order of first use by `faces`, one per distinct
/// position (`-0.0` and `0.0` alike, as parry compares with `==`). `None` for an index out of
/// range or a NaN position.
fn first_use_order(positions: &[Vec3], faces: &[[u32; 3]]) -> Option<Vec<u32>> {
    let key = |p: Vec3| (p + Vec3::ZERO).to_array().map(f32::to_bits);
    let mut seen: FxHashMap<[u32; 3], ()> = FxHashMap::default();
    seen.reserve(positions.len());
    let mut order = Vec::with_capacity(positions.len());
    for &corner in faces.iter().flatten() {
        let p = *positions.get(corner as usize)?;
        if p.is_nan() {
            return None;
        }
        if seen.insert(key(p), ()).is_none() {
            order.push(corner);
        }
    }
    Some(order)
}
