//! The vertex attributes of a fracture's rest and pieces, carried over from the asset that
//! broke through each vertex's [`VertexOrigin`]: a surface vertex interpolates its face's
//! corners (float and unsigned normalised formats; every other format, and joint weights, is the
//! corner of largest weight's), so textures, colours and skin data continue across the break.
//! A cut face's vertices get UVs projected on its plane at the asset's own texel density
//! (UV units per metre along its surface), tangents along that projection, and everything else
//! from the nearest surface point.

use bevy::mesh::{Mesh, VertexAttributeValues};
use dentbend::fracture::{SurfacePoint, VertexOrigin, cut_uv_axes, texel_density};
use dentbend::glam::{Vec2, Vec3, Vec4};
use dentbend::mesh::orthogonal_tangent;

/// What a fracture's output mesh takes its attributes from: the asset that broke (one value
/// per vertex of `faces`' mesh), the faces its origins name, the scale the output's
/// coordinates have over the asset's (the entity's for a piece, which is spawned unscaled; 1
/// for the rest, written without it), the scale the broken mesh had over the asset (the
/// entity's: the cuts' normals are in its coordinates), and the asset's UV units per metre
/// (measured once per fracture).
#[derive(Clone, Copy)]
pub(crate) struct Broken<'a> {
    pub asset: &'a Mesh,
    pub faces: &'a [[u32; 3]],
    pub scale: Vec3,
    pub body_scale: Vec3,
    pub texel_density: f32,
}

impl<'a> Broken<'a> {
    /// The broken `asset` with `faces`, under the entity's `body_scale`, for output written at
    /// the asset's own scale (the rest).
    pub fn new(asset: &'a Mesh, faces: &'a [[u32; 3]], body_scale: Vec3) -> Self {
        Self { asset, faces, scale: Vec3::ONE, body_scale, texel_density: uv_density(asset, faces) }
    }

    /// The same, for output whose coordinates have `scale` over the asset's (a piece).
    pub fn scaled(self, scale: Vec3) -> Self {
        Self { scale, ..self }
    }
}

/// Adds to `out` (a fracture output's positions, normals and indices) every other attribute
/// of the broken asset, one value per vertex of `origins`.
/// An attribute the asset does not hold one value per vertex of is left out, with a warning.
pub(crate) fn carry_attributes(out: &mut Mesh, broken: &Broken, origins: &[VertexOrigin]) {
    let count = broken.asset.count_vertices();
    let Ok(attributes) = broken.asset.try_attributes() else { return };
    let positions: Vec<Vec3> = match out.attribute(Mesh::ATTRIBUTE_POSITION) {
        Some(VertexAttributeValues::Float32x3(p)) => p.iter().map(|p| Vec3::from_array(*p)).collect(),
        _ => return,
    };
    let normals: Vec<Vec3> = match out.attribute(Mesh::ATTRIBUTE_NORMAL) {
        Some(VertexAttributeValues::Float32x3(n)) => n.iter().map(|n| Vec3::from_array(*n)).collect(),
        _ => vec![Vec3::Z; positions.len()],
    };
    let texel_density = broken.texel_density;
    for (attribute, values) in attributes {
        let id = attribute.id;
        if id == Mesh::ATTRIBUTE_POSITION.id || id == Mesh::ATTRIBUTE_NORMAL.id {
            continue;
        }
        if values.len() != count {
            log::warn!(
                "bevy_dentbend: a broken mesh's attribute {id:?} had {} values for {count} vertices; left out",
                values.len()
            );
            continue;
        }
        let nearest = id == Mesh::ATTRIBUTE_JOINT_WEIGHT.id;
        let mut carried = carry(values, broken.faces, origins, nearest);
        let cut = |k: usize| matches!(origins[k], VertexOrigin::Cut { .. });
        // The cut's plane axes, in the asset's coordinates (from the cut's own normal: the
        // same for all its vertices, so the projection has no seam).
        let axes = |k: usize| {
            let n = match origins[k] {
                VertexOrigin::Cut { normal, .. } => normal * broken.body_scale,
                VertexOrigin::Surface(_) => normals[k] * broken.scale,
            };
            cut_uv_axes(n.normalize_or_zero())
        };
        match &mut carried {
            VertexAttributeValues::Float32x2(uvs) if id == Mesh::ATTRIBUTE_UV_0.id || id == Mesh::ATTRIBUTE_UV_1.id => {
                for (k, uv) in uvs.iter_mut().enumerate().filter(|(k, _)| cut(*k)) {
                    let ((u, v), p) = (axes(k), positions[k] / broken.scale);
                    *uv = (Vec2::new(u.dot(p), v.dot(p)) * texel_density).to_array();
                }
            }
            VertexAttributeValues::Float32x4(tangents) if id == Mesh::ATTRIBUTE_TANGENT.id => {
                for (k, t) in tangents.iter_mut().enumerate() {
                    *t = if cut(k) {
                        // Bevy's bitangent is n × t·w: w = 1 makes it the projection's v axis.
                        let along = (axes(k).0 * broken.scale).normalize_or_zero();
                        perpendicular(along.extend(1.0), normals[k]).to_array()
                    } else {
                        perpendicular(Vec4::from_array(*t), normals[k]).to_array()
                    };
                }
            }
            _ => {}
        }
        out.insert_attribute(*attribute, carried);
    }
}

