//! Game assets through damage as data: `fracture::carry_asset` makes a broken asset's rest and
//! pieces game assets too (UVs, colours, authored normals, tangents, skin and face groups
//! carried over, each surface vertex from its own side of every seam, each cut face with UVs
//! projected at the asset's texel density), and `ReplayStep::carry` brings an asset through a
//! replayed dent batch with its recorded refinement.

use std::collections::HashMap;

use dentbend::TriMesh;
use dentbend::fracture::{FracturePattern, PatternParams, Placement, VertexOrigin, break_body, carry_asset};
use dentbend::glam::{Vec2, Vec3, Vec4};
use dentbend::mesh::{self, Asset, FaceGroup, MeshError, Skin, VertexAttributes};
use dentbend::record::{DamageRecord, DentBatch, ReplayStep, decode_records, encode_records};

/// The side of a box a face of unit normal `n` is on: its axis (0 x, 1 y, 2 z) and sign.
fn side(n: Vec3) -> (usize, bool) {
    let axis = (0..3).max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs())).unwrap();
    (axis, n[axis] > 0.0)
}

fn side_normal((axis, positive): (usize, bool)) -> Vec3 {
    let mut n = Vec3::ZERO;
    n[axis] = if positive { 1.0 } else { -1.0 };
    n
}

/// A point's UV on a side with axis `axis`: the other two coordinates, 2 UV units a metre.
fn uv_on(axis: usize, p: Vec3) -> Vec2 {
    let (a, b) = [(1, 2), (0, 2), (0, 1)][axis];
    Vec2::new(2.0 * p[a], 2.0 * p[b])
}

/// A 1.2 × 0.8 × 0.1 m panel as a game asset: vertices split at its hard edges (one copy per
/// side), UVs projected per side at 2 UV units a metre, a colour whose red is x and whose green
/// is 1 on the front (+z), the sides' normals authored, tangents along each side's first UV
/// axis, a joint per side (its axis), and the front's faces in a group of their own.
fn panel() -> (Asset, Vec<(usize, bool)>) {
    let welded = mesh::subdivided_box(Vec3::new(1.2, 0.8, 0.1), [24, 16, 2]).unwrap();
    let (mut positions, mut faces, mut keys) = (Vec::new(), Vec::new(), HashMap::new());
    for face in welded.faces() {
        let [a, b, c] = face.map(|v| welded.positions()[v as usize]);
        let s = side((b - a).cross(c - a).normalize());
        faces.push(face.map(|v| {
            *keys.entry((v, s)).or_insert_with(|| {
                positions.push((welded.positions()[v as usize], s));
                positions.len() as u32 - 1
            })
        }));
    }
    let sides: Vec<(usize, bool)> = positions.iter().map(|&(_, s)| s).collect();
    let points: Vec<Vec3> = positions.iter().map(|&(p, _)| p).collect();
    let tri = TriMesh::new(points.clone(), faces).unwrap();
    let tangent = |(axis, _): (usize, bool)| side_normal(((axis + 1) % 3, true)).extend(1.0);
    let attributes = VertexAttributes {
        uvs: vec![points.iter().zip(&sides).map(|(&p, s)| uv_on(s.0, p)).collect()],
        normals: Some(sides.iter().map(|&s| side_normal(s)).collect()),
        tangents: Some(sides.iter().map(|&s| tangent(s)).collect()),
        colors: vec![
            points.iter().zip(&sides).map(|(p, &s)| Vec4::new(p.x, f32::from(s == (2, true)), 0.0, 1.0)).collect(),
        ],
        skin: Some(Skin {
            joints: sides.iter().map(|&(axis, _)| [axis as u16, 0, 0, 0]).collect(),
            weights: vec![Vec4::X; points.len()],
        }),
    };
    let front = FaceGroup { material: Some("front".into()), ..FaceGroup::default() };
    let face_groups = tri
        .faces()
        .iter()
        .map(|f| u32::from(sides[f[0] as usize] == (2, true) && sides[f[1] as usize] == (2, true)))
        .collect();
    (Asset::new(tri, attributes, vec![FaceGroup::default(), front], face_groups).unwrap(), sides)
}

