//! Meshes: made from the caller's flat arrays (copied), read back through pointers into the
//! library's own memory (no copy).

use dentbend::TriMesh;
use dentbend::glam::{Vec2, Vec3};
use dentbend::mesh::{Asset, VertexAttributes};

use crate::handles;
use crate::status::{Failure, guarded_value};

// Positions and normals are handed out as 3 packed floats a vertex.
const _: () = assert!(std::mem::size_of::<Vec3>() == 12 && std::mem::align_of::<Vec3>() == 4);

/// Most vertices a mesh may have: larger counts are taken for garbage (the library reads
/// `3 * vertex_count` floats from the caller's pointer and could not check the buffer).
pub const DB_MAX_VERTICES: usize = 1 << 27;
/// Most triangles a mesh may have, for the same reason.
pub const DB_MAX_TRIANGLES: usize = 1 << 28;

/// A triangle mesh the library owns (opaque in C): positions, triangles, vertex normals (its
/// own, or the caller's authored ones), UVs when given, and the vertices the last change moved.
#[derive(Debug)]
pub struct DbMesh {
    pub(crate) asset: Asset,
    /// Vertices the last successful dent moved or added, ascending.
    pub(crate) moved: Vec<u32>,
}

impl DbMesh {
    /// The mesh: positions, triangles and smooth normals.
    pub(crate) fn mesh(&self) -> &TriMesh {
        self.asset.mesh()
    }

    /// The mesh behind `handle` (`what` names it), checked: not null, and alive where handles
    /// are tracked.
    ///
    /// # Safety
    /// `handle` is null or a pointer `db_mesh_new` returned and `db_mesh_free` has not freed.
    pub(crate) unsafe fn get<'a>(handle: *const DbMesh, what: &str) -> Result<&'a DbMesh, Failure> {
        // SAFETY: the caller's contract.
        unsafe { handles::get(handle, what) }
    }

    /// As [`get`](Self::get), mutably.
    ///
    /// # Safety
    /// As [`get`](Self::get), and no other reference to the mesh is in use.
    pub(crate) unsafe fn get_mut<'a>(handle: *mut DbMesh, what: &str) -> Result<&'a mut DbMesh, Failure> {
        // SAFETY: the caller's contract.
        unsafe { handles::get_mut(handle, what) }
    }
}

/// Reads `count` items of `width` values from `pointer` (null only when `count` is 0).
///
/// # Safety
/// `pointer` holds `count * width` values when `count` > 0.
unsafe fn read<T: Copy>(pointer: *const T, count: usize, width: usize, what: &str) -> Result<&[T], Failure> {
    if count == 0 {
        return Ok(&[]);
    }
    if pointer.is_null() {
        return Err(Failure::null(what));
    }
    // SAFETY: not null, and by the caller's contract `count * width` values long.
    Ok(unsafe { std::slice::from_raw_parts(pointer, count * width) })
}

/// A new mesh from `vertex_count` positions (3 floats each, x y z) and `triangle_count`
/// triangles (3 vertex indices each, counter-clockwise seen from outside). Both arrays are
/// copied. Returns null on failure (null pointers, counts past `DB_MAX_VERTICES` or
/// `DB_MAX_TRIANGLES`, an empty mesh, a coordinate that is NaN, infinite or beyond +-1e6, an index
/// out of range), with the reason in `db_last_error`.
///
/// # Safety
/// `positions` holds `3 * vertex_count` floats and `indices` `3 * triangle_count` values.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_mesh_new(
    positions: *const f32,
    vertex_count: usize,
    indices: *const u32,
    triangle_count: usize,
) -> *mut DbMesh {
    // SAFETY: the caller's contract; no attributes.
    unsafe {
        db_mesh_new_with_attributes(
            positions,
            vertex_count,
            indices,
            triangle_count,
            std::ptr::null(),
            std::ptr::null(),
        )
    }
}

/// As `db_mesh_new`, with the caller's vertex `normals` (3 floats a vertex, unit; null: the
/// mesh's own smooth normals) and `uvs` (2 floats a vertex; null: none), copied. A game asset's
/// vertices split at hard edges and UV seams keep them: a dent recomputes the normals around
/// what it moved, each side of a hard edge from its own faces, and new vertices interpolate
/// both from their parents.
///
/// # Safety
/// As `db_mesh_new`; `normals` is null or holds `3 * vertex_count` floats, `uvs` null or
/// `2 * vertex_count`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_mesh_new_with_attributes(
    positions: *const f32,
    vertex_count: usize,
    indices: *const u32,
    triangle_count: usize,
    normals: *const f32,
    uvs: *const f32,
) -> *mut DbMesh {
    let made = guarded_value(|| {
        if vertex_count > DB_MAX_VERTICES || triangle_count > DB_MAX_TRIANGLES {
            return Err(Failure::invalid(format!(
                "{vertex_count} vertices and {triangle_count} triangles: the limits are {DB_MAX_VERTICES} and \
                 {DB_MAX_TRIANGLES} (a count this large is taken for garbage)"
            )));
        }
        // SAFETY: the caller's contract.
        let (p, i) =
            unsafe { (read(positions, vertex_count, 3, "positions")?, read(indices, triangle_count, 3, "indices")?) };
        let points = p.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect();
        let faces = i.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let mesh = TriMesh::new(points, faces).map_err(|e| Failure::invalid(e.to_string()))?;
        let mut attributes = VertexAttributes::default();
        if !normals.is_null() {
            // SAFETY: not null, `3 * vertex_count` floats by the caller's contract.
            let n = unsafe { read(normals, vertex_count, 3, "normals")? };
            attributes.normals = Some(n.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect());
        }
        if !uvs.is_null() {
            // SAFETY: not null, `2 * vertex_count` floats by the caller's contract.
            let uv = unsafe { read(uvs, vertex_count, 2, "uvs")? };
            attributes.uvs = vec![uv.chunks_exact(2).map(|c| Vec2::new(c[0], c[1])).collect()];
        }
        let groups = vec![Default::default()];
        let face_groups = vec![0; mesh.face_count()];
        let asset = Asset::new(mesh, attributes, groups, face_groups).map_err(|e| Failure::invalid(e.to_string()))?;
        Ok(DbMesh { asset, moved: Vec::new() })
    });
    made.map_or(std::ptr::null_mut(), handles::make)
}