/// The UV units per metre along `asset`'s surface ([`texel_density`] of its `faces` and first
/// UV set; 1 without UVs).
fn uv_density(asset: &Mesh, faces: &[[u32; 3]]) -> f32 {
    let (Some(VertexAttributeValues::Float32x3(p)), Some(VertexAttributeValues::Float32x2(uv))) =
        (asset.attribute(Mesh::ATTRIBUTE_POSITION), asset.attribute(Mesh::ATTRIBUTE_UV_0))
    else {
        return 1.0;
    };
    let positions: Vec<Vec3> = p.iter().map(|p| Vec3::from_array(*p)).collect();
    let uvs: Vec<Vec2> = uv.iter().map(|u| Vec2::from_array(*u)).collect();
    texel_density(&positions, faces, &uvs)
}

/// `tangent` made unit and perpendicular to `normal`, its handedness w made ±1.
fn perpendicular(tangent: Vec4, normal: Vec3) -> Vec4 {
    let w = if tangent.w < 0.0 { -1.0 } else { 1.0 };
    orthogonal_tangent(tangent.truncate().extend(w), normal)
}

/// The surface point each origin takes its attributes from (a cut's nearest; `None`: none).
fn point(origin: &VertexOrigin) -> Option<SurfacePoint> {
    match *origin {
        VertexOrigin::Surface(p) => Some(p),
        VertexOrigin::Cut { nearest, .. } => nearest,
    }
}

