// Offscreen pictures of triangle meshes (src/render/gpu.rs): a soft vertical background gradient,
// then every mesh lit so that shallow dents read as shading: per-vertex normals interpolated, a
// key directional light, a dim fill light, a hemispherical ambient and a modest Blinn–Phong
// highlight, all two-sided (a normal facing away from the eye is flipped, since dented thin
// meshes show their inside faces). Colours are linear RGB; the target is Rgba8UnormSrgb, so the
// hardware encodes sRGB on store. Depth is Depth32Float (less, cleared to 1); 1× or 4× MSAA.
//
// Not a compute kernel: no dispatch. Drawn as one render pass per picture tile:
//   vs_background / fs_background: one full-screen triangle, 3 vertices, no vertex buffer.
//   vs_mesh / fs_mesh: indexed triangle list (u32 indices), one draw per mesh.
//
// Bindings (group 0), host structs in src/render/gpu_frame.rs (keep in sync):
//   @binding(0) var<uniform> frame: Frame       camera, lights and background of the picture
//   @binding(1) var<uniform> material: Material dynamic offset, one 256-byte-aligned slot per mesh
//
// Vertex layout (buffer 0, 24 bytes per vertex, step mode vertex), host `GpuVertex`:
//   @location(0) position: vec3<f32>  offset 0,  world units
//   @location(1) normal:   vec3<f32>  offset 12, world space, unit length (zero is tolerated)

// Keep in sync with `FrameUniform` in src/render/gpu_frame.rs.
struct Frame {
    // World → clip for this tile (the picture's view-projection with the tile's crop applied).
    view_proj: mat4x4<f32>,
    // xyz: camera position, world units; w unused.
    eye: vec4<f32>,
    // xyz: unit vector from the surface towards the key light, world space; w: its intensity.
    key: vec4<f32>,
    // xyz: unit vector towards the fill light, world space; w: its intensity.
    fill: vec4<f32>,
    // xyz: the picture's up direction (hemisphere axis), world space; w: Blinn–Phong exponent.
    up: vec4<f32>,
    // rgb: ambient light from the sky side of the hemisphere (linear); a: specular strength.
    sky: vec4<f32>,
    // rgb: ambient light from the ground side (linear); a unused.
    ground: vec4<f32>,
    // rgb: background at the top of the picture (linear); a unused.
    background_top: vec4<f32>,
    // rgb: background at the bottom of the picture (linear); a unused.
    background_bottom: vec4<f32>,
    // x, y: this tile's top-left corner in the picture, pixels; z: picture height, pixels.
    tile: vec4<f32>,
}

// Keep in sync with `MaterialUniform` in src/render/gpu_frame.rs.
struct Material {
    // rgb: base colour, linear in [0, 1]; a unused.
    colour: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> material: Material;

struct BackgroundOut {
    @builtin(position) clip: vec4<f32>,
}

// A triangle covering the whole viewport: clip (-1,-1), (3,-1), (-1,3).
@vertex
fn vs_background(@builtin(vertex_index) index: u32) -> BackgroundOut {
    let x = f32(i32(index & 1u) * 4 - 1);
    let y = f32(i32(index >> 1u) * 4 - 1);
    return BackgroundOut(vec4<f32>(x, y, 1.0, 1.0));
}

@fragment
fn fs_background(in: BackgroundOut) -> @location(0) vec4<f32> {
    // Framebuffer y grows downwards; `tile.y` places the tile in the whole picture.
    let t = clamp((in.clip.y + frame.tile.y) / max(frame.tile.z, 1.0), 0.0, 1.0);
    let colour = mix(frame.background_top.rgb, frame.background_bottom.rgb, t);
    return vec4<f32>(colour, 1.0);
}

struct MeshIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

struct MeshOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

@vertex
fn vs_mesh(in: MeshIn) -> MeshOut {
    return MeshOut(frame.view_proj * vec4<f32>(in.position, 1.0), in.position, in.normal);
}

// Key + fill (Lambert), hemispherical ambient and a Blinn–Phong highlight from the key light,
// two-sided. `normal` need not be unit; a zero normal is lit by the ambient only.
fn shade(normal: vec3<f32>, world: vec3<f32>, base: vec3<f32>) -> vec3<f32> {
    let to_eye = normalize(frame.eye.xyz - world);
    let length_n = length(normal);
    var n = select(vec3<f32>(0.0), normal / length_n, length_n > 1e-12);
    if dot(n, to_eye) < 0.0 {
        n = -n;
    }
    let key_cos = max(dot(n, frame.key.xyz), 0.0);
    let diffuse = frame.key.w * key_cos + frame.fill.w * max(dot(n, frame.fill.xyz), 0.0);
    let sky_weight = 0.5 + 0.5 * dot(n, frame.up.xyz);
    let ambient = mix(frame.ground.rgb, frame.sky.rgb, sky_weight);
    let half_vector = normalize(frame.key.xyz + to_eye);
    let highlight = pow(max(dot(n, half_vector), 0.0), frame.up.w) * select(0.0, 1.0, key_cos > 0.0);
    return base * (ambient + vec3<f32>(diffuse)) + vec3<f32>(frame.sky.a * highlight);
}

@fragment
fn fs_mesh(in: MeshOut) -> @location(0) vec4<f32> {
    let base = clamp(material.colour.rgb, vec3<f32>(0.0), vec3<f32>(1.0));
    return vec4<f32>(shade(in.normal, in.world, base), 1.0);
}
