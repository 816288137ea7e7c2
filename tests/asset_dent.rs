//! An asset through a refined dent: new vertices take their parents' blended UVs, new faces
//! their parent face's group, normals far from the dent stay bit-identical and the crate's hard
//! edges stay hard; a dent that does not fit the asset is refused and changes nothing.

use dentbend::dent::{DentJob, dent_batch_tracked};
use dentbend::glam::{Affine3A, Vec2, Vec3};
use dentbend::mesh::{Asset, FaceGroup, Refinement, builtin, builtin_asset};
use dentbend::{DentParams, Impact, MeshError, TriMesh};

/// The crate, its faces in two groups (its top side, faces 4 and 5, apart), dented from above
/// by a ball of radius 0.5 at (0.3, 1, 0.2), 0.1 deep: the dented mesh, refinement and moved.
fn dented_crate() -> (Asset, TriMesh, Refinement, Vec<u32>) {
    let (mesh, attributes, ..) = builtin_asset("crate").unwrap().into_parts();
    let groups = vec![FaceGroup::default(), FaceGroup { material: Some("top".into()), ..FaceGroup::default() }];
    let face_groups = (0..12).map(|f| u32::from(f == 4 || f == 5)).collect();
    let asset = Asset::new(mesh, attributes, groups, face_groups).unwrap();
    let mut ball = builtin("sphere").unwrap();
    ball.transform(Affine3A::from_scale_rotation_translation(
        Vec3::splat(0.5),
        Default::default(),
        Vec3::new(0.3, 1.5, 0.2),
    ))
    .unwrap();
    let impact = Impact { point: Vec3::new(0.3, 1.0, 0.2), normal: -Vec3::Y, relative_velocity: -Vec3::Y };
    let mut meshes = vec![asset.mesh().clone()];
    let jobs = [DentJob { target: 0, projectile: &ball, impact, params: DentParams::new(0.1) }];
    let outcome = dent_batch_tracked(&mut meshes, &jobs).unwrap();
    let refinement = outcome.refined.into_iter().next().unwrap();
    assert!(refinement.added_vertices() > 50, "the crate is refined under the dent");
    (asset, meshes.pop().unwrap(), refinement, outcome.moved.into_iter().next().unwrap())
}

#[test]
fn new_vertices_interpolate_uvs_and_new_faces_keep_their_group() {
    let (mut asset, dented, refinement, moved) = dented_crate();
    let before = asset.clone();
    asset.follow_dent(dented, &refinement, &moved).unwrap();
    let uvs = &asset.attributes().uvs[0];
    let base = before.mesh().vertex_count();
    assert_eq!(uvs.len(), asset.mesh().vertex_count());
    assert_eq!(uvs[..base], before.attributes().uvs[0][..]);
    // Where each vertex was before the dent moved it, and the top side's UV map there
    // (u along z, v along x: the crate's top side has axes u = z, v = x).
    let undented = refinement.interpolate(before.mesh().positions(), |a, b, t| a.lerp(*b, t)).unwrap();
    let top_uv = |p: Vec3| Vec2::new((p.z + 1.0) / 2.0, (p.x + 1.0) / 2.0);
    // A vertex is on the top side when a top face (group 1) uses it: a seam's sides (the top's
    // edges) have a vertex each, with its own side's UVs.
    let mut on_top = vec![false; asset.mesh().vertex_count()];
    let faces = asset.mesh().faces();
    for f in (0..faces.len()).filter(|&f| asset.face_groups()[f] == 1) {
        faces[f].iter().for_each(|&v| on_top[v as usize] = true);
    }
    for (k, split) in refinement.vertices.iter().enumerate() {
        let v = base + k;
        let [a, b] = split.parents.map(|p| uvs[p as usize]);
        // Tolerance: one f32 rounding of the lerp.
        assert!(uvs[v].distance(a.lerp(b, split.fraction)) <= 1e-6, "vertex {v}: {} vs its parents' lerp", uvs[v]);
        if on_top[v] {
            assert!(uvs[v].distance(top_uv(undented[v])) <= 1e-5, "top vertex {v}: {} at {}", uvs[v], undented[v]);
        }
    }
    // Every new face is a piece of a top face (group 1) or of a side face below its edges.
    for (k, &parent) in refinement.face_parents.iter().enumerate() {
        let face = refinement.base_face_count + k;
        assert_eq!(asset.face_groups()[face], before.face_groups()[parent as usize], "face {face}");
    }
    assert!(asset.face_groups().iter().filter(|&&g| g == 1).count() > 2);
}