/// Frees `mesh` (null: nothing). Freeing a mesh twice is undefined behaviour; debug builds of
/// the library (and its `track-handles` feature) catch it, leave the memory alone and say so in
/// `db_last_error`.
///
/// # Safety
/// `mesh` is null or a mesh of `db_mesh_new` not freed yet.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_mesh_free(mesh: *mut DbMesh) {
    // SAFETY: the caller's contract.
    unsafe { handles::free(mesh, "db_mesh_free") }
}

/// Reads one value from live mesh `mesh`; `fallback` (with the reason in `db_last_error`) when
/// it is null or not alive.
///
/// # Safety
/// As [`DbMesh::get`].
unsafe fn read_mesh<T>(mesh: *const DbMesh, fallback: T, value: impl FnOnce(&DbMesh) -> T) -> T {
    // SAFETY: the caller's contract.
    guarded_value(|| unsafe { DbMesh::get(mesh, "mesh") }.map(value)).unwrap_or(fallback)
}

/// Number of vertices of `mesh` (0 when it is null).
///
/// # Safety
/// `mesh` is null or a live mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_mesh_vertex_count(mesh: *const DbMesh) -> usize {
    // SAFETY: the caller's contract.
    unsafe { read_mesh(mesh, 0, |m| m.mesh().vertex_count()) }
}

/// Number of triangles of `mesh` (0 when it is null).
///
/// # Safety
/// `mesh` is null or a live mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_mesh_triangle_count(mesh: *const DbMesh) -> usize {
    // SAFETY: the caller's contract.
    unsafe { read_mesh(mesh, 0, |m| m.mesh().face_count()) }
}

/// The positions of `mesh`: 3 floats a vertex, `db_mesh_vertex_count` vertices, valid until the
/// next change of the mesh (a dent may also add vertices). Null when `mesh` is null.
///
/// # Safety
/// `mesh` is null or a live mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_mesh_positions(mesh: *const DbMesh) -> *const f32 {
    // SAFETY: the caller's contract.
    unsafe { read_mesh(mesh, std::ptr::null(), |m| m.mesh().positions().as_ptr().cast()) }
}

/// The vertex normals of `mesh` (the caller's authored ones when given, else unit,
/// area-weighted): 3 floats a vertex, valid as `db_mesh_positions`.
///
/// # Safety
/// `mesh` is null or a live mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_mesh_normals(mesh: *const DbMesh) -> *const f32 {
    // SAFETY: the caller's contract.
    unsafe {
        read_mesh(mesh, std::ptr::null(), |m| match &m.asset.attributes().normals {
            Some(authored) => authored.as_ptr().cast(),
            None => m.mesh().normals().as_ptr().cast(),
        })
    }
}

/// The triangles of `mesh`: 3 vertex indices each, `db_mesh_triangle_count` triangles, valid as
/// `db_mesh_positions` (a dent that refines the mesh changes them).
///
/// # Safety
/// `mesh` is null or a live mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_mesh_indices(mesh: *const DbMesh) -> *const u32 {
    // SAFETY: the caller's contract.
    unsafe { read_mesh(mesh, std::ptr::null(), |m| m.mesh().faces().as_ptr().cast()) }
}

/// The UVs of `mesh` (2 floats a vertex, the first set), valid as `db_mesh_positions`; null
/// when it has none.
///
/// # Safety
/// `mesh` is null or a live mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_mesh_uvs(mesh: *const DbMesh) -> *const f32 {
    // SAFETY: the caller's contract.
    unsafe {
        read_mesh(mesh, std::ptr::null(), |m| {
            m.asset.attributes().uvs.first().map_or(std::ptr::null(), |uv| uv.as_ptr().cast())
        })
    }
}

/// How many vertices the last successful dent of `mesh` moved or added.
///
/// # Safety
/// `mesh` is null or a live mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_mesh_moved_count(mesh: *const DbMesh) -> usize {
    // SAFETY: the caller's contract.
    unsafe { read_mesh(mesh, 0, |m| m.moved.len()) }
}

/// The vertices the last successful dent of `mesh` moved or added (ascending indices,
/// `db_mesh_moved_count` of them): the ones a renderer's copy must update. Valid as
/// `db_mesh_positions`.
///
/// # Safety
/// `mesh` is null or a live mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_mesh_moved(mesh: *const DbMesh) -> *const u32 {
    // SAFETY: the caller's contract.
    unsafe { read_mesh(mesh, std::ptr::null(), |m| m.moved.as_ptr()) }
}
