//! glTF 2.0 output of an [`Asset`] as one binary `.glb` file: the vertex data once, read by one
//! mesh and node per face group, each mesh one triangle primitive with the group's material.

use std::io::Write;
use std::path::Path;

use glam::{Vec3, Vec4};
use serde_json::{Value, json};

use super::atomic_write::write_atomically;
use super::glb;
use super::{Asset, MeshError};

/// `bufferView.target` of vertex attribute data.
const ARRAY_BUFFER: u32 = 34962;
/// `bufferView.target` of index data.
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
/// `accessor.componentType` of f32, u16 and u32 components.
const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
/// Base colour (linear RGBA) and roughness of the materials written (their names and indices
/// are the asset's; textures and other properties are not carried).
const BASE_COLOR: [f32; 4] = [0.6, 0.6, 0.6, 1.0];
const ROUGHNESS: f32 = 0.6;

/// Writes `asset` as a binary glTF file: f32 `POSITION` (with `min`/`max`), `NORMAL` (the
/// authored normals, else the smooth ones; a zero normal as +z), `TANGENT`, `TEXCOORD_n` and
/// `COLOR_n` (RGBA) of every set, u16 `JOINTS_0` and f32 `WEIGHTS_0`, shared by one node, mesh
/// and triangle primitive per face group (named after the group's object), whose material keeps
/// the group's glTF material index (new indices after the largest for OBJ materials) and name.
/// [`load_asset`](super::load_asset) reads the attributes back bit for bit. Written
/// through a temporary sibling file.
///
/// # Errors
/// [`MeshError::Io`] naming `path` if it cannot be written; [`MeshError::InvalidParameter`] if
/// the file would exceed the format's 4 GiB limit.
pub fn save_glb_asset(asset: &Asset, path: impl AsRef<Path>) -> Result<(), MeshError> {
    let bytes = glb_asset_bytes(asset)?;
    write_atomically(path.as_ref(), |out| out.write_all(&bytes))
}