#[test]
fn far_normals_stay_bit_identical_and_hard_edges_stay_hard() {
    let (asset, dented, refinement, listed) = dented_crate();
    let old = asset.attributes().normals.clone().unwrap();
    // The vertices the dent really moved (the batch's list also names every new vertex): new
    // ones where they are not halfway along their parents, as refinement computes them.
    let undented = refinement.interpolate(asset.mesh().positions(), |a, b, _| *a * 0.5 + *b * 0.5).unwrap();
    let moved: Vec<u32> =
        (0..dented.vertex_count() as u32).filter(|&v| dented.positions()[v as usize] != undented[v as usize]).collect();
    let mut followed = asset.clone();
    followed.follow_dent(dented.clone(), &refinement, &moved).unwrap();
    let normals = followed.attributes().normals.as_ref().unwrap();
    // Vertices on no face that touches a moved vertex keep their normal bit for bit.
    let near = |moved: &[u32]| {
        let mut near = vec![false; dented.vertex_count()];
        for f in dented.faces().iter().filter(|f| f.iter().any(|v| moved.contains(v))) {
            f.iter().for_each(|&v| near[v as usize] = true);
        }
        near
    };
    let near_moved = near(&moved);
    let far: Vec<usize> = (0..asset.mesh().vertex_count()).filter(|&v| !near_moved[v]).collect();
    assert!(far.len() >= 16, "only {} far vertices", far.len());
    for &v in &far {
        assert_eq!(normals[v].to_array().map(f32::to_bits), old[v].to_array().map(f32::to_bits), "vertex {v}");
    }
    // With the batch's list, which names every new vertex, the top side's four corners are
    // recomputed (their faces were refined) from the top side's faces alone: still +y within
    // 0.1° (the dent is 0.4 away), not blended with the sides; the side vertices at the same
    // corners keep their side's normal exactly.
    let mut followed = asset.clone();
    followed.follow_dent(dented.clone(), &refinement, &listed).unwrap();
    let normals = followed.attributes().normals.as_ref().unwrap();
    let near_listed = near(&listed);
    let top = 8..12; // side 2 of the crate is +y
    for v in top.clone() {
        assert!(near_listed[v], "top corner {v} was not recomputed");
        assert!(normals[v].dot(Vec3::Y) > 0.999_998, "top corner {v}: {}", normals[v]);
    }
    let positions = followed.mesh().positions();
    for v in (0..24).filter(|v| !top.contains(v) && positions[*v].y == 1.0) {
        assert_eq!(normals[v], old[v], "side vertex {v} at {} took the top's normal", positions[v]);
        assert!(normals[v].dot(Vec3::Y).abs() < 1e-6);
    }
}

#[test]
fn a_dent_that_does_not_fit_is_refused_and_changes_nothing() {
    let (mut asset, dented, refinement, moved) = dented_crate();
    let before = asset.clone();
    let unrefined = builtin_asset("crate").unwrap().mesh().clone();
    let result = asset.follow_dent(unrefined, &refinement, &moved);
    assert!(
        matches!(result, Err(MeshError::DentMismatch { what: "the dented mesh's vertex count", .. })),
        "{result:?}"
    );
    let mut bad_parent = refinement.clone();
    bad_parent.vertices[0].parents[1] = 1_000_000;
    let result = asset.follow_dent(dented.clone(), &bad_parent, &moved);
    assert!(matches!(result, Err(MeshError::DentMismatch { what: "a new vertex's parent", .. })), "{result:?}");
    let result = asset.follow_dent(dented, &refinement, &[u32::MAX]);
    assert!(matches!(result, Err(MeshError::DentMismatch { what: "a moved vertex", .. })), "{result:?}");
    assert_eq!(asset, before);
}

#[test]
fn tangents_stay_perpendicular_and_skin_weights_sum_to_one() {
    let (asset, dented, refinement, moved) = dented_crate();
    let (mesh, attributes, groups, face_groups, _) = asset.into_parts();
    let n = mesh.vertex_count();
    let normals = attributes.normals.clone().unwrap();
    let dressed = dentbend::mesh::VertexAttributes {
        tangents: Some(
            normals.iter().map(|n| n.any_orthonormal_vector().extend(if n.x < 0.0 { -1.0 } else { 1.0 })).collect(),
        ),
        skin: Some(dentbend::mesh::Skin {
            joints: (0..n as u16).map(|v| [v % 5, 5 + v % 3, 9, 10]).collect(),
            weights: (0..n)
                .map(|v| {
                    let mut w = [0.4, 0.3, 0.2, 0.1];
                    w.rotate_left(v % 4);
                    dentbend::glam::Vec4::from_array(w)
                })
                .collect(),
        }),
        ..attributes
    };
    let mut asset = Asset::new(mesh, dressed, groups, face_groups).unwrap();
    asset.follow_dent(dented, &refinement, &moved).unwrap();
    let a = asset.attributes();
    let (normals, tangents, skin) =
        (a.normals.as_ref().unwrap(), a.tangents.as_ref().unwrap(), a.skin.as_ref().unwrap());
    for (k, split) in refinement.vertices.iter().enumerate() {
        let v = n + k;
        let (t, normal) = (tangents[v], normals[v]);
        // Tolerances: a few f32 roundings of a unit vector.
        assert!((normal.length() - 1.0).abs() < 1e-5, "vertex {v}: normal {normal}");
        assert!((t.truncate().length() - 1.0).abs() < 1e-5 && t.truncate().dot(normal).abs() < 1e-5, "vertex {v}: {t}");
        let nearer = split.parents[usize::from(split.fraction >= 0.5)];
        assert_eq!(t.w, tangents[nearer as usize].w, "vertex {v}: handedness not its nearer parent's");
        let w = skin.weights[v];
        assert!((w.element_sum() - 1.0).abs() < 1e-5 && w.min_element() >= 0.0, "vertex {v}: weights {w}");
        // The four largest merged influences, largest first.
        assert!(w.x >= w.y && w.y >= w.z && w.z >= w.w, "vertex {v}: weights {w} not sorted");
        let [a, b] = split.parents.map(|p| skin.joints[p as usize]);
        assert!(skin.joints[v].iter().zip(w.to_array()).all(|(j, wt)| wt == 0.0 || a.contains(j) || b.contains(j)));
    }
}
