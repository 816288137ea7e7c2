//! A game asset's mesh: a [`TriMesh`] with the per-vertex attributes (UV sets, authored normals,
//! tangents, colour sets, skin) and per-face groups (objects, groups, materials) that engines
//! and file formats carry, validated on construction.
//!
//! Assets split vertices wherever an attribute is discontinuous (a hard edge, a UV seam, a
//! material boundary): such a vertex is several vertices at bit-identical positions, each used
//! only by the faces of its own side. [`Asset::follow_dent`] brings every attribute through a
//! dent.

use glam::{Vec2, Vec3, Vec4};

use super::{MeshError, TriMesh};

/// Per-vertex attributes, each array one entry per vertex of the asset's mesh.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VertexAttributes {
    /// Texture coordinate sets (OBJ `vt`, glTF `TEXCOORD_n`), unitless; glTF's convention (u
    /// right, v down from the image's top) is kept as read, OBJ's (v up) likewise.
    pub uvs: Vec<Vec<Vec2>>,
    /// Authored unit normals (OBJ `vn`, glTF `NORMAL`), mesh frame; `None`: the mesh's own
    /// smooth normals ([`TriMesh::normals`]) stand in.
    pub normals: Option<Vec<Vec3>>,
    /// Tangents (glTF `TANGENT`): unit xyz in the mesh frame, perpendicular to the normal; w = ±1
    /// is the handedness (bitangent = w·(normal × tangent)).
    pub tangents: Option<Vec<Vec4>>,
    /// Colour sets (glTF `COLOR_n`), linear RGBA, each channel in [0, 1] by convention.
    pub colors: Vec<Vec<Vec4>>,
    /// Skin influences (glTF `JOINTS_0`/`WEIGHTS_0`).
    pub skin: Option<Skin>,
}

/// Up to four joint influences per vertex.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Skin {
    /// Joint indices into the asset's skeleton, one quadruple per vertex.
    pub joints: Vec<[u16; 4]>,
    /// Weights of those joints, each ≥ 0, summing to 1 for a skinned vertex.
    pub weights: Vec<Vec4>,
}

/// What a run of faces belongs to: OBJ's `o`, `g`, `usemtl` and `s` state, or a glTF primitive's
/// mesh name and material.
#[derive(Debug, Clone, Default, PartialEq, Eq, Hash)]
pub struct FaceGroup {
    /// Object name (OBJ `o`, glTF mesh name).
    pub object: Option<String>,
    /// Group names as written after OBJ `g`.
    pub group: Option<String>,
    /// Material name (OBJ `usemtl`, glTF material name).
    pub material: Option<String>,
    /// glTF material index, when the faces came from glTF.
    pub material_index: Option<u32>,
    /// OBJ smoothing group as written after `s` (`off`, `1`, ...).
    pub smoothing: Option<String>,
}

/// A [`TriMesh`] with per-vertex attributes and per-face groups. Invariants, checked by every
/// constructor: every attribute array has one entry per vertex, every value is finite (weights
/// also ≥ 0), there is at least one group and one group index per face, each in range.
#[derive(Debug, Clone, PartialEq)]
pub struct Asset {
    pub(super) mesh: TriMesh,
    pub(super) attributes: VertexAttributes,
    groups: Vec<FaceGroup>,
    pub(super) face_groups: Vec<u32>,
    material_libraries: Vec<String>,
}

impl Asset {
    /// An asset of `mesh` with `attributes` and faces grouped by `face_groups` (one index into
    /// `groups` per face).
    ///
    /// # Errors
    /// [`MeshError::AttributeLength`] naming an array of the wrong length,
    /// [`MeshError::AttributeValue`] for a NaN or infinite value (or a negative weight), a group
    /// index past `groups`, or no groups at all.
    pub fn new(
        mesh: TriMesh,
        attributes: VertexAttributes,
        groups: Vec<FaceGroup>,
        face_groups: Vec<u32>,
    ) -> Result<Self, MeshError> {
        check_attributes(&attributes, mesh.vertex_count())?;
        check_groups(&groups, &face_groups, mesh.face_count())?;
        Ok(Self { mesh, attributes, groups, face_groups, material_libraries: Vec::new() })
    }

    /// An asset with no attributes but the mesh's own and one unnamed group.
    pub fn from_mesh(mesh: TriMesh) -> Self {
        let face_groups = vec![0; mesh.face_count()];
        Self {
            mesh,
            attributes: VertexAttributes::default(),
            groups: vec![FaceGroup::default()],
            face_groups,
            material_libraries: Vec::new(),
        }
    }

    /// This asset naming the OBJ material libraries `libraries` (the text after `mtllib`).
    pub fn with_material_libraries(mut self, libraries: Vec<String>) -> Self {
        self.material_libraries = libraries;
        self
    }

