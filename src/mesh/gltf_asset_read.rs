//! glTF 2.0 input of an [`Asset`]: the triangle primitives of the default scene, as
//! [`load_gltf`](super::load_gltf) reads them, with their vertex attributes (`TEXCOORD_n`,
//! `NORMAL`, `TANGENT`, `COLOR_n`, `JOINTS_0`/`WEIGHTS_0`) and one face group per mesh name and
//! material.

use std::collections::HashMap;
use std::path::Path;

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use gltf::json::Root;
use gltf::json::accessor::Type;
use gltf::json::mesh::Mode;
use gltf::json::validation::Checked;

use super::asset::{FaceGroup, Skin, VertexAttributes};
use super::gltf_access::Buffers;
use super::gltf_read::{document, scene_nodes, triangles};
use super::obj::MEMORY;
use super::{Asset, MeshError, TriMesh};

/// Most UV sets and colour sets read (a larger `TEXCOORD_n`/`COLOR_n` is refused).
pub const MAX_ATTRIBUTE_SETS: u32 = 8;

/// Reads a `.gltf` or `.glb` file as an asset (see [`parse_gltf_asset`]).
///
/// # Errors
/// [`MeshError::Io`] if the file cannot be read, otherwise as [`parse_gltf_asset`].
pub fn load_gltf_asset(path: impl AsRef<Path>) -> Result<Asset, MeshError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io { path: path.to_path_buf(), source })?;
    parse_gltf_asset_named(&bytes, path, Some(path.parent().unwrap_or(Path::new(""))))
}

/// Parses glTF bytes as an asset: the geometry as [`parse_gltf`](super::parse_gltf) reads it,
/// with every primitive's attributes — UV sets (f32 or normalized u8/u16), normals and tangents
/// (turned by the node's world matrix; a mirroring matrix flips tangent w), colour sets (RGB
/// read with alpha 1), joints and weights — and its mesh name and material as its face group.
/// Primitives that share their attribute accessors and world matrix share their vertices. A
/// vertex whose primitive lacks an attribute another has gets UV (0, 0), its smooth normal,
/// a tangent perpendicular to it (w = 1), white, or joint 0 with weight 1.
///
/// # Errors
/// As [`parse_gltf`](super::parse_gltf), and [`MeshError::Parse`] for an attribute accessor
/// whose count differs from its primitive's `POSITION` count or of an unsupported layout, or a
/// set index past [`MAX_ATTRIBUTE_SETS`]; [`MeshError::AttributeValue`] for a NaN or infinite
/// attribute.
pub fn parse_gltf_asset(bytes: &[u8]) -> Result<Asset, MeshError> {
    parse_gltf_asset_named(bytes, Path::new(MEMORY), None)
}

fn parse_gltf_asset_named(bytes: &[u8], path: &Path, folder: Option<&Path>) -> Result<Asset, MeshError> {
    let fail = |message: String| MeshError::Parse { path: path.to_path_buf(), format: "glTF", message };
    let (root, bin) = document(bytes).map_err(fail)?;
    let mut reader = Reader { root: &root, buffers: Buffers::new(&root, folder, bin), out: Columns::default() };
    for (node, world) in scene_nodes(&root).map_err(fail)? {
        reader.add_node(node, world).map_err(|e| match e {
            Failure::Message(m) => fail(m),
            Failure::Mesh(e) => e,
        })?;
    }
    if reader.out.faces.is_empty() {
        return Err(fail("the default scene has no triangles".to_owned()));
    }
    reader.out.into_asset()
}

/// A failure while reading a node.
enum Failure {
    Message(String),
    Mesh(MeshError),
}

impl From<String> for Failure {
    fn from(message: String) -> Self {
        Self::Message(message)
    }
}

/// Everything read so far, one entry per vertex (or face) in every column.
#[derive(Default)]
struct Columns {
    positions: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
    face_groups: Vec<u32>,
    groups: Vec<FaceGroup>,
    uvs: Vec<Vec<Vec2>>,
    normals: Vec<Option<Vec3>>,
    tangents: Vec<Option<Vec4>>,
    colors: Vec<Vec<Vec4>>,
    joints: Vec<[u16; 4]>,
    weights: Vec<Vec4>,
    any_normal: bool,
    any_tangent: bool,
    any_skin: bool,
    /// Vertices already read, by attribute accessors and world matrix: their first index.
    shared: HashMap<SharedKey, u32>,
}

/// A primitive's attribute accessors by semantic (sorted) and its world matrix's bits.
type SharedKey = (Vec<(String, usize)>, [u32; 16]);

struct Reader<'a> {
    root: &'a Root,
    buffers: Buffers<'a>,
    out: Columns,
}

