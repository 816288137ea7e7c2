//! A fracture's rest and pieces as game assets: the attributes of the [`Asset`] that broke,
//! carried over through each output vertex's [`VertexOrigin`], for any engine.
//!
//! A surface vertex blends its face's corners with its weights (UVs, colours, normals, tangents)
//! or takes its heaviest corner's values (skin influences). A cut face's vertices get UVs
//! projected on the cut's plane at the asset's own texel density (UV units per metre along its
//! surface, per UV set), the cut's normal, tangents along that projection, and colours and skin
//! from their nearest surface point. Faces keep the group of the face they lie on (a cut face
//! its nearest surface's).

use glam::{Vec2, Vec3, Vec4};

use super::{SurfacePoint, VertexOrigin};
use crate::mesh::{Asset, MeshError, Skin, TriMesh, VertexAttributes, orthogonal_tangent};

/// The asset of `mesh`, an output of breaking `broken` (its rest or a piece, in the same
/// coordinates), whose vertices lie where `origins` say on `broken`'s mesh, with `broken`'s
/// attributes and groups carried over (see the module's rules).
///
/// # Errors
/// [`MeshError::DentMismatch`] when `origins` is not one per vertex of `mesh`, or names a face
/// `broken` does not have; [`MeshError::AttributeValue`] for a carried value that is not
/// finite (it never is from finite attributes).
pub fn carry_asset(broken: &Asset, mesh: TriMesh, origins: &[VertexOrigin]) -> Result<Asset, MeshError> {
    let faces = broken.mesh().faces();
    if origins.len() != mesh.vertex_count() {
        return Err(mismatch("origins, one per output vertex", mesh.vertex_count(), origins.len()));
    }
    if let Some(bad) = origins.iter().filter_map(point).find(|p| p.face as usize >= faces.len()) {
        return Err(mismatch("a surface point's face within the broken mesh's faces", faces.len(), bad.face as usize));
    }
    let corners = |o: &VertexOrigin| point(o).map(|p| (faces[p.face as usize].map(|v| v as usize), p.weights));
    let from = broken.attributes();
    let cut_normal = |k: usize| match origins[k] {
        VertexOrigin::Cut { normal, .. } => Some(normal),
        VertexOrigin::Surface(_) => None,
    };
    let normals = from.normals.as_ref().map(|authored| {
        (0..origins.len())
            .map(|k| {
                let blended = corners(&origins[k]).filter(|_| cut_normal(k).is_none()).map(|c| blend(authored, c));
                cut_normal(k).or(blended.and_then(Vec3::try_normalize)).unwrap_or(mesh.normals()[k])
            })
            .collect::<Vec<Vec3>>()
    });
    let shading: &[Vec3] = normals.as_deref().unwrap_or(mesh.normals());
    let uvs = from
        .uvs
        .iter()
        .map(|set| {
            let density = texel_density(broken.mesh().positions(), broken.mesh().faces(), set);
            (0..origins.len())
                .map(|k| match cut_normal(k) {
                    Some(n) => {
                        let (u, v) = cut_uv_axes(n);
                        let p = mesh.positions()[k];
                        Vec2::new(u.dot(p), v.dot(p)) * density
                    }
                    None => corners(&origins[k]).map_or(Vec2::ZERO, |c| blend(set, c)),
                })
                .collect()
        })
        .collect();
    let tangents = from.tangents.as_ref().map(|authored| {
        (0..origins.len())
            .map(|k| match (cut_normal(k), corners(&origins[k])) {
                (Some(n), _) => perpendicular(cut_uv_axes(n).0.extend(1.0), shading[k]),
                (None, Some(c)) => {
                    let w = authored[heaviest(c)].w;
                    perpendicular(blend(authored, c).truncate().extend(w), shading[k])
                }
                (None, None) => Vec4::new(1.0, 0.0, 0.0, 1.0),
            })
            .collect()
    });
    // Colours and skin: a cut vertex takes its nearest surface point's.
    let colors =
        from.colors.iter().map(|set| origins.iter().map(|o| corners(o).map_or(set[0], |c| blend(set, c))).collect());
    let skin = from.skin.as_ref().map(|s| {
        let at = |o: &VertexOrigin| corners(o).map_or(0, heaviest);
        Skin {
            joints: origins.iter().map(|o| s.joints[at(o)]).collect(),
            weights: origins.iter().map(|o| s.weights[at(o)]).collect(),
        }
    });
    // A face lies on the input face nearest its centre among those around its corners' points
    // (a corner at an input vertex or edge names any one face there, maybe across a group's
    // border).
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); broken.mesh().vertex_count()];
    for (f, face) in faces.iter().enumerate() {
        face.iter().for_each(|&v| around[v as usize].push(f as u32));
    }
    let face_groups = mesh
        .faces()
        .iter()
        .map(|f| {
            let centre = f.iter().map(|&v| mesh.positions()[v as usize]).sum::<Vec3>() / 3.0;
            let named = f.iter().filter_map(|&v| point(&origins[v as usize])).map(|p| p.face);
            let candidates = named.flat_map(|n| faces[n as usize]).flat_map(|v| around[v as usize].iter().copied());
            let distance = |face: u32| off(broken.mesh(), face, centre);
            let nearest = candidates.min_by(|&a, &b| distance(a).total_cmp(&distance(b)).then(a.cmp(&b)));
            nearest.map_or(0, |face| broken.face_groups()[face as usize])
        })
        .collect();
    let attributes = VertexAttributes { uvs, normals, tangents, colors: colors.collect(), skin };
    let asset = Asset::new(mesh, attributes, broken.groups().to_vec(), face_groups)?;
    Ok(asset.with_material_libraries(broken.material_libraries().to_vec()))
}

