// skin: linear blend skinning of a parent mesh (paper §4, run every frame on the mesh of an
// articulated body). Each vertex blends the skinning matrices S = current pose × (rest pose)⁻¹
// of its four bones, M = Σ wᵢ·Sᵢ + (1 − Σ wᵢ)·I (weight missing from one stays on the rest pose;
// identity bones give the rest mesh back exactly), then writes
//   position = M·(rest position, 1)
//   normal   = normalize_or_zero(cof(A)·rest normal),  A = M's 3×3 linear part,
// where cof(A) = det(A)·A⁻ᵀ, whose rows are the cross products of A's rows: the inverse-transpose
// up to a factor the normalization removes (a mirroring A flips the normal along with the
// skinned triangles' winding), and still defined where A is singular. GPU twin of
// src/cpu/skin.rs (`skin`, `skin_vertex`); the statements below follow that function.
// Weights are taken as given (the host validates them); an influence naming a bone
// >= params.bone_count is skipped, as if its weight were 0, so nothing is read out of bounds.
//
// Bindings (group 0):
//   0 params      uniform SkinParams: vertex and bone counts
//   1 bones       uniform array<SkinBone, SKIN_MAX_BONES>: the skinning matrices, three rows
//                 [a_r0, a_r1, a_r2, t_r] each (translation in world units), the first
//                 params.bone_count used (a uniform, because the four storage bindings below are
//                 the downlevel limit; the host rewrites only the used bones each frame)
//   2 rest        array<SkinRest>, read: rest position (xyz, world units, w = 0) and rest normal
//                 (xyz, w = 0) of every vertex, interleaved
//   3 influences  array<SkinInfluence>, read: four bone indices and four weights per vertex
//   4 positions   array<vec4<f32>>, read_write: skinned position per vertex, xyz world units,
//                 w = 0 (the layout of the displace and normals kernels' position buffers)
//   5 normals     array<vec4<f32>>, read_write: skinned unit normal per vertex (zero where the
//                 transformed normal vanishes), w = 0
//
// Dispatch geometry: one invocation per vertex, x = vertex index; dispatch =
// [ceil(vertex_count / WORKGROUP), 1, 1] with WORKGROUP = 64. Invocations past
// params.vertex_count return at once.
//
// Host constants matched: SkinParams = cpu::SkinParams, SkinBone = cpu::SkinBone and
// SkinInfluence = cpu::SkinInfluence (src/cpu/skin_layout.rs, 16, 48 and 32 bytes);
// SkinRest = skin::SkinRest (src/gpu/skin.rs, 32 bytes); SKIN_MAX_BONES = skin::MAX_BONES and
// WORKGROUP = skin::WORKGROUP (src/gpu/skin.rs).

const WORKGROUP: u32 = 64u;
const SKIN_MAX_BONES: u32 = 256u;
// Largest finite f32: a squared length in (0, F32_MAX] has a finite, non-zero 1/sqrt.
const F32_MAX: f32 = 3.40282347e38;

struct SkinParams {
    vertex_count: u32,
    bone_count: u32,
    _pad0: u32,
    _pad1: u32,
}

struct SkinBone {
    rows: array<vec4<f32>, 3>,
}

struct SkinRest {
    position: vec4<f32>,
    normal: vec4<f32>,
}

struct SkinInfluence {
    bones: vec4<u32>,
    weights: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: SkinParams;
@group(0) @binding(1) var<uniform> bones: array<SkinBone, SKIN_MAX_BONES>;
@group(0) @binding(2) var<storage, read> rest: array<SkinRest>;
@group(0) @binding(3) var<storage, read> influences: array<SkinInfluence>;
@group(0) @binding(4) var<storage, read_write> positions: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> normals: array<vec4<f32>>;

@compute @workgroup_size(WORKGROUP, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let v = id.x;
    if v >= params.vertex_count {
        return;
    }
    let influence = influences[v];

    // Blend the rows of the bones' matrices, skipping bones past the bone count.
    var row0 = vec4<f32>(0.0);
    var row1 = vec4<f32>(0.0);
    var row2 = vec4<f32>(0.0);
    var total = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let b = influence.bones[k];
        if b >= params.bone_count {
            continue;
        }
        let w = influence.weights[k];
        // b < bone_count <= SKIN_MAX_BONES; the min only makes the bound evident.
        let bone = min(b, SKIN_MAX_BONES - 1u);
        row0 += w * bones[bone].rows[0];
        row1 += w * bones[bone].rows[1];
        row2 += w * bones[bone].rows[2];
        total += w;
    }
    // The weight missing from one stays on the rest pose: M += (1 − Σ w)·I.
    let missing = 1.0 - total;
    row0.x += missing;
    row1.y += missing;
    row2.z += missing;

    let vertex = rest[v];
    let p1 = vec4<f32>(vertex.position.xyz, 1.0);
    let position = vec3<f32>(dot(row0, p1), dot(row1, p1), dot(row2, p1));
    // Rows of cof(A) = det(A)·A⁻ᵀ: the cross products of A's rows.
    let a0 = row0.xyz;
    let a1 = row1.xyz;
    let a2 = row2.xyz;
    let n = vertex.normal.xyz;
    let m = vec3<f32>(dot(cross(a1, a2), n), dot(cross(a2, a0), n), dot(cross(a0, a1), n));
    // glam `normalize_or_zero`: zero unless 1/|m| is finite and non-zero.
    let length2 = dot(m, m);
    var normal = vec3<f32>(0.0);
    if length2 > 0.0 && length2 <= F32_MAX {
        normal = m * (1.0 / sqrt(length2));
    }
    positions[v] = vec4<f32>(position, 0.0);
    normals[v] = vec4<f32>(normal, 0.0);
}