impl Reader<'_> {
    /// Appends the triangle primitives of node `index`'s mesh, if it has one, placed by `world`.
    fn add_node(&mut self, index: usize, world: Mat4) -> Result<(), Failure> {
        let root = self.root;
        let Some(mesh_index) = root.nodes.get(index).and_then(|n| n.mesh).map(|m| m.value()) else { return Ok(()) };
        let count = root.meshes.len();
        let mesh = root.meshes.get(mesh_index).ok_or_else(|| {
            format!("node {index} refers to mesh {mesh_index}, which does not exist ({count} meshes)")
        })?;
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let what = format!("mesh {mesh_index} primitive {p}");
            let mode = match primitive.mode {
                Checked::Valid(mode @ (Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan)) => mode,
                _ => continue,
            };
            let mut attributes: Vec<(String, usize)> = Vec::new();
            for (semantic, accessor) in &primitive.attributes {
                if let Checked::Valid(semantic) = semantic {
                    attributes.push((semantic.to_string(), accessor.value()));
                }
            }
            attributes.sort();
            let Some(&(_, position)) = attributes.iter().find(|(s, _)| s == "POSITION") else { continue };
            let key = (attributes, world.to_cols_array().map(f32::to_bits));
            let base = match self.out.shared.get(&key) {
                Some(&base) => base,
                None => {
                    let base = self.add_vertices(&key.0, position, world).map_err(|e| match e {
                        Failure::Message(m) => Failure::Message(format!("{what}: {m}")),
                        other => other,
                    })?;
                    self.out.shared.insert(key, base);
                    base
                }
            };
            let vertex_count = self.buffers.count(position).unwrap_or(0) as usize;
            let indices = match primitive.indices {
                Some(accessor) => self.buffers.indices(accessor.value()).map_err(|e| format!("{what}: {e}"))?,
                None => (0..vertex_count as u32).collect(),
            };
            let group = self.group(mesh.name.clone(), primitive.material.map(|m| m.value()));
            for mut triangle in triangles(mode, &indices) {
                if let Some(&bad) = triangle.iter().find(|&&i| i as usize >= vertex_count) {
                    let face = self.out.faces.len();
                    return Err(Failure::Mesh(MeshError::IndexOutOfRange { face, index: bad, vertex_count }));
                }
                if world.determinant() < 0.0 {
                    triangle.swap(1, 2);
                }
                self.out.faces.push(triangle.map(|i| base + i));
                self.out.face_groups.push(group);
            }
        }
        Ok(())
    }

    /// The index of the group of `object` and material `material`, added on first use.
    fn group(&mut self, object: Option<String>, material: Option<usize>) -> u32 {
        let name = material.and_then(|m| self.root.materials.get(m)).and_then(|m| m.name.clone());
        let group =
            FaceGroup { object, material: name, material_index: material.map(|m| m as u32), ..FaceGroup::default() };
        let groups = &mut self.out.groups;
        match groups.iter().position(|g| *g == group) {
            Some(g) => g as u32,
            None => {
                groups.push(group);
                (groups.len() - 1) as u32
            }
        }
    }

    /// Appends one primitive's vertices and attributes; returns the first one's index.
    fn add_vertices(&mut self, attributes: &[(String, usize)], position: usize, world: Mat4) -> Result<u32, Failure> {
        let positions = self.buffers.positions(position)?;
        let n = positions.len();
        let out = &mut self.out;
        let base = u32::try_from(out.positions.len() + n)
            .map(|_| out.positions.len() as u32)
            .map_err(|_| format!("the merged mesh would have more than {} vertices", u32::MAX))?;
        let identity = world == Mat4::IDENTITY;
        let linear = Mat3::from_mat4(world);
        let normal_matrix = linear.inverse().transpose();
        let handedness = if linear.determinant() < 0.0 { -1.0 } else { 1.0 };
        match world == Mat4::IDENTITY {
            true => out.positions.extend(positions),
            false => out.positions.extend(positions.iter().map(|&p| world.transform_point3(p))),
        }
        let (mut normals, mut tangents) = (vec![None; n], vec![None; n]);
        let (mut uvs, mut colors) = (HashMap::new(), HashMap::new());
        let mut skin: (Option<Vec<[u16; 4]>>, Option<Vec<Vec4>>) = (None, None);
        for (semantic, accessor) in attributes {
            let accessor = *accessor;
            let declared = self.buffers.count(accessor).unwrap_or(0);
            if semantic != "POSITION" && declared != n as u64 {
                return Err(format!("{semantic} has {declared} elements, POSITION has {n}").into());
            }
            let set = |s: &str| -> Result<u32, String> {
                let k: u32 = s.parse().map_err(|_| format!("attribute {semantic} is not understood"))?;
                match k < MAX_ATTRIBUTE_SETS {
                    true => Ok(k),
                    false => Err(format!("attribute {semantic}: at most {MAX_ATTRIBUTE_SETS} sets are read")),
                }
            };
            let buffers = &mut self.buffers;
            match semantic.as_str() {
                "NORMAL" => {
                    let read = buffers.floats(accessor, "NORMAL", &[Type::Vec3], [0.0; 4])?;
                    let turn = |v: [f32; 4]| match identity {
                        true => Vec4::from_array(v).truncate(),
                        false => (normal_matrix * Vec4::from_array(v).truncate()).normalize_or_zero(),
                    };
                    normals = read.into_iter().map(|v| Some(turn(v))).collect();
                }
                "TANGENT" => {
                    let read = buffers.floats(accessor, "TANGENT", &[Type::Vec4], [0.0; 4])?;
                    let turn = |v: Vec4| match identity {
                        true => v,
                        false => (linear * v.truncate()).normalize_or_zero().extend(v.w * handedness),
                    };
                    tangents = read.into_iter().map(|v| Some(turn(Vec4::from_array(v)))).collect();
                }
                "JOINTS_0" => skin.0 = Some(buffers.joints(accessor)?),
                "WEIGHTS_0" => {
                    let read = buffers.floats(accessor, "WEIGHTS_0", &[Type::Vec4], [0.0; 4])?;
                    skin.1 = Some(read.into_iter().map(Vec4::from_array).collect());
                }
                s if s.starts_with("TEXCOORD_") => {
                    let read = buffers.floats(accessor, s, &[Type::Vec2], [0.0; 4])?;
                    uvs.insert(set(&s[9..])?, read.into_iter().map(|v| Vec2::new(v[0], v[1])).collect::<Vec<_>>());
                }
                s if s.starts_with("COLOR_") => {
                    let read = buffers.floats(accessor, s, &[Type::Vec3, Type::Vec4], [1.0; 4])?;
                    colors.insert(set(&s[6..])?, read.into_iter().map(Vec4::from_array).collect::<Vec<_>>());
                }
                _ => {}
            }
        }
        let out = &mut self.out;
        out.any_normal |= !normals.is_empty() && normals[0].is_some();
        out.any_tangent |= !tangents.is_empty() && tangents[0].is_some();
        out.normals.extend(normals);
        out.tangents.extend(tangents);
        extend_sets(&mut out.uvs, uvs, base as usize, n, Vec2::ZERO);
        extend_sets(&mut out.colors, colors, base as usize, n, Vec4::ONE);
        match skin {
            (Some(joints), Some(weights)) => {
                out.any_skin = true;
                out.joints.extend(joints);
                out.weights.extend(weights);
            }
            _ => {
                out.joints.extend(std::iter::repeat_n([0; 4], n));
                out.weights.extend(std::iter::repeat_n(Vec4::X, n));
            }
        }
        Ok(base)
    }
}

