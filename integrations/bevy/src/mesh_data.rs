//! Bevy meshes as dentbend sees them: a [`TriMesh`] from a Bevy [`Mesh`], where positions and
//! normals sit in Bevy's interleaved vertex buffer, and dented positions and normals written
//! back into a mesh asset (the CPU path).
//!
//! Bevy interleaves a mesh's attributes in the order of their ids (position 0, normal 1, UV 2,
//! …), each `format.size()` bytes, so a vertex is the sum of those sizes.

use bevy::asset::RenderAssetUsages;
use bevy::mesh::{Indices, Mesh, MeshVertexAttribute, PrimitiveTopology, VertexAttributeValues};
use bevy::render::render_resource::VertexFormat;
use dentbend::TriMesh;
use dentbend::glam::Vec3;
use dentbend::gpu::VertexLayout;
use dentbend::mesh::Refinement;

/// Why a Bevy mesh cannot dent.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MeshDataError {
    /// The main world no longer holds the mesh's data (`RenderAssetUsages::RENDER_WORLD` only).
    #[error("the mesh's data lives only in the render world (give it RenderAssetUsages::MAIN_WORLD too)")]
    Extracted,
    /// Not a triangle list.
    #[error("the mesh is a {0:?}, not a triangle list")]
    Topology(PrimitiveTopology),
    /// No `Mesh::ATTRIBUTE_POSITION`, or not three f32 per vertex.
    #[error("the mesh has no Float32x3 positions")]
    NoPositions,
    /// Normals that are not three f32 per vertex.
    #[error("the mesh's normals are not Float32x3")]
    BadNormals,
    /// dentbend refused the triangles (NaN, ∞, indices out of range, no triangle).
    #[error("dentbend refused the mesh: {0}")]
    Refused(String),
}

/// Where a mesh's positions and normals are in Bevy's vertex buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SlabLayout {
    /// Bytes per vertex (all attributes).
    pub stride: u64,
    /// Byte offsets of the position and normal within a vertex.
    pub fields: VertexLayout,
}

/// The triangles of `mesh` (its own coordinates) as a [`TriMesh`], vertex for vertex (no
/// welding, so vertex `v` of the result is vertex `v` of Bevy's buffer). A mesh without indices
/// is read as consecutive triangles.
///
/// # Errors
/// [`MeshDataError`].
pub fn tri_mesh(mesh: &Mesh) -> Result<TriMesh, MeshDataError> {
    if mesh.primitive_topology() != PrimitiveTopology::TriangleList {
        return Err(MeshDataError::Topology(mesh.primitive_topology()));
    }
    let positions = match mesh.try_attribute_option(Mesh::ATTRIBUTE_POSITION) {
        Err(_) => return Err(MeshDataError::Extracted),
        Ok(Some(VertexAttributeValues::Float32x3(p))) => p.iter().map(|p| Vec3::from_array(*p)).collect::<Vec<_>>(),
        Ok(_) => return Err(MeshDataError::NoPositions),
    };
    let indices: Vec<u32> = match mesh.try_indices_option() {
        Err(_) => return Err(MeshDataError::Extracted),
        Ok(Some(Indices::U16(i))) => i.iter().map(|&i| u32::from(i)).collect(),
        Ok(Some(Indices::U32(i))) => i.clone(),
        Ok(None) => (0..positions.len() as u32).collect(),
    };
    let faces = indices.chunks_exact(3).map(|f| [f[0], f[1], f[2]]).collect();
    TriMesh::new(positions, faces).map_err(|e| MeshDataError::Refused(e.to_string()))
}

/// Gives `mesh` the smooth normals of `tri` (its triangles, [`tri_mesh`]) when it has none;
/// whether it had to.
///
/// # Errors
/// [`MeshDataError::Extracted`], [`MeshDataError::BadNormals`].
pub fn add_missing_normals(mesh: &mut Mesh, tri: &TriMesh) -> Result<bool, MeshDataError> {
    match mesh.try_attribute_option(Mesh::ATTRIBUTE_NORMAL) {
        Err(_) => Err(MeshDataError::Extracted),
        Ok(Some(VertexAttributeValues::Float32x3(_))) => Ok(false),
        Ok(Some(_)) => Err(MeshDataError::BadNormals),
        Ok(None) => {
            let normals: Vec<[f32; 3]> = tri.normals().iter().map(|n| n.to_array()).collect();
            mesh.try_insert_attribute(Mesh::ATTRIBUTE_NORMAL, normals).map_err(|_| MeshDataError::Extracted)?;
            Ok(true)
        }
    }
}