/// The `.glb` bytes [`save_asset`](super::save_asset) writes for a `.glb` path.
///
/// # Errors
/// As [`save_asset`](super::save_asset), less the I/O.
pub fn glb_asset_bytes(asset: &Asset) -> Result<Vec<u8>, MeshError> {
    let mut doc = Doc::default();
    let mesh = asset.mesh();
    let a = asset.attributes();
    let count = mesh.vertex_count();
    let (lo, hi) = mesh.bounds();
    let mut attributes = serde_json::Map::new();
    let floats = |values: &mut dyn Iterator<Item = f32>| values.flat_map(f32::to_le_bytes).collect::<Vec<u8>>();
    let position = floats(&mut mesh.positions().iter().flat_map(|p| p.to_array()));
    let bounds = Some((lo.to_array().to_vec(), hi.to_array().to_vec()));
    attributes.insert("POSITION".into(), doc.accessor(&position, FLOAT, count, "VEC3", bounds).into());
    let normals = asset.shading_normals().iter().map(|&n| if n == Vec3::ZERO { Vec3::Z } else { n });
    let normal = floats(&mut normals.flat_map(|n| n.to_array()));
    attributes.insert("NORMAL".into(), doc.accessor(&normal, FLOAT, count, "VEC3", None).into());
    if let Some(tangents) = &a.tangents {
        let data = floats(&mut tangents.iter().flat_map(|t| t.to_array()));
        attributes.insert("TANGENT".into(), doc.accessor(&data, FLOAT, count, "VEC4", None).into());
    }
    for (k, set) in a.uvs.iter().enumerate() {
        let data = floats(&mut set.iter().flat_map(|t| t.to_array()));
        attributes.insert(format!("TEXCOORD_{k}"), doc.accessor(&data, FLOAT, count, "VEC2", None).into());
    }
    for (k, set) in a.colors.iter().enumerate() {
        let data = floats(&mut set.iter().flat_map(|c| c.to_array()));
        attributes.insert(format!("COLOR_{k}"), doc.accessor(&data, FLOAT, count, "VEC4", None).into());
    }
    if let Some(skin) = &a.skin {
        let joints: Vec<u8> = skin.joints.iter().flatten().flat_map(|j| j.to_le_bytes()).collect();
        attributes.insert("JOINTS_0".into(), doc.accessor(&joints, UNSIGNED_SHORT, count, "VEC4", None).into());
        let data = floats(&mut skin.weights.iter().flat_map(|w: &Vec4| w.to_array()));
        attributes.insert("WEIGHTS_0".into(), doc.accessor(&data, FLOAT, count, "VEC4", None).into());
    }
    let materials = material_indices(asset);
    for (g, group) in asset.groups().iter().enumerate() {
        let faces = mesh.faces().iter().zip(asset.face_groups()).filter(|(_, fg)| **fg as usize == g);
        let indices: Vec<u8> = faces.flat_map(|(f, _)| f.iter().flat_map(|i| i.to_le_bytes())).collect();
        if indices.is_empty() {
            continue;
        }
        doc.target = ELEMENT_ARRAY_BUFFER;
        let index = doc.accessor(&indices, UNSIGNED_INT, indices.len() / 4, "SCALAR", None);
        doc.target = ARRAY_BUFFER;
        let mut primitive = json!({ "attributes": attributes.clone(), "indices": index, "mode": 4 });
        if let Some(m) = materials[g] {
            primitive["material"] = m.into();
        }
        let mut mesh_json = json!({ "primitives": [primitive] });
        if let Some(name) = &group.object {
            mesh_json["name"] = name.clone().into();
        }
        let mut node = json!({ "mesh": doc.meshes.len() });
        if let Some(name) = &group.object {
            node["name"] = name.clone().into();
        }
        doc.meshes.push(mesh_json);
        doc.nodes.push(node);
    }
    let material_count = materials.iter().flatten().map(|&m| m as usize + 1).max().unwrap_or(0);
    let material_json: Vec<Value> = (0..material_count)
        .map(|m| {
            let name =
                asset.groups().iter().zip(&materials).find(|(g, i)| **i == Some(m as u32) && g.material.is_some());
            let mut material = json!({ "pbrMetallicRoughness": {
                "baseColorFactor": BASE_COLOR, "metallicFactor": 0.0, "roughnessFactor": ROUGHNESS } });
            if let Some((group, _)) = name {
                material["name"] = group.material.clone().into();
            }
            material
        })
        .collect();
    let nodes: Vec<usize> = (0..doc.nodes.len()).collect();
    let mut root = json!({
        "asset": { "version": "2.0", "generator": concat!("dentbend ", env!("CARGO_PKG_VERSION")) },
        "scene": 0,
        "scenes": [{ "nodes": nodes }],
        "nodes": doc.nodes,
        "meshes": doc.meshes,
        "buffers": [{ "byteLength": doc.bin.len() }],
        "bufferViews": doc.views,
        "accessors": doc.accessors,
    });
    if !material_json.is_empty() {
        root["materials"] = material_json.into();
    }
    let json = serde_json::to_vec(&root).map_err(|e| MeshError::InvalidParameter(format!("glTF JSON: {e}")))?;
    glb::pack(&json, &doc.bin).map_err(MeshError::InvalidParameter)
}

/// Each group's material index: its glTF one, else one per distinct OBJ material name after
/// the largest glTF index, else none.
fn material_indices(asset: &Asset) -> Vec<Option<u32>> {
    let mut next = asset.groups().iter().filter_map(|g| g.material_index).map(|m| m + 1).max().unwrap_or(0);
    let mut named: Vec<(&str, u32)> = Vec::new();
    let mut out = Vec::with_capacity(asset.groups().len());
    for group in asset.groups() {
        out.push(match (group.material_index, group.material.as_deref()) {
            (Some(m), _) => Some(m),
            (None, Some(name)) => Some(match named.iter().find(|(n, _)| *n == name) {
                Some(&(_, m)) => m,
                None => {
                    named.push((name, next));
                    next += 1;
                    next - 1
                }
            }),
            (None, None) => None,
        });
    }
    out
}

/// The document's arrays and binary buffer so far.
struct Doc {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
    nodes: Vec<Value>,
    /// `bufferView.target` of the next view.
    target: u32,
}

impl Default for Doc {
    fn default() -> Self {
        let (bin, views, accessors, meshes, nodes) = Default::default();
        Self { bin, views, accessors, meshes, nodes, target: ARRAY_BUFFER }
    }
}

impl Doc {
    /// Appends `data` (padded to 4 bytes) as a new view read by a new accessor; its index.
    fn accessor(
        &mut self,
        data: &[u8],
        component: u32,
        count: usize,
        kind: &str,
        bounds: Option<(Vec<f32>, Vec<f32>)>,
    ) -> usize {
        let view =
            json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": data.len(), "target": self.target });
        self.views.push(view);
        self.bin.extend_from_slice(data);
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        let mut accessor =
            json!({ "bufferView": self.views.len() - 1, "componentType": component, "count": count, "type": kind });
        if let Some((lo, hi)) = bounds {
            accessor["min"] = lo.into();
            accessor["max"] = hi.into();
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }
}
