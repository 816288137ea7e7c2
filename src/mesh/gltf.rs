//! glTF 2.0 output: meshes as a binary `.glb` file that Blender, three.js or a game engine opens
//! directly, either one mesh ([`save_glb`]) or a whole frame of a scene, one named node per
//! body ([`save_glb_scene`]).
//!
//! Each body becomes a node (its local→world matrix), a mesh with one indexed triangle primitive
//! (f32 `POSITION` with the `min`/`max` the specification requires, f32 `NORMAL`, u32 indices)
//! and a metallic-roughness material of its colour. Bodies that share one [`TriMesh`] (the same
//! reference) share its vertex and index data in the file.

use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::io::Write;
use std::path::Path;

use glam::{Affine3A, Mat4, Vec3};
use serde::Serialize;

use super::atomic_write::write_atomically;
use super::glb;
use super::{MeshError, TriMesh};

/// Base colour, linear RGB in [0, 1], of the material [`save`](super::save) (`.glb`) and [`GltfNode::new`] use:
/// a neutral grey.
pub const DEFAULT_GLTF_COLOR: [f32; 3] = [0.6, 0.6, 0.6];
/// Roughness of every material written; metallic is 0 (a plastic-like dielectric).
const ROUGHNESS: f32 = 0.6;
/// `bufferView.target` of vertex attribute data.
const ARRAY_BUFFER: u32 = 34962;
/// `bufferView.target` of index data.
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
/// `accessor.componentType` of f32 components.
const FLOAT: u32 = 5126;
/// `accessor.componentType` of u32 components.
const UNSIGNED_INT: u32 = 5125;
/// `primitive.mode` of an indexed triangle list.
const TRIANGLES: u32 = 4;

/// One body of a scene written by [`save_glb_scene`].
#[derive(Debug, Clone, Copy)]
pub struct GltfNode<'a> {
    /// Node, mesh and material name shown by viewers (names need not be unique).
    pub name: &'a str,
    /// The body's mesh in its local frame, world units (metres by convention).
    pub mesh: &'a TriMesh,
    /// Local→world placement of the mesh, stored as the node's `matrix` (left out when it is the
    /// identity). Must be finite; viewers expect a rotation, positive scale and translation.
    pub transform: Affine3A,
    /// Base colour, linear RGB, each channel in [0, 1].
    pub color: [f32; 3],
}

impl<'a> GltfNode<'a> {
    /// A body named `name` at the world origin (identity transform) in [`DEFAULT_GLTF_COLOR`].
    pub fn new(name: &'a str, mesh: &'a TriMesh) -> Self {
        Self { name, mesh, transform: Affine3A::IDENTITY, color: DEFAULT_GLTF_COLOR }
    }
}

/// Writes `mesh` as a binary glTF file: one node (named after the file stem, identity
/// transform) holding one mesh in a grey, non-metallic material (roughness 0.6). Positions are
/// written as f32 unchanged, so [`load`](super::load) reads them back bit for bit.
///
/// The file is written to a temporary sibling and renamed into place, so a failed save leaves
/// no partial file.
///
/// # Errors
/// [`MeshError::Io`] naming `path` if it cannot be written (for example, its directory does not
/// exist); [`MeshError::InvalidParameter`] if the file would exceed the format's 4 GiB limit.
pub fn save_glb(path: impl AsRef<Path>, mesh: &TriMesh) -> Result<(), MeshError> {
    let path = path.as_ref();
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("mesh");
    save_glb_scene(path, &[GltfNode::new(name, mesh)])
}