/// Appends `n` values to every set (`read`'s where it has one, else `fill`), adding sets `read`
/// names that `sets` lacks (filled for the `base` vertices before).
fn extend_sets<T: Copy>(sets: &mut Vec<Vec<T>>, mut read: HashMap<u32, Vec<T>>, base: usize, n: usize, fill: T) {
    let needed = read.keys().map(|&k| k as usize + 1).max().unwrap_or(0);
    while sets.len() < needed {
        sets.push(vec![fill; base]);
    }
    for (k, set) in sets.iter_mut().enumerate() {
        match read.remove(&(k as u32)) {
            Some(values) => set.extend(values),
            None => set.extend(std::iter::repeat_n(fill, n)),
        }
    }
}

impl Columns {
    /// The asset, missing attributes filled (see [`parse_gltf_asset`]).
    fn into_asset(self) -> Result<Asset, MeshError> {
        let mesh = TriMesh::new(self.positions, self.faces)?;
        let normals: Vec<Vec3> =
            self.normals.iter().zip(mesh.normals()).map(|(n, &smooth)| n.unwrap_or(smooth)).collect();
        let tangents = self.any_tangent.then(|| {
            let fill = |(t, n): (&Option<Vec4>, &Vec3)| t.unwrap_or_else(|| n.any_orthonormal_vector().extend(1.0));
            self.tangents.iter().zip(&normals).map(fill).collect()
        });
        let attributes = VertexAttributes {
            uvs: self.uvs,
            normals: self.any_normal.then_some(normals),
            tangents,
            colors: self.colors,
            skin: self.any_skin.then_some(Skin { joints: self.joints, weights: self.weights }),
        };
        Asset::new(mesh, attributes, self.groups, self.face_groups)
    }
}