/// The panel breaks; its rest and every piece carry the attributes one per vertex: each surface
/// vertex has the UV, colour, normal and joint of its position on its own side (the box's edges
/// stay seams), within 1e-5 (f32 barycentrics); each cut vertex the cut's normal, its nearest
/// surface point's colour; each cut face UVs of its plane's projection at the asset's 2 UV units
/// a metre (UV area = 4 × area, within 1e-3 relative); every tangent unit and perpendicular to
/// its normal; every face on the front in the front's group.
#[test]
fn a_broken_asset_keeps_its_attributes_across_the_break() {
    let (asset, sides) = panel();
    let tri = asset.mesh();
    let pattern = FracturePattern::new(PatternParams { cells: 12, seed: 5, radius: 0.25 }).unwrap();
    let placement = Placement { point: Vec3::new(0.0, 0.0, 0.05), normal: -Vec3::Z };
    let outcome = break_body(tri, &pattern, &placement, 1000.0).unwrap().expect("it breaks");
    let mut outputs: Vec<_> = outcome.pieces.iter().map(|p| (&p.mesh, &p.origins)).collect();
    outputs.extend(outcome.rest.as_ref().map(|r| (r, &outcome.rest_origins)));
    assert!(outputs.len() > 4);
    let close = |a: Vec4, b: Vec4| (a - b).abs().max_element() < 1e-5;
    let (mut surface, mut cut) = (0, 0);
    for (mesh, origins) in outputs {
        let carried = carry_asset(&asset, mesh.clone(), origins).unwrap();
        let a = carried.attributes();
        let (uvs, normals, tangents) = (&a.uvs[0], a.normals.as_ref().unwrap(), a.tangents.as_ref().unwrap());
        let (colours, skin) = (&a.colors[0], a.skin.as_ref().unwrap());
        assert_eq!(carried.mesh(), mesh, "the mesh is the output's");
        for (v, origin) in origins.iter().enumerate() {
            let p = mesh.positions()[v];
            let t = tangents[v];
            assert!((t.truncate().length() - 1.0).abs() < 1e-5 && t.truncate().dot(normals[v]).abs() < 1e-5, "{t}");
            assert!(t.w == 1.0 || t.w == -1.0);
            match origin {
                VertexOrigin::Surface(point) => {
                    surface += 1;
                    let s = sides[tri.faces()[point.face as usize][0] as usize];
                    assert!(close(uvs[v].extend(0.0).extend(0.0), uv_on(s.0, p).extend(0.0).extend(0.0)), "UV {v}");
                    assert!(close(colours[v], Vec4::new(p.x, f32::from(s == (2, true)), 0.0, 1.0)), "colour {v}");
                    assert!(close(normals[v].extend(0.0), side_normal(s).extend(0.0)), "normal {v}: {}", normals[v]);
                    assert_eq!(skin.joints[v][0], s.0 as u16, "joint {v}");
                }
                VertexOrigin::Cut { normal, nearest } => {
                    cut += 1;
                    assert_eq!(normals[v], *normal, "a cut vertex's normal is the cut's");
                    let point = nearest.expect("a cut with a surface beside it");
                    let corners = tri.faces()[point.face as usize];
                    let at: Vec3 = (0..3).map(|k| tri.positions()[corners[k] as usize] * point.weights[k]).sum();
                    let front = f32::from(sides[corners[0] as usize] == (2, true));
                    assert!(close(colours[v], Vec4::new(at.x, front, 0.0, 1.0)), "cut colour {v}");
                }
            }
        }
        let is_cut = |v: u32| matches!(origins[v as usize], VertexOrigin::Cut { .. });
        for (f, face) in mesh.faces().iter().enumerate() {
            if face.iter().all(|&v| is_cut(v)) {
                let [a, b, c] = face.map(|v| mesh.positions()[v as usize]);
                let [ua, ub, uc] = face.map(|v| uvs[v as usize]);
                let area = 0.5 * (b - a).cross(c - a).length();
                // A sliver's areas are mostly f32 rounding: faces of 1e-6 m² or more compared.
                if area >= 1e-6 {
                    let uv_area = 0.5 * (ub - ua).perp_dot(uc - ua).abs();
                    assert!((uv_area - 4.0 * area).abs() <= 1e-3 * 4.0 * area, "UV area {uv_area} for {area} m²");
                }
            } else if face.iter().all(|&v| !is_cut(v)) {
                let front = face.iter().all(|&v| side(normals[v as usize]) == (2, true));
                assert_eq!(carried.face_groups()[f], u32::from(front), "face {f}'s group");
            }
        }
    }
    assert!(surface > 100 && cut > 20, "{surface} surface and {cut} cut vertices checked");
}

/// Origins that do not describe the output are refused.
#[test]
fn origins_that_do_not_fit_are_refused() {
    let (asset, _) = panel();
    let mesh = asset.mesh().clone();
    let short = vec![VertexOrigin::Cut { normal: Vec3::Z, nearest: None }; mesh.vertex_count() - 1];
    assert!(matches!(carry_asset(&asset, mesh.clone(), &short), Err(MeshError::DentMismatch { .. })));
    let point = dentbend::fracture::SurfacePoint { face: u32::MAX, weights: [1.0, 0.0, 0.0] };
    let far = vec![VertexOrigin::Surface(point); mesh.vertex_count()];
    assert!(matches!(carry_asset(&asset, mesh, &far), Err(MeshError::DentMismatch { .. })));
}