/// Writes several bodies as one binary glTF scene: one node per body, in order, with its name,
/// transform and colour (see [`GltfNode`]), so a viewer opens the whole frame at once. Written
/// through a temporary sibling file like [`save`](super::save).
///
/// # Errors
/// [`MeshError::InvalidParameter`] (nothing is written) for an empty body list, a non-finite
/// transform, a colour channel outside [0, 1] or a file over 4 GiB; [`MeshError::Io`] naming
/// `path` if it cannot be written.
///
/// # Example
/// ```no_run
/// use dentbend::glam::{Affine3A, Vec3};
/// use dentbend::mesh::{GltfNode, builtin, save_glb_scene};
/// let (block, ball) = (builtin("block").unwrap(), builtin("sphere").unwrap());
/// let above = Affine3A::from_translation(Vec3::new(0.0, 1.5, 0.0));
/// let bodies = [
///     GltfNode::new("block", &block),
///     GltfNode { name: "ball", mesh: &ball, transform: above, color: [0.8, 0.1, 0.1] },
/// ];
/// save_glb_scene("frame_0001.glb", &bodies).unwrap();
/// ```
pub fn save_glb_scene(path: impl AsRef<Path>, bodies: &[GltfNode<'_>]) -> Result<(), MeshError> {
    let bytes = encode(bodies)?;
    write_atomically(path.as_ref(), |out| out.write_all(&bytes))
}

/// The `.glb` bytes of a scene.
fn encode(bodies: &[GltfNode<'_>]) -> Result<Vec<u8>, MeshError> {
    if bodies.is_empty() {
        return Err(MeshError::InvalidParameter("a glTF scene needs at least one body".to_owned()));
    }
    let mut doc = Document::default();
    let mut bin = Vec::new();
    let mut written: HashMap<*const TriMesh, MeshData> = HashMap::new();
    for (index, body) in bodies.iter().enumerate() {
        check_body(body)?;
        let data = match written.entry(std::ptr::from_ref(body.mesh)) {
            Entry::Occupied(entry) => *entry.get(),
            Entry::Vacant(entry) => *entry.insert(doc.push_mesh_data(&mut bin, body.mesh)),
        };
        let [r, g, b] = body.color;
        doc.materials.push(Material {
            name: body.name,
            pbr_metallic_roughness: Pbr {
                base_color_factor: [r, g, b, 1.0],
                metallic_factor: 0.0,
                roughness_factor: ROUGHNESS,
            },
        });
        doc.meshes.push(Mesh {
            name: body.name,
            primitives: [Primitive {
                attributes: data.attributes,
                indices: data.indices,
                material: index,
                mode: TRIANGLES,
            }],
        });
        let matrix = (body.transform != Affine3A::IDENTITY).then(|| Mat4::from(body.transform).to_cols_array());
        doc.nodes.push(Node { name: body.name, mesh: index, matrix });
    }
    doc.scenes[0].nodes = (0..bodies.len()).collect();
    doc.buffers[0].byte_length = bin.len();
    let json = serde_json::to_vec(&doc).map_err(|e| MeshError::InvalidParameter(format!("glTF JSON: {e}")))?;
    glb::pack(&json, &bin).map_err(MeshError::InvalidParameter)
}

/// Rejects what would make an invalid file: a non-finite transform, a colour outside [0, 1].
fn check_body(body: &GltfNode<'_>) -> Result<(), MeshError> {
    let name = body.name;
    if !body.transform.is_finite() {
        return Err(MeshError::InvalidParameter(format!("body '{name}' has a non-finite transform")));
    }
    if !body.color.iter().all(|c| (0.0..=1.0).contains(c)) {
        let color = body.color;
        return Err(MeshError::InvalidParameter(format!("body '{name}' colour {color:?} is not linear RGB in [0, 1]")));
    }
    Ok(())
}

/// Little-endian bytes of 3-vectors.
fn vec3_bytes(values: impl Iterator<Item = Vec3>) -> Vec<u8> {
    values.flat_map(|v| v.to_array()).flat_map(f32::to_le_bytes).collect()
}

impl<'a> Document<'a> {
    /// Appends `mesh`'s positions, normals and indices to `bin` (each a whole number of 4-byte
    /// words, so every view stays aligned) with a view and an accessor each.
    fn push_mesh_data(&mut self, bin: &mut Vec<u8>, mesh: &TriMesh) -> MeshData {
        let (lo, hi) = mesh.bounds();
        let count = mesh.vertex_count();
        let positions = vec3_bytes(mesh.positions().iter().copied());
        // The specification wants unit normals; a vertex on degenerate faces only has none.
        let normals = vec3_bytes(mesh.normals().iter().map(|&n| if n == Vec3::ZERO { Vec3::Z } else { n }));
        let indices: Vec<u8> = mesh.faces().iter().flatten().flat_map(|i| i.to_le_bytes()).collect();
        let float3 = |bounds: Option<(Vec3, Vec3)>| Layout {
            target: ARRAY_BUFFER,
            component_type: FLOAT,
            count,
            kind: "VEC3",
            bounds,
        };
        let attributes = Attributes {
            position: self.push_accessor(bin, &positions, float3(Some((lo, hi)))),
            normal: self.push_accessor(bin, &normals, float3(None)),
        };
        MeshData {
            attributes,
            indices: self.push_accessor(
                bin,
                &indices,
                Layout {
                    target: ELEMENT_ARRAY_BUFFER,
                    component_type: UNSIGNED_INT,
                    count: 3 * mesh.face_count(),
                    kind: "SCALAR",
                    bounds: None,
                },
            ),
        }
    }

    /// Appends `data` to `bin` as a new buffer view read by a new accessor; returns the
    /// accessor's index.
    fn push_accessor(&mut self, bin: &mut Vec<u8>, data: &[u8], layout: Layout) -> usize {
        self.buffer_views.push(View {
            buffer: 0,
            byte_offset: bin.len(),
            byte_length: data.len(),
            target: layout.target,
        });
        bin.extend_from_slice(data);
        self.accessors.push(Accessor {
            buffer_view: self.buffer_views.len() - 1,
            component_type: layout.component_type,
            count: layout.count,
            kind: layout.kind,
            min: layout.bounds.map(|(lo, _)| lo.to_array()),
            max: layout.bounds.map(|(_, hi)| hi.to_array()),
        });
        self.accessors.len() - 1
    }
}

/// How [`Document::push_accessor`] describes its data.
struct Layout {
    target: u32,
    component_type: u32,
    count: usize,
    kind: &'static str,
    bounds: Option<(Vec3, Vec3)>,
}

// ---- the JSON document (glTF 2.0 schema, only the parts written) --------------------------------

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Document<'a> {
    asset: Asset,
    scene: usize,
    scenes: [Scene; 1],
    nodes: Vec<Node<'a>>,
    meshes: Vec<Mesh<'a>>,
    materials: Vec<Material<'a>>,
    buffers: [Buffer; 1],
    buffer_views: Vec<View>,
    accessors: Vec<Accessor>,
}

impl Default for Document<'_> {
    fn default() -> Self {
        Self {
            asset: Asset { version: "2.0", generator: concat!("dentbend ", env!("CARGO_PKG_VERSION")) },
            scene: 0,
            scenes: [Scene { nodes: Vec::new() }],
            nodes: Vec::new(),
            meshes: Vec::new(),
            materials: Vec::new(),
            buffers: [Buffer { byte_length: 0 }],
            buffer_views: Vec::new(),
            accessors: Vec::new(),
        }
    }
}

