// normals: unit vertex normals of triangle meshes, the area-weighted average of the normals of
// the faces touching each vertex: n = normalize_or_zero(Σ (b − a) × (c − a)) over its faces
// (a, b, c), zero where the sum's length is zero or too small to invert. GPU twin of
// `TriMesh::recompute_normals` and, with `moved_only`, `TriMesh::recompute_normals_near` in
// src/mesh/trimesh.rs (`face_area_normal`, glam's `cross` and `normalize_or_zero`).
// WGSL has no float atomics, so instead of scattering each face into its three corners, every
// vertex gathers its own faces through a CSR adjacency that the host builds once per mesh; it
// lists a vertex's faces in ascending face order, so each sum is accumulated in the same order as
// the CPU's loop over faces.
//
// Bindings (group 0):
//   0 params     uniform array<NormalsParams, NORMALS_MAX_TARGETS>: the targets of this dispatch
//                (a uniform, because the four storage bindings below are the downlevel limit)
//   1 positions  array<vec4<f32>>, read: xyz = world position, w = moved flag (> 0: the vertex
//                moved in this batch, as written by displace.wgsl); target t's vertices at
//                params[t].vertex_offset
//   2 faces      array<u32>, read: three vertex indices per triangle, relative to the target's
//                vertex_offset; target t's triangles at params[t].face_offset (in triangles)
//   3 adjacency  array<u32>, read: per target, at params[t].adjacency_offset, vertex_count + 1
//                offsets followed by the face lists: the faces of vertex v (indices relative to
//                the target's face_offset) are block[block[v] .. block[v + 1]], offsets counted
//                from the start of the target's block (so block[0] = vertex_count + 1)
//   4 normals    array<vec4<f32>>, read_write: xyz = unit normal, w = 0, at the positions' index
//
// Dispatch geometry: one invocation per vertex, x = vertex index within the target, y = target
// index of the dispatch (dent-batch order); dispatch = [ceil(max vertex_count / 64), targets,
// 1], at most NORMALS_MAX_TARGETS targets per dispatch. Invocations past their target's
// vertex_count return at once. With params[t].moved_only = 1 a vertex is recomputed only when
// one of its faces has a moved corner (the vertices `recompute_normals_near` refreshes); the
// others keep the normal already in `normals`.
//
// Host constants matched: NormalsParams = normals::NormalsParams (src/gpu/normals.rs, 32 bytes),
// NORMALS_MAX_TARGETS = normals::MAX_TARGETS_PER_DISPATCH, WORKGROUP = normals::WORKGROUP.

const WORKGROUP: u32 = 64u;
const NORMALS_MAX_TARGETS: u32 = 512u;
// Largest finite f32: `rcp <= F32_MAX` is glam's `rcp.is_finite()` for the non-NaN rcp > 0.
const F32_MAX: f32 = 3.40282347e38;

struct NormalsParams {
    vertex_count: u32,
    vertex_offset: u32,
    face_offset: u32,
    adjacency_offset: u32,
    moved_only: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<uniform> params: array<NormalsParams, NORMALS_MAX_TARGETS>;
@group(0) @binding(1) var<storage, read> positions: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> faces: array<u32>;
@group(0) @binding(3) var<storage, read> adjacency: array<u32>;
@group(0) @binding(4) var<storage, read_write> normals: array<vec4<f32>>;

// glam `Vec3::cross`, written out in its order.
fn cross_glam(u: vec3<f32>, w: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(u.y * w.z - w.y * u.z, u.z * w.x - w.z * u.x, u.x * w.y - w.x * u.y);
}

@compute @workgroup_size(WORKGROUP, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let t = id.y;
    let target_params = params[min(t, NORMALS_MAX_TARGETS - 1u)];
    if t >= NORMALS_MAX_TARGETS || id.x >= target_params.vertex_count {
        return;
    }
    let base = target_params.vertex_offset;
    let block = target_params.adjacency_offset;
    let first = adjacency[block + id.x];
    let end = adjacency[block + id.x + 1u];

    if target_params.moved_only != 0u {
        var near_moved = false;
        for (var e = first; e < end; e++) {
            let f = 3u * (target_params.face_offset + adjacency[block + e]);
            for (var c = 0u; c < 3u; c++) {
                near_moved = near_moved || positions[base + faces[f + c]].w > 0.0;
            }
        }
        if !near_moved {
            return;
        }
    }

    // trimesh.rs `recompute_normals`: the sum of `face_area_normal` over the vertex's faces.
    var sum = vec3<f32>(0.0);
    for (var e = first; e < end; e++) {
        let f = 3u * (target_params.face_offset + adjacency[block + e]);
        let a = positions[base + faces[f]].xyz;
        let b = positions[base + faces[f + 1u]].xyz;
        let c = positions[base + faces[f + 2u]].xyz;
        sum += cross_glam(b - a, c - a);
    }
    // glam `normalize_or_zero`: rcp = 1 / sqrt(|sum|²), kept when finite and > 0.
    let rcp = 1.0 / sqrt(sum.x * sum.x + sum.y * sum.y + sum.z * sum.z);
    var n = vec3<f32>(0.0);
    if rcp > 0.0 && rcp <= F32_MAX {
        n = sum * rcp;
    }
    normals[base + id.x] = vec4<f32>(n, 0.0);
}