/// Where two groups meet at shared vertices (a welded mesh, its material changing at x = 0),
/// every surface face of the rest and pieces keeps the group of the side its centre lies on,
/// however its corners' points name a face at a shared vertex.
#[test]
fn groups_that_share_vertices_stay_apart_across_the_break() {
    let welded = mesh::subdivided_box(Vec3::new(1.2, 0.8, 0.1), [24, 16, 2]).unwrap();
    let centre_x = |m: &TriMesh, f: &[u32; 3]| f.iter().map(|&v| m.positions()[v as usize].x).sum::<f32>() / 3.0;
    let face_groups = welded.faces().iter().map(|f| u32::from(centre_x(&welded, f) > 0.0)).collect();
    let right = FaceGroup { material: Some("right".into()), ..FaceGroup::default() };
    let asset = Asset::new(welded.clone(), VertexAttributes::default(), vec![FaceGroup::default(), right], face_groups)
        .unwrap();
    let pattern = FracturePattern::new(PatternParams { cells: 12, seed: 5, radius: 0.25 }).unwrap();
    let placement = Placement { point: Vec3::new(0.0, 0.0, 0.05), normal: -Vec3::Z };
    let outcome = break_body(&welded, &pattern, &placement, 1000.0).unwrap().expect("it breaks");
    let mut outputs: Vec<_> = outcome.pieces.iter().map(|p| (&p.mesh, &p.origins)).collect();
    outputs.extend(outcome.rest.as_ref().map(|r| (r, &outcome.rest_origins)));
    let mut checked = 0;
    for (mesh, origins) in outputs {
        let carried = carry_asset(&asset, mesh.clone(), origins).unwrap();
        for (f, face) in mesh.faces().iter().enumerate() {
            let surface = face.iter().all(|&v| matches!(origins[v as usize], VertexOrigin::Surface(_)));
            let x = centre_x(mesh, face);
            if surface && x.abs() > 1e-6 {
                assert_eq!(carried.face_groups()[f], u32::from(x > 0.0), "face {f} centred at x = {x}");
                checked += 1;
            }
        }
        assert_eq!(carried.material_libraries(), asset.material_libraries());
    }
    assert!(checked > 1000, "{checked} faces checked");
}

/// A replayed edit brings an asset through a refinement as the refinement itself does, given
/// the batch's recorded refinement (the same UVs and face groups, bit for bit); an edit that
/// changed the faces with no refinement to say how is refused, the asset unchanged. The
/// refinement survives the damage file's encoding.
#[test]
fn a_replayed_refinement_carries_attributes_as_the_refinement_does() {
    let welded = mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [4, 1, 4]).unwrap();
    let uvs = welded.positions().iter().map(|p| Vec2::new(p.x * 0.7 + p.y, p.z * 1.3)).collect();
    // Eight groups, face by face, so that a face in the wrong group shows.
    let groups: Vec<FaceGroup> =
        (0..8).map(|k| FaceGroup { group: Some(format!("g{k}")), ..FaceGroup::default() }).collect();
    let face_groups = (0..welded.face_count() as u32).map(|f| f % 8).collect();
    let attributes = VertexAttributes { uvs: vec![uvs], ..VertexAttributes::default() };
    let asset = Asset::new(welded.clone(), attributes, groups, face_groups).unwrap();
    let ball = mesh::Ball { centre: Vec3::new(0.2, 0.25, -0.1), radius: 0.6 };
    let (refined, refinement) = mesh::refine(&welded, &ball, 0.1, 100_000).unwrap();
    assert!(refinement.vertices.len() > 100, "{} new vertices", refinement.vertices.len());
    let mut exact = asset.clone();
    let moved: Vec<u32> = (welded.vertex_count() as u32..refined.vertex_count() as u32).collect();
    exact.follow_dent(refined.clone(), &refinement, &moved).unwrap();

    // Through the file's encoding.
    let batch = DentBatch { dents: 1, impacts: Vec::new(), edit: None, after: 0, refinement: Some(refinement) };
    let decoded = decode_records(&encode_records(&[DamageRecord::Dents(batch)]).unwrap()).unwrap();
    let [DamageRecord::Dents(DentBatch { refinement: Some(read), .. })] = &decoded[..] else { panic!("{decoded:?}") };
    let step = ReplayStep::Edited { before: &welded, after: &refined };
    let mut replayed = asset.clone();
    step.carry(&mut replayed, Some(read)).unwrap();
    assert_eq!(replayed, exact);

    let mut untouched = asset.clone();
    assert!(matches!(step.carry(&mut untouched, None), Err(MeshError::DentMismatch { .. })));
    assert_eq!(untouched, asset, "unchanged");
}
