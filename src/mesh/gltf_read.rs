//! glTF 2.0 input (`.gltf` and `.glb`): every triangle primitive of every mesh node in the
//! default scene, placed by its node's world transform and merged into one [`TriMesh`].
//!
//! The JSON schema comes from the `gltf` crate; the node graph, primitives and buffer data are
//! walked here with checked indices (see [`super::gltf_access`]) so that no malformed file can
//! make the reader panic. Skins, morph targets, materials and textures are ignored: a skinned or
//! morphed mesh is read in its bind pose.

use std::path::Path;

use glam::{Affine3A, Mat4, Quat, Vec3};
use gltf::json::Root;
use gltf::json::mesh::{Mode, Semantic};
use gltf::json::validation::Checked;

use super::gltf_access::Buffers;
use super::obj::MEMORY;
use super::{MeshError, TriMesh, glb};

/// Required extensions that change how geometry is stored, which this reader cannot decode.
/// Other required extensions (materials, textures, lights) do not affect the mesh and are ignored.
const GEOMETRY_EXTENSIONS: &[&str] =
    &["KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_mesh_quantization"];

/// Reads a `.gltf` or `.glb` file into one mesh: the triangle primitives (`TRIANGLES`,
/// `TRIANGLE_STRIP` and `TRIANGLE_FAN`, indexed or not) of every mesh node in the default scene
/// (the first scene if none is marked, every root node if there are no scenes), with positions
/// transformed to world units by the node's world matrix. A node whose world matrix mirrors
/// (negative determinant) has its triangles re-wound so they stay counter-clockwise seen from
/// outside. Points and lines primitives, and primitives without `POSITION`, are skipped with a
/// warning. Buffers may be the `.glb` BIN chunk, base64 `data:` URIs or files relative to the
/// `.gltf` file.
///
/// # Errors
/// [`MeshError::Io`] if the file cannot be read; [`MeshError::Parse`] naming the file for a
/// malformed container or JSON, a reference to something that does not exist, data that runs
/// past its buffer, an unsupported accessor layout or required compression extension, a node
/// graph that is not a tree, or no triangles at all; [`MeshError::IndexOutOfRange`] for a
/// triangle index past its primitive's vertices and [`MeshError::NonFinite`] for a NaN or
/// infinite position (after transformation).
pub fn load_gltf(path: impl AsRef<Path>) -> Result<TriMesh, MeshError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io { path: path.to_path_buf(), source })?;
    parse_gltf_named(&bytes, path, Some(path.parent().unwrap_or(Path::new(""))))
}

/// Parses the bytes of a `.gltf` or `.glb` file held in memory, as [`load`](super::load) reads a `.gltf` or `.glb` file,
/// except that nothing is read from disk: buffers must be the `.glb` BIN chunk or base64 `data:`
/// URIs, and a buffer naming a file is refused.
///
/// # Errors
/// As [`load`](super::load), with [`MeshError::Parse`] for a buffer URI that names a file.
pub fn parse_gltf(bytes: &[u8]) -> Result<TriMesh, MeshError> {
    parse_gltf_named(bytes, Path::new(MEMORY), None)
}

/// [`parse_gltf`] with the path to name in errors and the folder that relative buffer URIs are
/// resolved against (`None`: they are refused).
fn parse_gltf_named(bytes: &[u8], path: &Path, folder: Option<&Path>) -> Result<TriMesh, MeshError> {
    let fail = |message: String| MeshError::Parse { path: path.to_path_buf(), format: "glTF", message };
    let (root, bin) = document(bytes).map_err(fail)?;
    let root = &root;
    let mut reader =
        Reader { root, buffers: Buffers::new(root, folder, bin), positions: Vec::new(), faces: Vec::new() };
    for (node, world) in scene_nodes(root).map_err(fail)? {
        reader.add_node(node, world).map_err(|e| e.into_mesh_error(&fail))?;
    }
    if reader.faces.is_empty() {
        return Err(fail("the default scene has no triangles".to_owned()));
    }
    TriMesh::new(reader.positions, reader.faces)
}

/// The JSON document of a `.gltf` or `.glb` file and its BIN chunk, refused if it needs a
/// geometry extension this reader cannot decode.
pub(crate) fn document(bytes: &[u8]) -> Result<(Root, Option<&[u8]>), String> {
    if bytes.is_empty() {
        return Err("the file is empty".to_owned());
    }
    let (json, bin) = if bytes.starts_with(b"glTF") {
        let chunks = glb::split(bytes)?;
        (chunks.json, chunks.bin)
    } else {
        (bytes, None)
    };
    let root: Root = gltf::json::deserialize::from_slice(json).map_err(|e| format!("invalid glTF JSON: {e}"))?;
    if let Some(ext) = root.extensions_required.iter().find(|e| GEOMETRY_EXTENSIONS.contains(&e.as_str())) {
        return Err(format!("the file requires extension {ext}, which dentbend cannot decode"));
    }
    Ok((root, bin))
}