/// One value per origin: `values` blended over the corners of the face its point names with
/// the point's weights (float and unsigned normalised formats unless `nearest`), else the
/// value of the corner of largest weight. An origin without a point, or naming a face or
/// vertex out of range, takes vertex 0's value.
fn carry(
    values: &VertexAttributeValues,
    faces: &[[u32; 3]],
    origins: &[VertexOrigin],
    nearest: bool,
) -> VertexAttributeValues {
    use VertexAttributeValues as V;
    let corners = |o: &VertexOrigin| -> ([usize; 3], [f32; 3]) {
        point(o)
            .and_then(|p| faces.get(p.face as usize).map(|f| (f.map(|v| v as usize), p.weights)))
            .unwrap_or(([0; 3], [1.0, 0.0, 0.0]))
    };
    let blend = |v: &[f32], o: &VertexOrigin| -> f32 {
        let (c, w) = corners(o);
        (0..3).map(|k| v.get(c[k]).copied().unwrap_or_default() * w[k]).sum()
    };
    if !nearest {
        macro_rules! mix {
            ($v:expr, $n:literal, $to:expr, $from:expr) => {{
                origins
                    .iter()
                    .map(|o| {
                        let (c, w) = corners(o);
                        $from(std::array::from_fn::<f32, $n, _>(|ch| {
                            (0..3).map(|k| $v.get(c[k]).map_or(0.0, |x| $to(x, ch)) * w[k]).sum()
                        }))
                    })
                    .collect()
            }};
        }
        match values {
            V::Float32(v) => return V::Float32(origins.iter().map(|o| blend(v, o)).collect()),
            V::Float32x2(v) => return V::Float32x2(mix!(v, 2, |x: &[f32; 2], k| x[k], |a| a)),
            V::Float32x3(v) => return V::Float32x3(mix!(v, 3, |x: &[f32; 3], k| x[k], |a| a)),
            V::Float32x4(v) => return V::Float32x4(mix!(v, 4, |x: &[f32; 4], k| x[k], |a| a)),
            V::Float64(v) => {
                return V::Float64(
                    origins
                        .iter()
                        .map(|o| {
                            let (c, w) = corners(o);
                            (0..3).map(|k| v.get(c[k]).copied().unwrap_or_default() * f64::from(w[k])).sum()
                        })
                        .collect(),
                );
            }
            V::Unorm8x4(v) => {
                return V::Unorm8x4(
                    mix!(v, 4, |x: &[u8; 4], k| f32::from(x[k]), |a: [f32; 4]| a.map(|c| c.round() as u8))
                );
            }
            V::Unorm8x4Bgra(v) => {
                return V::Unorm8x4Bgra(
                    mix!(v, 4, |x: &[u8; 4], k| f32::from(x[k]), |a: [f32; 4]| a.map(|c| c.round() as u8))
                );
            }
            V::Unorm16x4(v) => {
                return V::Unorm16x4(
                    mix!(v, 4, |x: &[u16; 4], k| f32::from(x[k]), |a: [f32; 4]| a.map(|c| c.round() as u16))
                );
            }
            _ => {}
        }
    }
    // The corner of largest weight's value.
    let pick = |o: &VertexOrigin| -> usize {
        let (c, w) = corners(o);
        let k = (0..3).max_by(|&a, &b| w[a].total_cmp(&w[b])).unwrap_or(0);
        c[k]
    };
    fn take<T: Copy + Default>(v: &[T], at: impl Iterator<Item = usize>) -> Vec<T> {
        at.map(|k| v.get(k).copied().unwrap_or_default()).collect()
    }
    let at = || origins.iter().map(pick);
    match values {
        V::Uint8(v) => V::Uint8(take(v, at())),
        V::Unorm8(v) => V::Unorm8(take(v, at())),
        V::Uint8x2(v) => V::Uint8x2(take(v, at())),
        V::Unorm8x2(v) => V::Unorm8x2(take(v, at())),
        V::Uint8x4(v) => V::Uint8x4(take(v, at())),
        V::Unorm8x4(v) => V::Unorm8x4(take(v, at())),
        V::Unorm8x4Bgra(v) => V::Unorm8x4Bgra(take(v, at())),
        V::Sint8(v) => V::Sint8(take(v, at())),
        V::Snorm8(v) => V::Snorm8(take(v, at())),
        V::Sint8x2(v) => V::Sint8x2(take(v, at())),
        V::Snorm8x2(v) => V::Snorm8x2(take(v, at())),
        V::Sint8x4(v) => V::Sint8x4(take(v, at())),
        V::Snorm8x4(v) => V::Snorm8x4(take(v, at())),
        V::Uint16(v) => V::Uint16(take(v, at())),
        V::Unorm16(v) => V::Unorm16(take(v, at())),
        V::Uint16x2(v) => V::Uint16x2(take(v, at())),
        V::Unorm16x2(v) => V::Unorm16x2(take(v, at())),
        V::Uint16x4(v) => V::Uint16x4(take(v, at())),
        V::Unorm16x4(v) => V::Unorm16x4(take(v, at())),
        V::Sint16(v) => V::Sint16(take(v, at())),
        V::Snorm16(v) => V::Snorm16(take(v, at())),
        V::Sint16x2(v) => V::Sint16x2(take(v, at())),
        V::Snorm16x2(v) => V::Snorm16x2(take(v, at())),
        V::Sint16x4(v) => V::Sint16x4(take(v, at())),
        V::Snorm16x4(v) => V::Snorm16x4(take(v, at())),
        V::Float16(v) => V::Float16(take(v, at())),
        V::Float16x2(v) => V::Float16x2(take(v, at())),
        V::Float16x4(v) => V::Float16x4(take(v, at())),
        V::Float32(v) => V::Float32(take(v, at())),
        V::Float32x2(v) => V::Float32x2(take(v, at())),
        V::Float32x3(v) => V::Float32x3(take(v, at())),
        V::Float32x4(v) => V::Float32x4(take(v, at())),
        V::Uint32(v) => V::Uint32(take(v, at())),
        V::Unorm10_10_10_2(v) => V::Unorm10_10_10_2(take(v, at())),
        V::Uint32x2(v) => V::Uint32x2(take(v, at())),
        V::Uint32x3(v) => V::Uint32x3(take(v, at())),
        V::Uint32x4(v) => V::Uint32x4(take(v, at())),
        V::Sint32(v) => V::Sint32(take(v, at())),
        V::Sint32x2(v) => V::Sint32x2(take(v, at())),
        V::Sint32x3(v) => V::Sint32x3(take(v, at())),
        V::Sint32x4(v) => V::Sint32x4(take(v, at())),
        V::Float64(v) => V::Float64(take(v, at())),
        V::Float64x2(v) => V::Float64x2(take(v, at())),
        V::Float64x3(v) => V::Float64x3(take(v, at())),
        V::Float64x4(v) => V::Float64x4(take(v, at())),
    }
}

