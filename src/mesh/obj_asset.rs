//! Wavefront OBJ input of an [`Asset`]: positions with their texture coordinates (`vt`),
//! normals (`vn`), objects, groups, materials, smoothing groups and material libraries.
//! The writer is `obj_asset_write.rs`.

use std::collections::HashMap;
use std::path::Path;

use glam::{Vec2, Vec3};

use super::asset::{FaceGroup, VertexAttributes};
use super::obj::MEMORY;
use super::{Asset, MeshError, TriMesh};

/// One face corner: `v`, `vt`, `vn` indices, zero-based (`vt`/`vn` optional).
type Corner = (u32, Option<u32>, Option<u32>);

/// The `vt` and `vn` indices a vertex is used with (`None`: no face uses it yet).
type Pair = Option<(Option<u32>, Option<u32>)>;

/// Reads an OBJ file as an asset (see [`parse_obj_asset`]).
///
/// # Errors
/// [`MeshError::Io`] if the file cannot be read, otherwise as [`parse_obj_asset`].
pub fn load_obj_asset(path: impl AsRef<Path>) -> Result<Asset, MeshError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io { path: path.to_path_buf(), source })?;
    parse_obj_asset_named(&String::from_utf8_lossy(&bytes), path)
}

/// Parses OBJ text as an asset. Statements read: `v x y z` (mesh units), `vt u [v]`, `vn x y z`,
/// `f` with corners `v`, `v/vt`, `v//vn` or `v/vt/vn` (1-based or negative, relative), polygons
/// fan-triangulated; `o`, `g`, `usemtl` and `s` set the group of the faces after them and
/// `mtllib` names a material library; anything else and `#` comments are ignored.
///
/// Vertex `i` is `v` number `i + 1` with the first `vt`/`vn` pair a face uses it with; every
/// other pair it is used with makes one more vertex, appended, at the same position. The asset
/// has one UV set if any corner names a `vt` and authored normals if any names a `vn` (corners
/// without one get UV (0, 0) or the mesh's smooth normal).
///
/// # Errors
/// [`MeshError::Parse`] with the line number for a malformed statement, a NaN or infinite
/// number, an index 0 or out of range for its `v`, `vt` or `vn` list, or a face of fewer than
/// three corners; as [`TriMesh::new`] for no faces or a coordinate out of range.
///
/// # Example
/// ```
/// let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl red\nf 1/1 2/2 3/3\n";
/// let asset = dentbend::mesh::parse_obj_asset(text).unwrap();
/// assert_eq!(asset.attributes().uvs[0][1], dentbend::glam::Vec2::new(1.0, 0.0));
/// assert_eq!(asset.groups()[0].material.as_deref(), Some("red"));
/// ```
pub fn parse_obj_asset(text: &str) -> Result<Asset, MeshError> {
    parse_obj_asset_named(text, Path::new(MEMORY))
}

/// [`parse_obj_asset`] with the path to name in errors.
pub(crate) fn parse_obj_asset_named(text: &str, path: &Path) -> Result<Asset, MeshError> {
    let fail = |line: usize, message: String| MeshError::Parse {
        path: path.to_path_buf(),
        format: "OBJ",
        message: format!("line {line}: {message}"),
    };
    let mut s = State::default();
    let mut polygon: Vec<Corner> = Vec::new();
    for (number, raw) in text.lines().enumerate() {
        let line = number + 1;
        let content = raw.split('#').next().unwrap_or_default();
        let mut tokens = content.split_ascii_whitespace();
        let Some(keyword) = tokens.next() else { continue };
        let rest = || content.trim_start()[keyword.len()..].trim().to_owned();
        match keyword {
            "v" => s.positions.push(Vec3::from_array(numbers(&mut tokens, 3, 3, "vertex").map_err(|m| fail(line, m))?)),
            "vt" => {
                let [u, v, _] = numbers(&mut tokens, 1, 3, "texture coordinate").map_err(|m| fail(line, m))?;
                s.texcoords.push(Vec2::new(u, v));
            }
            "vn" => s.normals.push(Vec3::from_array(numbers(&mut tokens, 3, 3, "normal").map_err(|m| fail(line, m))?)),
            "f" | "fo" => {
                polygon.clear();
                for corner in tokens {
                    polygon.push(s.corner(corner).map_err(|m| fail(line, m))?);
                }
                if polygon.len() < 3 {
                    return Err(fail(line, format!("face has {} corners, at least 3 are needed", polygon.len())));
                }
                let group = s.group_index();
                for i in 1..polygon.len() - 1 {
                    s.triangles.push(([polygon[0], polygon[i], polygon[i + 1]], line));
                    s.face_groups.push(group);
                }
            }
            "o" => s.current.object = Some(rest()),
            "g" => s.current.group = Some(rest()),
            "usemtl" => s.current.material = Some(rest()),
            "s" => s.current.smoothing = Some(rest()),
            "mtllib" => s.libraries.push(rest()),
            _ => {}
        }
    }
    s.into_asset(&fail)
}