/// Every node of the scene to load with its world matrix, parents before children, in file
/// order.
pub(crate) fn scene_nodes(root: &Root) -> Result<Vec<(usize, Mat4)>, String> {
    let roots: Vec<usize> = match (root.scene, root.scenes.first()) {
        (Some(scene), _) => {
            let count = root.scenes.len();
            let scene = root
                .scenes
                .get(scene.value())
                .ok_or(format!("default scene {scene} does not exist ({count} scenes)"))?;
            scene.nodes.iter().map(|n| n.value()).collect()
        }
        (None, Some(first)) => first.nodes.iter().map(|n| n.value()).collect(),
        (None, None) => {
            let mut is_child = vec![false; root.nodes.len()];
            for child in root.nodes.iter().flat_map(|n| n.children.iter().flatten()) {
                if let Some(flag) = is_child.get_mut(child.value()) {
                    *flag = true;
                }
            }
            (0..root.nodes.len()).filter(|&n| !is_child[n]).collect()
        }
    };
    let mut visited = vec![false; root.nodes.len()];
    let mut out = Vec::new();
    let mut stack: Vec<(usize, Mat4)> = roots.iter().rev().map(|&n| (n, Mat4::IDENTITY)).collect();
    while let Some((index, parent)) = stack.pop() {
        let count = root.nodes.len();
        let node =
            root.nodes.get(index).ok_or_else(|| format!("node {index} does not exist (the file has {count})"))?;
        if std::mem::replace(&mut visited[index], true) {
            return Err(format!("node {index} is reached twice: the node hierarchy is not a tree"));
        }
        let local = match node.matrix {
            Some(m) => Mat4::from_cols_array(&m),
            None => Mat4::from_scale_rotation_translation(
                Vec3::from_array(node.scale.unwrap_or([1.0; 3])),
                node.rotation.map_or(Quat::IDENTITY, |r| Quat::from_array(r.0)),
                Vec3::from_array(node.translation.unwrap_or([0.0; 3])),
            ),
        };
        let world = parent * local;
        out.push((index, world));
        stack.extend(node.children.iter().flatten().rev().map(|c| (c.value(), world)));
    }
    Ok(out)
}

/// A failure while reading one node: a message for [`MeshError::Parse`] or a mesh error as is.
enum NodeError {
    Message(String),
    Mesh(MeshError),
}

impl NodeError {
    fn into_mesh_error(self, fail: &impl Fn(String) -> MeshError) -> MeshError {
        match self {
            Self::Message(message) => fail(message),
            Self::Mesh(error) => error,
        }
    }
}

impl From<String> for NodeError {
    fn from(message: String) -> Self {
        Self::Message(message)
    }
}

/// The merged mesh so far.
struct Reader<'a> {
    root: &'a Root,
    buffers: Buffers<'a>,
    positions: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
}

impl Reader<'_> {
    /// Appends the triangle primitives of node `index`'s mesh, if it has one, placed by `world`.
    fn add_node(&mut self, index: usize, world: Mat4) -> Result<(), NodeError> {
        let root = self.root;
        let Some(mesh_index) = root.nodes.get(index).and_then(|n| n.mesh).map(|m| m.value()) else { return Ok(()) };
        let count = root.meshes.len();
        let mesh = root.meshes.get(mesh_index).ok_or_else(|| {
            format!("node {index} refers to mesh {mesh_index}, which does not exist ({count} meshes)")
        })?;
        let transform = (world != Mat4::IDENTITY).then(|| Affine3A::from_mat4(world));
        let mirrored = world.determinant() < 0.0;
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let what = format!("mesh {mesh_index} primitive {p}");
            let mode = match primitive.mode {
                Checked::Valid(mode @ (Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan)) => mode,
                other => {
                    log::warn!("glTF {what}: mode {other:?} is not triangles; skipped");
                    continue;
                }
            };
            let Some(position_accessor) = primitive.attributes.get(&Checked::Valid(Semantic::Positions)) else {
                log::warn!("glTF {what} has no POSITION attribute; skipped");
                continue;
            };
            let positions = self.buffers.positions(position_accessor.value()).map_err(|e| format!("{what}: {e}"))?;
            let vertex_count = positions.len();
            let (Ok(base), Ok(_)) =
                (u32::try_from(self.positions.len()), u32::try_from(self.positions.len() + vertex_count))
            else {
                return Err(format!("{what}: the merged mesh would have more than {} vertices", u32::MAX).into());
            };
            let indices = match primitive.indices {
                Some(accessor) => self.buffers.indices(accessor.value()).map_err(|e| format!("{what}: {e}"))?,
                None => (0..vertex_count as u32).collect(),
            };
            for mut triangle in triangles(mode, &indices) {
                if let Some(&bad) = triangle.iter().find(|&&i| i as usize >= vertex_count) {
                    let face = self.faces.len();
                    return Err(NodeError::Mesh(MeshError::IndexOutOfRange { face, index: bad, vertex_count }));
                }
                if mirrored {
                    triangle.swap(1, 2);
                }
                self.faces.push(triangle.map(|i| base + i));
            }
            match transform {
                Some(t) => self.positions.extend(positions.iter().map(|&q| t.transform_point3(q))),
                None => self.positions.extend(positions),
            }
        }
        Ok(())
    }
}

/// The triangles of a primitive's index list, counter-clockwise as the glTF specification
/// orders strips and fans; a triangle list's incomplete last triangle is dropped.
pub(crate) fn triangles(mode: Mode, indices: &[u32]) -> Vec<[u32; 3]> {
    let n = indices.len();
    match mode {
        Mode::TriangleStrip => (2..n)
            .map(|i| match i % 2 {
                0 => [indices[i - 2], indices[i - 1], indices[i]],
                _ => [indices[i - 1], indices[i - 2], indices[i]],
            })
            .collect(),
        Mode::TriangleFan => (2..n).map(|i| [indices[i - 1], indices[i], indices[0]]).collect(),
        _ => {
            if !n.is_multiple_of(3) {
                log::warn!("glTF triangle list has {n} indices, not a multiple of 3; the last {} ignored", n % 3);
            }
            indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect()
        }
    }
}