#[cfg(test)]
mod tests {
    use bevy::mesh::VertexAttributeValues as V;
    use dentbend::TriMesh;
    use dentbend::fracture::{FracturePattern, PatternParams, Placement, break_body};

    use super::*;
    use crate::bevy_mesh;

    /// The side of a box a face of unit normal `n` is on: its axis (0 x, 1 y, 2 z) and sign.
    fn side(n: Vec3) -> (usize, bool) {
        let axis = (0..3).max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs())).unwrap_or(0);
        (axis, n[axis] > 0.0)
    }

    /// A point's UV on a side with axis `axis`: the other two coordinates, 2 UV units a metre.
    fn uv_on(axis: usize, p: Vec3) -> [f32; 2] {
        let (a, b) = [(1, 2), (0, 2), (0, 1)][axis];
        [2.0 * p[a], 2.0 * p[b]]
    }

    /// A 1.2 × 0.8 × 0.1 m panel as a game asset: vertices split at its hard edges (one copy per
    /// side of the box), UVs projected per side at 2 UV units a metre, a colour whose red is the
    /// vertex's x and whose green is 1 on the front face. Its mesh and asset.
    fn panel_asset() -> (TriMesh, Mesh) {
        let welded = dentbend::mesh::subdivided_box(Vec3::new(1.2, 0.8, 0.1), [24, 16, 2]).unwrap();
        let (mut positions, mut faces, mut keys) = (Vec::new(), Vec::new(), std::collections::HashMap::new());
        for face in welded.faces() {
            let [a, b, c] = face.map(|v| welded.positions()[v as usize]);
            let s = side((b - a).cross(c - a).normalize());
            faces.push(face.map(|v| {
                *keys.entry((v, s)).or_insert_with(|| {
                    positions.push(welded.positions()[v as usize]);
                    positions.len() as u32 - 1
                })
            }));
        }
        let tri = TriMesh::new(positions, faces).unwrap();
        let sides: Vec<(usize, bool)> = tri.normals().iter().map(|&n| side(n)).collect();
        let uvs: Vec<[f32; 2]> = tri.positions().iter().zip(&sides).map(|(&p, s)| uv_on(s.0, p)).collect();
        let colours: Vec<[f32; 4]> = tri
            .positions()
            .iter()
            .zip(&sides)
            .map(|(p, &s)| [p.x, if s == (2, true) { 1.0 } else { 0.0 }, 0.0, 1.0])
            .collect();
        let asset = bevy_mesh(&tri)
            .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, uvs)
            .with_inserted_attribute(Mesh::ATTRIBUTE_COLOR, colours);
        (tri, asset)
    }

    /// The panel breaks; its rest and every piece carry UVs and colours one per vertex: each
    /// surface vertex has the UV and colour of its position on its own side of the box (so the
    /// box's edges stay seams), within 1e-5 (f32 barycentrics); each cut face's UVs are its
    /// plane's projection at the asset's 2 UV units a metre (UV area = 4 × area, within 1e-3
    /// relative) and each cut vertex's colour its nearest surface point's.
    #[test]
    fn a_broken_asset_keeps_its_uvs_and_colours() {
        let (tri, asset) = panel_asset();
        let pattern = FracturePattern::new(PatternParams { cells: 12, seed: 5, radius: 0.25 }).unwrap();
        let placement = Placement { point: Vec3::new(0.0, 0.0, 0.05), normal: -Vec3::Z };
        let outcome = break_body(&tri, &pattern, &placement, 1000.0).unwrap().expect("it breaks");
        let mut outputs: Vec<_> = outcome.pieces.iter().map(|p| (&p.mesh, &p.origins)).collect();
        outputs.extend(outcome.rest.as_ref().map(|r| (r, &outcome.rest_origins)));
        assert!(outputs.len() > 4);
        for (mesh, origins) in outputs {
            let mut made = bevy_mesh(mesh);
            carry_attributes(&mut made, &Broken::new(&asset, tri.faces(), Vec3::ONE), origins);
            let Some(V::Float32x2(uvs)) = made.attribute(Mesh::ATTRIBUTE_UV_0) else { panic!("no UVs") };
            let Some(V::Float32x4(colours)) = made.attribute(Mesh::ATTRIBUTE_COLOR) else { panic!("no colours") };
            assert_eq!((uvs.len(), colours.len()), (mesh.vertex_count(), mesh.vertex_count()));
            for (v, origin) in origins.iter().enumerate() {
                let p = mesh.positions()[v];
                if let VertexOrigin::Surface(point) = origin {
                    let corners = tri.faces()[point.face as usize];
                    let s = side(tri.normals()[corners[0] as usize]);
                    let expected = uv_on(s.0, p);
                    let close = |a: &[f32], b: &[f32]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-5);
                    assert!(close(&uvs[v], &expected), "vertex {v} at {p}: UV {:?}, not {expected:?}", uvs[v]);
                    let green = if s == (2, true) { 1.0 } else { 0.0 };
                    assert!(close(&colours[v], &[p.x, green, 0.0, 1.0]), "vertex {v}: colour {:?}", colours[v]);
                } else {
                    let VertexOrigin::Cut { nearest: Some(point), .. } = origin else {
                        panic!("a cut with no surface")
                    };
                    let corners = tri.faces()[point.face as usize];
                    let at: Vec3 = (0..3).map(|k| tri.positions()[corners[k] as usize] * point.weights[k]).sum();
                    let green = if side(tri.normals()[corners[0] as usize]) == (2, true) { 1.0 } else { 0.0 };
                    let expected = [at.x, green, 0.0, 1.0];
                    let close = colours[v].iter().zip(&expected).all(|(x, y)| (x - y).abs() < 1e-5);
                    assert!(close, "cut vertex {v}: colour {:?}, not {expected:?}", colours[v]);
                }
            }
            let cut = |v: u32| matches!(origins[v as usize], VertexOrigin::Cut { .. });
            for face in mesh.faces().iter().filter(|f| f.iter().all(|&v| cut(v))) {
                let [a, b, c] = face.map(|v| mesh.positions()[v as usize]);
                let [ua, ub, uc] = face.map(|v| Vec2::from_array(uvs[v as usize]));
                let area = 0.5 * (b - a).cross(c - a).length();
                // A sliver's areas are mostly f32 rounding (its positions' ulps, about 3e-8 m
                // here, are a good part of its height): faces of 1e-6 m² or more are compared.
                if area < 1e-6 {
                    continue;
                }
                let uv_area = 0.5 * (ub - ua).perp_dot(uc - ua).abs();
                assert!((uv_area - 4.0 * area).abs() <= 1e-3 * 4.0 * area, "UV area {uv_area} for {area} m²");
            }
        }
    }
}
