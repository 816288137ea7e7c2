// moved: compacts one resident target's moved vertices (those whose `w` flag the last batch's
// `displace` set, i.e. whose position changed) into a short list, so a physics engine can refit
// its collider from a read-back of only what moved. Each moved vertex v appends
// (v, bits of x, bits of y, bits of z) to `list` at a slot taken from the atomic counter
// used[0], which the host zeroes first; the slots come in no fixed order (the host sorts them
// by index). GPU twin of src/cpu/moved.rs (`moved`), which appends in index order.
//
// Bindings (group 0):
//   0 params     MovedParams, uniform: the target's first vertex and vertex count
//   1 positions  array<vec4<f32>>, read: the resident vertex buffer (xyz world units, w = 1.0
//                when the last batch moved the vertex)
//   2 list       array<vec4<u32>>, read_write: the moved vertices, vertex_count slots at least
//   3 used       array<atomic<u32>>, read_write: used[0] = slots used (zero before dispatch)
//
// Dispatch geometry: one invocation per target vertex, x = vertex index within the target;
// dispatch = [ceil(vertex_count / 64), 1, 1]. Invocations past vertex_count return at once.
//
// Host constants matched: MovedParams (16 bytes) in src/cpu/moved.rs; WORKGROUP =
// moved::WORKGROUP in src/gpu/moved.rs.

const WORKGROUP: u32 = 64u;

struct MovedParams {
    // First vertex of the target in positions (vertices).
    vertex_offset: u32,
    // Vertices of the target.
    vertex_count: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> params: MovedParams;
@group(0) @binding(1) var<storage, read> positions: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> list: array<vec4<u32>>;
@group(0) @binding(3) var<storage, read_write> used: array<atomic<u32>>;

@compute @workgroup_size(WORKGROUP, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let v = id.x;
    if v >= params.vertex_count {
        return;
    }
    let p = positions[params.vertex_offset + v];
    if p.w > 0.0 {
        let slot = atomicAdd(&used[0], 1u);
        list[slot] = vec4<u32>(v, bitcast<u32>(p.x), bitcast<u32>(p.y), bitcast<u32>(p.z));
    }
}