    /// The mesh: positions (mesh units), faces and smooth normals.
    pub fn mesh(&self) -> &TriMesh {
        &self.mesh
    }

    /// The per-vertex attributes.
    pub fn attributes(&self) -> &VertexAttributes {
        &self.attributes
    }

    /// The face groups, in order of first use.
    pub fn groups(&self) -> &[FaceGroup] {
        &self.groups
    }

    /// Each face's index into [`groups`](Self::groups).
    pub fn face_groups(&self) -> &[u32] {
        &self.face_groups
    }

    /// OBJ material libraries (`mtllib`), in file order.
    pub fn material_libraries(&self) -> &[String] {
        &self.material_libraries
    }

    /// Unit vertex normals to shade with: the authored ones, else the mesh's smooth ones.
    pub fn shading_normals(&self) -> &[Vec3] {
        self.attributes.normals.as_deref().unwrap_or(self.mesh.normals())
    }

    /// Replaces the attributes.
    ///
    /// # Errors
    /// As [`Asset::new`]; the asset is unchanged then.
    pub fn set_attributes(&mut self, attributes: VertexAttributes) -> Result<(), MeshError> {
        check_attributes(&attributes, self.mesh.vertex_count())?;
        self.attributes = attributes;
        Ok(())
    }

    /// The parts: mesh, attributes, groups, face groups and material libraries.
    pub fn into_parts(self) -> (TriMesh, VertexAttributes, Vec<FaceGroup>, Vec<u32>, Vec<String>) {
        (self.mesh, self.attributes, self.groups, self.face_groups, self.material_libraries)
    }

    /// Replaces mesh, attributes and face groups already checked by the caller.
    pub(crate) fn replace_checked(&mut self, mesh: TriMesh, attributes: VertexAttributes, face_groups: Vec<u32>) {
        debug_assert!(check_attributes(&attributes, mesh.vertex_count()).is_ok());
        debug_assert!(check_groups(&self.groups, &face_groups, mesh.face_count()).is_ok());
        (self.mesh, self.attributes, self.face_groups) = (mesh, attributes, face_groups);
    }
}

/// Every attribute array one entry per vertex (`count`), every value finite, weights ≥ 0.
pub(crate) fn check_attributes(a: &VertexAttributes, count: usize) -> Result<(), MeshError> {
    let length = |attribute: String, actual: usize| match actual == count {
        true => Ok(()),
        false => Err(MeshError::AttributeLength { attribute, expected: count, actual }),
    };
    let finite = |attribute: String, bad: Option<usize>| match bad {
        None => Ok(()),
        Some(index) => Err(MeshError::AttributeValue { attribute, index, reason: "not finite" }),
    };
    for (set, uvs) in a.uvs.iter().enumerate() {
        length(format!("uv set {set}"), uvs.len())?;
        finite(format!("uv set {set}"), uvs.iter().position(|v| !v.is_finite()))?;
    }
    if let Some(normals) = &a.normals {
        length("normals".into(), normals.len())?;
        finite("normals".into(), normals.iter().position(|v| !v.is_finite()))?;
    }
    if let Some(tangents) = &a.tangents {
        length("tangents".into(), tangents.len())?;
        finite("tangents".into(), tangents.iter().position(|v| !v.is_finite()))?;
    }
    for (set, colors) in a.colors.iter().enumerate() {
        length(format!("colour set {set}"), colors.len())?;
        finite(format!("colour set {set}"), colors.iter().position(|v| !v.is_finite()))?;
    }
    if let Some(skin) = &a.skin {
        length("skin joints".into(), skin.joints.len())?;
        length("skin weights".into(), skin.weights.len())?;
        finite("skin weights".into(), skin.weights.iter().position(|v| !v.is_finite()))?;
        if let Some(index) = skin.weights.iter().position(|w| w.min_element() < 0.0) {
            return Err(MeshError::AttributeValue { attribute: "skin weights".into(), index, reason: "negative" });
        }
    }
    Ok(())
}

/// At least one group, one group index per face (`faces`), each in range.
fn check_groups(groups: &[FaceGroup], face_groups: &[u32], faces: usize) -> Result<(), MeshError> {
    if face_groups.len() != faces {
        let actual = face_groups.len();
        return Err(MeshError::AttributeLength { attribute: "face groups".into(), expected: faces, actual });
    }
    if groups.is_empty() {
        return Err(MeshError::AttributeLength { attribute: "groups".into(), expected: 1, actual: 0 });
    }
    match face_groups.iter().position(|&g| g as usize >= groups.len()) {
        None => Ok(()),
        Some(index) => {
            Err(MeshError::AttributeValue { attribute: "face groups".into(), index, reason: "no such group" })
        }
    }
}