#[derive(Serialize)]
struct Asset {
    version: &'static str,
    generator: &'static str,
}

#[derive(Serialize)]
struct Scene {
    nodes: Vec<usize>,
}

#[derive(Serialize)]
struct Node<'a> {
    name: &'a str,
    mesh: usize,
    /// Column-major 4×4 local→world matrix.
    #[serde(skip_serializing_if = "Option::is_none")]
    matrix: Option<[f32; 16]>,
}

#[derive(Serialize)]
struct Mesh<'a> {
    name: &'a str,
    primitives: [Primitive; 1],
}

#[derive(Serialize)]
struct Primitive {
    attributes: Attributes,
    indices: usize,
    material: usize,
    mode: u32,
}

/// Accessor indices of one mesh's data in the file.
#[derive(Clone, Copy)]
struct MeshData {
    attributes: Attributes,
    indices: usize,
}

/// A primitive's `attributes`: accessor indices by semantic.
#[derive(Serialize, Clone, Copy)]
struct Attributes {
    #[serde(rename = "POSITION")]
    position: usize,
    #[serde(rename = "NORMAL")]
    normal: usize,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Material<'a> {
    name: &'a str,
    pbr_metallic_roughness: Pbr,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Pbr {
    base_color_factor: [f32; 4],
    metallic_factor: f32,
    roughness_factor: f32,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Buffer {
    byte_length: usize,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct View {
    buffer: usize,
    byte_offset: usize,
    byte_length: usize,
    target: u32,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Accessor {
    buffer_view: usize,
    component_type: u32,
    count: usize,
    #[serde(rename = "type")]
    kind: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    min: Option<[f32; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    max: Option<[f32; 3]>,
}