/// How far `p` lies off face `face` of `mesh`, m: its distance to the face's plane plus how
/// far outside the triangle its projection falls (along the edges' scale).
fn off(mesh: &TriMesh, face: u32, p: Vec3) -> f32 {
    let [a, b, c] = mesh.faces()[face as usize].map(|v| mesh.positions()[v as usize]);
    let n = (b - a).cross(c - a);
    let area2 = n.length_squared();
    if area2 <= 0.0 {
        return f32::INFINITY;
    }
    let plane = (p - a).dot(n).abs() / area2.sqrt();
    // Barycentric weights of the projection; the most negative says how far outside.
    let weights = [(c - b).cross(p - b).dot(n), (a - c).cross(p - c).dot(n), (b - a).cross(p - a).dot(n)];
    let outside = weights.iter().fold(0.0f32, |m, &w| m.min(w / area2));
    plane + (-outside) * (b - a).length().max((c - a).length())
}

fn mismatch(what: &'static str, expected: usize, actual: usize) -> MeshError {
    MeshError::DentMismatch { what, expected, actual }
}

/// The surface point an origin takes its attributes from (a cut's nearest; `None`: none).
fn point(origin: &VertexOrigin) -> Option<SurfacePoint> {
    match *origin {
        VertexOrigin::Surface(p) => Some(p),
        VertexOrigin::Cut { nearest, .. } => nearest,
    }
}

/// `values` at a face's `corners` blended with `weights`.
fn blend<T>(values: &[T], (corners, weights): ([usize; 3], [f32; 3])) -> T
where
    T: Copy + std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T>,
{
    values[corners[0]] * weights[0] + values[corners[1]] * weights[1] + values[corners[2]] * weights[2]
}

/// The corner of largest weight.
fn heaviest((corners, weights): ([usize; 3], [f32; 3])) -> usize {
    let k = (0..3).max_by(|&a, &b| weights[a].total_cmp(&weights[b])).unwrap_or(0);
    corners[k]
}

/// UV units per metre along a mesh's surface (`positions`, `faces`) for the UV set `uvs`: the
/// total UV length of its faces' edges over their total length; 1 for a mesh with no length or
/// no UV length. Edges with an end past either array are left out.
pub fn texel_density(positions: &[Vec3], faces: &[[u32; 3]], uvs: &[Vec2]) -> f32 {
    let (mut along_uv, mut along_surface) = (0.0f64, 0.0f64);
    for face in faces {
        for k in 0..3 {
            let (a, b) = (face[k] as usize, face[(k + 1) % 3] as usize);
            let (Some(pa), Some(pb), Some(ua), Some(ub)) = (positions.get(a), positions.get(b), uvs.get(a), uvs.get(b))
            else {
                continue;
            };
            along_surface += f64::from(pa.distance(*pb));
            along_uv += f64::from(ua.distance(*ub));
        }
    }
    let density = (along_uv / along_surface) as f32;
    if density.is_finite() && density > 0.0 { density } else { 1.0 }
}

/// The axes (u, v) a cut of unit normal `normal` projects UVs on, with u × v = normal: the
/// same for every vertex of one cut, which share its normal, so its projection has no seam.
pub fn cut_uv_axes(normal: Vec3) -> (Vec3, Vec3) {
    let helper = if normal.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    let u = (helper - normal * normal.dot(helper)).normalize_or_zero();
    (u, normal.cross(u))
}

/// `tangent` made unit and perpendicular to `normal`, its handedness w made ±1.
fn perpendicular(tangent: Vec4, normal: Vec3) -> Vec4 {
    let w = if tangent.w < 0.0 { -1.0 } else { 1.0 };
    orthogonal_tangent(tangent.truncate().extend(w), normal)
}