/// Where `mesh`'s positions and normals lie in its interleaved vertex (as Bevy packs it).
///
/// # Errors
/// [`MeshDataError::Extracted`], [`MeshDataError::NoPositions`], [`MeshDataError::BadNormals`]
/// (also when it has no normals).
pub fn slab_layout(mesh: &Mesh) -> Result<SlabLayout, MeshDataError> {
    let attributes = mesh.try_attributes().map_err(|_| MeshDataError::Extracted)?;
    let (mut stride, mut position, mut normal) = (0, None, None);
    for (attribute, _) in attributes {
        let at = stride;
        stride += attribute.format.size();
        let is = |other: MeshVertexAttribute| attribute.id == other.id;
        if is(Mesh::ATTRIBUTE_POSITION) {
            position = (attribute.format == VertexFormat::Float32x3).then_some(at);
        } else if is(Mesh::ATTRIBUTE_NORMAL) {
            normal = (attribute.format == VertexFormat::Float32x3).then_some(at);
        }
    }
    let position = position.ok_or(MeshDataError::NoPositions)?;
    let normal = normal.ok_or(MeshDataError::BadNormals)?;
    Ok(SlabLayout { stride, fields: VertexLayout { position, normal: Some(normal) } })
}

/// A copy of `mesh` that the main world keeps (dentable meshes are private to their entity and
/// must stay readable for the CPU path and for colliders).
pub fn private_copy(mesh: &Mesh) -> Mesh {
    let mut copy = mesh.clone();
    copy.asset_usage = RenderAssetUsages::MAIN_WORLD | RenderAssetUsages::RENDER_WORLD;
    copy
}

/// Writes `dented`'s positions and normals into `mesh` (Bevy uploads the asset again). When a
/// dent refined the mesh (`refinement` not empty), its new vertices get every other attribute
/// from their split edge (`split_attributes.rs`: interpolated, tangents re-orthogonalised,
/// integer ones and joint weights from the nearer parent), and the indices are replaced.
///
/// # Errors
/// [`MeshDataError::Extracted`] when the main world no longer holds the data.
pub fn write_dented(mesh: &mut Mesh, dented: &TriMesh, refinement: &Refinement) -> Result<(), MeshDataError> {
    let extracted = |_| MeshDataError::Extracted;
    if !refinement.vertices.is_empty() {
        if mesh.try_attributes().is_err() {
            return Err(MeshDataError::Extracted);
        }
        crate::split_attributes::extend_attributes(mesh, refinement, dented.normals());
        let indices = dented.faces().iter().flatten().copied().collect();
        mesh.try_insert_indices(Indices::U32(indices)).map_err(extracted)?;
    }
    write_vertices(mesh, dented.positions(), dented.normals())
}

/// Replaces `mesh`'s positions (its own coordinates, m) and unit normals.
///
/// # Errors
/// [`MeshDataError::Extracted`] when the main world no longer holds the data.
pub fn write_vertices(mesh: &mut Mesh, positions: &[Vec3], normals: &[Vec3]) -> Result<(), MeshDataError> {
    let extracted = |_| MeshDataError::Extracted;
    let positions: Vec<[f32; 3]> = positions.iter().map(|p| p.to_array()).collect();
    let normals: Vec<[f32; 3]> = normals.iter().map(|n| n.to_array()).collect();
    mesh.try_insert_attribute(Mesh::ATTRIBUTE_POSITION, positions).map_err(extracted)?;
    mesh.try_insert_attribute(Mesh::ATTRIBUTE_NORMAL, normals).map_err(extracted)?;
    Ok(())
}

/// `mesh`'s positions with vertices `indices` moved to `positions`; `None` when an index is
/// past the mesh's vertices.
pub fn moved_positions(mesh: &TriMesh, indices: &[u32], positions: &[Vec3]) -> Option<Vec<Vec3>> {
    let mut out = mesh.positions().to_vec();
    for (&v, &p) in indices.iter().zip(positions) {
        *out.get_mut(v as usize)? = p;
    }
    Some(out)
}

/// `mesh` as a Bevy triangle-list mesh (positions, smooth normals, `u32` indices), kept in both
/// worlds.
pub fn bevy_mesh(mesh: &TriMesh) -> Mesh {
    let positions: Vec<[f32; 3]> = mesh.positions().iter().map(|p| p.to_array()).collect();
    let normals: Vec<[f32; 3]> = mesh.normals().iter().map(|n| n.to_array()).collect();
    Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::MAIN_WORLD | RenderAssetUsages::RENDER_WORLD)
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
        .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, normals)
        .with_inserted_indices(Indices::U32(mesh.faces().iter().flatten().copied().collect()))
}
