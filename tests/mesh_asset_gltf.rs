//! Assets in glTF: a `.glb` round trip keeps every UV set, normal, tangent, colour set, joint,
//! weight and material bit for bit; a hostile attribute accessor is a parse error.

use dentbend::MeshError;
use dentbend::glam::{Vec2, Vec4};
use dentbend::mesh::{
    Asset, FaceGroup, Skin, VertexAttributes, builtin_asset, glb_asset_bytes, parse_gltf, parse_gltf_asset,
};

/// The crate with two UV sets, tangents, two colour sets, a skin and its two halves in two
/// materials (faces 0..6 red, 6..12 blue).
fn dressed_crate() -> Asset {
    let (mesh, attributes, ..) = builtin_asset("crate").unwrap().into_parts();
    let n = mesh.vertex_count();
    let normals = attributes.normals.clone().unwrap();
    let attributes = VertexAttributes {
        uvs: vec![attributes.uvs[0].clone(), (0..n).map(|v| Vec2::new(v as f32 / 7.0, 0.3)).collect()],
        tangents: Some(
            normals.iter().map(|n| n.any_orthonormal_vector().extend(if n.y > 0.5 { -1.0 } else { 1.0 })).collect(),
        ),
        colors: vec![
            (0..n).map(|v| Vec4::new(v as f32 / 23.0, 0.5, 0.25, 1.0)).collect(),
            (0..n).map(|v| Vec4::new(0.1, v as f32 / 31.0, 0.9, 0.5)).collect(),
        ],
        skin: Some(Skin {
            joints: (0..n as u16).map(|v| [v % 3, 7, 300, 0]).collect(),
            weights: (0..n).map(|v| Vec4::new(0.5, 0.25, v as f32 / 96.0, 0.25 - v as f32 / 96.0)).collect(),
        }),
        normals: Some(normals),
    };
    let group = |object: &str, material: &str, index| FaceGroup {
        object: Some(object.into()),
        material: Some(material.into()),
        material_index: Some(index),
        ..FaceGroup::default()
    };
    let groups = vec![group("lid", "red", 0), group("box", "blue", 1)];
    let face_groups = (0..12).map(|f| u32::from(f >= 6)).collect();
    Asset::new(mesh, attributes, groups, face_groups).unwrap()
}

#[test]
fn glb_round_trip_keeps_every_attribute_and_material() {
    let asset = dressed_crate();
    let bytes = glb_asset_bytes(&asset).unwrap();
    let back = parse_gltf_asset(&bytes).unwrap();
    // Bit for bit: f32 data is written and read unchanged, and both primitives share one
    // vertex array (so no vertex is duplicated).
    assert_eq!(back.mesh().positions(), asset.mesh().positions());
    assert_eq!(back.mesh().faces(), asset.mesh().faces());
    assert_eq!(back.attributes(), asset.attributes());
    assert_eq!(back.groups(), asset.groups());
    assert_eq!(back.face_groups(), asset.face_groups());
    // The positions-only reader reads the file too (each primitive's vertices separately).
    assert_eq!(parse_gltf(&bytes).unwrap().face_count(), 12);
}

/// Standard base64 of `bytes`.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let word = chunk.iter().enumerate().fold(0u32, |w, (k, &b)| w | u32::from(b) << (16 - 8 * k));
        for k in 0..=chunk.len() {
            out.push(char::from(ALPHABET[(word >> (18 - 6 * k) & 63) as usize]));
        }
    }
    out
}

/// A one-triangle glTF whose TEXCOORD_0 accessor declares `uv_count` elements of `uv_type`
/// over a 24-byte view.
fn triangle_gltf(uv_count: usize, uv_type: &str, texcoord: &str) -> Vec<u8> {
    let floats: Vec<f32> = vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0];
    let data: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"{texcoord}":1}}}}]}}],
        "buffers":[{{"byteLength":60,"uri":"data:application/octet-stream;base64,{}"}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":24}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}},
                     {{"bufferView":1,"componentType":5126,"count":{uv_count},"type":"{uv_type}"}}]}}"#,
        base64(&data)
    )
    .into_bytes()
}

#[test]
fn hostile_attribute_accessors_are_parse_errors() {
    let good = parse_gltf_asset(&triangle_gltf(3, "VEC2", "TEXCOORD_0")).unwrap();
    assert_eq!(good.attributes().uvs[0], [Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)]);
    let cases = [
        (triangle_gltf(4, "VEC2", "TEXCOORD_0"), "TEXCOORD_0 has 4 elements"),
        (triangle_gltf(3_000_000_000, "VEC2", "TEXCOORD_0"), "TEXCOORD_0 has 3000000000 elements"),
        (triangle_gltf(3, "VEC3", "TEXCOORD_0"), "expected f32 or normalized"),
        (triangle_gltf(3, "VEC2", "TEXCOORD_4000000000"), "sets are read"),
    ];
    for (bytes, what) in cases {
        match parse_gltf_asset(&bytes) {
            Err(MeshError::Parse { message, .. }) => assert!(message.contains(what), "{what}: {message}"),
            other => panic!("{what}: expected a parse error, got {other:?}"),
        }
    }
}