/// Between 1 and 3 finite numbers after a keyword (`min` required, missing ones 0).
fn numbers<'a>(
    tokens: &mut impl Iterator<Item = &'a str>,
    min: usize,
    max: usize,
    what: &str,
) -> Result<[f32; 3], String> {
    let mut out = [0.0f32; 3];
    for (k, value) in out.iter_mut().enumerate().take(max) {
        let Some(token) = tokens.next() else {
            if k < min {
                return Err(format!("{what} has {k} numbers, expected at least {min}"));
            }
            break;
        };
        *value = token.parse().map_err(|_| format!("{what} value '{token}' is not a number"))?;
        if !value.is_finite() {
            return Err(format!("{what} value '{token}' is not finite"));
        }
    }
    Ok(out)
}

/// Everything read so far.
#[derive(Default)]
struct State {
    positions: Vec<Vec3>,
    texcoords: Vec<Vec2>,
    normals: Vec<Vec3>,
    triangles: Vec<([Corner; 3], usize)>,
    face_groups: Vec<u32>,
    groups: Vec<FaceGroup>,
    group_ids: HashMap<FaceGroup, u32>,
    current: FaceGroup,
    libraries: Vec<String>,
}

impl State {
    /// The index of the current group, added on first use.
    fn group_index(&mut self) -> u32 {
        if let Some(&g) = self.group_ids.get(&self.current) {
            return g;
        }
        let g = self.groups.len() as u32;
        self.groups.push(self.current.clone());
        self.group_ids.insert(self.current.clone(), g);
        g
    }

    /// One corner `v[/vt][/vn]`, resolved against the lists read so far.
    fn corner(&self, corner: &str) -> Result<Corner, String> {
        let mut parts = corner.split('/');
        let v = resolve(parts.next().unwrap_or_default(), self.positions.len(), "vertex", corner)?;
        let vt = parts.next().filter(|t| !t.is_empty());
        let vt = vt.map(|t| resolve(t, self.texcoords.len(), "texture coordinate", corner)).transpose()?;
        let vn = parts.next().filter(|t| !t.is_empty());
        let vn = vn.map(|t| resolve(t, self.normals.len(), "normal", corner)).transpose()?;
        if parts.next().is_some() {
            return Err(format!("face corner '{corner}' has more than three indices"));
        }
        Ok((v, vt, vn))
    }

    /// The asset: one vertex per distinct corner (see [`parse_obj_asset`]).
    fn into_asset(self, fail: &impl Fn(usize, String) -> MeshError) -> Result<Asset, MeshError> {
        let n = self.positions.len();
        let mut positions = self.positions;
        let mut pairs: Vec<Pair> = vec![None; n];
        let mut extra: HashMap<Corner, u32> = HashMap::new();
        let mut faces = Vec::with_capacity(self.triangles.len());
        for (triangle, line) in &self.triangles {
            let mut face = [0u32; 3];
            for (slot, &(v, vt, vn)) in face.iter_mut().zip(triangle) {
                let (Some(first), Some(&p)) = (pairs.get_mut(v as usize), positions.get(v as usize)) else {
                    return Err(fail(*line, format!("vertex index {} is past the last vertex ({n})", v + 1)));
                };
                *slot = match first {
                    None => {
                        *first = Some((vt, vn));
                        v
                    }
                    Some(pair) if *pair == (vt, vn) => v,
                    Some(_) => match extra.get(&(v, vt, vn)) {
                        Some(&index) => index,
                        None => {
                            let index = u32::try_from(positions.len())
                                .map_err(|_| fail(*line, "more than 2³² vertices".to_owned()))?;
                            positions.push(p);
                            pairs.push(Some((vt, vn)));
                            extra.insert((v, vt, vn), index);
                            index
                        }
                    },
                };
            }
            faces.push(face);
        }
        let mesh = TriMesh::new(positions, faces)?;
        let mut attributes = VertexAttributes::default();
        if pairs.iter().flatten().any(|p| p.0.is_some()) {
            let uv = |p: &Pair| p.and_then(|p| p.0).map_or(Vec2::ZERO, |i| self.texcoords[i as usize]);
            attributes.uvs.push(pairs.iter().map(uv).collect());
        }
        if pairs.iter().flatten().any(|p| p.1.is_some()) {
            let normal =
                |(p, &smooth): (&Pair, &Vec3)| p.and_then(|p| p.1).map_or(smooth, |i| self.normals[i as usize]);
            attributes.normals = Some(pairs.iter().zip(mesh.normals()).map(normal).collect());
        }
        Ok(Asset::new(mesh, attributes, self.groups, self.face_groups)?.with_material_libraries(self.libraries))
    }
}

/// A zero-based index from a 1-based or negative (relative to `so_far` read) OBJ index.
/// Positive vertex indices may point ahead (checked once the file is read); `vt` and `vn`
/// indices must name one already read.
fn resolve(token: &str, so_far: usize, what: &str, corner: &str) -> Result<u32, String> {
    let index: i64 = token.parse().map_err(|_| format!("face corner '{corner}': '{token}' is not a {what} index"))?;
    let zero_based = match index {
        0 => return Err(format!("{what} index 0 is invalid (OBJ indices start at 1)")),
        i if i > 0 => i - 1,
        i => so_far as i64 + i,
    };
    let ahead_ok = what == "vertex" && index > 0;
    if zero_based < 0 || (!ahead_ok && zero_based >= so_far as i64) {
        return Err(format!("{what} index {index} is out of range ({so_far} read so far)"));
    }
    u32::try_from(zero_based).map_err(|_| format!("{what} index {index} is too large"))
}
