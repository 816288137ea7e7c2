// interleave: copies one resident target's vertex positions and unit normals into a caller's
// interleaved vertex buffer (an engine's layout: position and normal at fixed byte offsets within
// each stride-sized vertex), so a renderer can draw the dented mesh without a read-back. For
// target vertex v it writes the three f32 of positions[vertex_offset + v].xyz at byte
// dst_offset + v·stride + position_offset and, unless normal_offset is NO_NORMAL, the three f32
// of normals[vertex_offset + v].xyz at byte dst_offset + v·stride + normal_offset (all byte
// quantities are passed in 4-byte words). The bits are copied unchanged, and no other byte of the
// destination is written. GPU twin of src/cpu/interleave.rs (`interleave`).
//
// Bindings (group 0):
//   0 params     InterleaveParams, uniform: the target's vertex range and the layout, in words
//   1 positions  array<vec4<f32>>, read: the resident vertex buffer (xyz world units, w moved)
//   2 normals    array<vec4<f32>>, read: the resident unit normals (xyz, w = 0)
//   3 dst        array<u32>, read_write: the caller's buffer, bound from a storage-offset-aligned
//                byte at or before the first vertex (dst_word counts from there)
//
// Dispatch geometry: one invocation per target vertex, x = vertex index within the target;
// dispatch = [ceil(vertex_count / 64), 1, 1]. Invocations past vertex_count return at once.
//
// Host constants matched: InterleaveParams (32 bytes) and NO_NORMAL in src/cpu/interleave.rs;
// WORKGROUP = interleave::WORKGROUP in src/gpu/interleave.rs.

const WORKGROUP: u32 = 64u;
const NO_NORMAL: u32 = 0xffffffffu;

struct InterleaveParams {
    // First vertex of the target in positions and normals (vertices).
    vertex_offset: u32,
    // Vertices to copy.
    vertex_count: u32,
    // Word of dst where vertex 0 starts.
    dst_word: u32,
    // Words from one vertex to the next in dst.
    stride_words: u32,
    // Word of the position within a vertex.
    position_word: u32,
    // Word of the normal within a vertex, or NO_NORMAL.
    normal_word: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> params: InterleaveParams;
@group(0) @binding(1) var<storage, read> positions: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> normals: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> dst: array<u32>;

fn write_vec3(word: u32, value: vec3<f32>) {
    dst[word] = bitcast<u32>(value.x);
    dst[word + 1u] = bitcast<u32>(value.y);
    dst[word + 2u] = bitcast<u32>(value.z);
}

@compute @workgroup_size(WORKGROUP, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let v = id.x;
    if v >= params.vertex_count {
        return;
    }
    let source = params.vertex_offset + v;
    let base = params.dst_word + v * params.stride_words;
    write_vec3(base + params.position_word, positions[source].xyz);
    if params.normal_word != NO_NORMAL {
        write_vec3(base + params.normal_word, normals[source].xyz);
    }
}
