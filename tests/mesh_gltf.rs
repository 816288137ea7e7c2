//! glTF 2.0 mesh I/O: `.glb` round trips, the GLB layout the specification asks for, multi-body
//! scenes, hand-written `.gltf` files (external and base64 buffers, node hierarchies, strips,
//! fans, skipped lines), malformed files rejected without panics, and saves that fail cleanly.

mod common;

use std::path::Path;

use common::TempDir;
use dentbend::TriMesh;
use dentbend::glam::{Affine3A, Quat, Vec3};
use dentbend::mesh::{self, GltfNode, MeshError};
use serde_json::{Value, json};

/// The JSON document and BIN chunk of `.glb` bytes, asserting the container layout: magic,
/// version 2, total length equal to the file length, JSON then BIN chunk, both padded to 4 bytes.
fn split_glb(bytes: &[u8]) -> (Value, Vec<u8>) {
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    assert_eq!(word(0), 0x4654_6C67, "magic");
    assert_eq!(word(4), 2, "version");
    assert_eq!(word(8) as usize, bytes.len(), "header length");
    assert_eq!(bytes.len() % 4, 0);
    let json_len = word(12) as usize;
    assert_eq!(json_len % 4, 0, "JSON chunk length");
    assert_eq!(&bytes[16..20], b"JSON");
    let json_bytes = &bytes[20..20 + json_len];
    let bin_at = 20 + json_len;
    let bin_len = word(bin_at) as usize;
    assert_eq!(bin_len % 4, 0, "BIN chunk length");
    assert_eq!(&bytes[bin_at + 4..bin_at + 8], b"BIN\0");
    assert_eq!(bin_at + 8 + bin_len, bytes.len(), "BIN is the last chunk");
    let json = serde_json::from_slice(json_bytes).expect("the JSON chunk parses (space padding is whitespace)");
    (json, bytes[bin_at + 8..].to_vec())
}

/// Little-endian bytes of f32 values.
fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// Standard base64 with padding.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let word = chunk.iter().enumerate().fold(0u32, |w, (i, &b)| w | (u32::from(b) << (16 - 8 * i)));
        for k in 0..4 {
            let c = if k <= chunk.len() { ALPHABET[((word >> (18 - 6 * k)) & 63) as usize] } else { b'=' };
            out.push(char::from(c));
        }
    }
    out
}

#[test]
fn bunny_round_trip_through_glb_is_bit_exact() {
    let dir = TempDir::new("gltf-bunny");
    let bunny = mesh::builtin("bunny").unwrap();
    let path = dir.path("bunny.glb");
    mesh::save(&path, &bunny).unwrap();
    for loaded in [mesh::load(&path).unwrap(), mesh::load(path.to_str().unwrap()).unwrap()] {
        assert_eq!(loaded.faces(), bunny.faces());
        let bits = |m: &TriMesh| m.positions().iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&loaded), bits(&bunny), "f32 positions are written and read unchanged");
    }
    // The extension dispatcher (case-insensitive) writes GLB and OBJ.
    let via_save = dir.path("via_save.GLB");
    mesh::save(&via_save, &bunny).unwrap();
    assert_eq!(mesh::load(&via_save).unwrap(), bunny);
    mesh::save(dir.path("bunny.obj"), &bunny).unwrap();
    assert_eq!(mesh::load(dir.path("bunny.obj")).unwrap().faces(), bunny.faces());
}

#[test]
fn glb_layout_follows_the_specification() {
    let dir = TempDir::new("gltf-layout");
    let bunny = mesh::builtin("bunny").unwrap();
    let path = dir.path("bunny.glb");
    mesh::save(&path, &bunny).unwrap();
    let (json, bin) = split_glb(&std::fs::read(&path).unwrap());
    assert_eq!(json["asset"]["version"], "2.0");
    let buffer_len = json["buffers"][0]["byteLength"].as_u64().unwrap() as usize;
    assert!(buffer_len <= bin.len() && bin.len() - buffer_len < 4, "BIN is the buffer plus at most 3 pad bytes");
    let primitive = &json["meshes"][0]["primitives"][0];
    assert_eq!(primitive["mode"], 4);
    let material = &json["materials"][primitive["material"].as_u64().unwrap() as usize]["pbrMetallicRoughness"];
    assert_eq!(material["metallicFactor"], 0.0);
    assert!((material["roughnessFactor"].as_f64().unwrap() - 0.6).abs() < 1e-6);
    let accessor = |index: &Value| &json["accessors"][index.as_u64().unwrap() as usize];
    let (vertices, indices) = (bunny.vertex_count() as u64, 3 * bunny.face_count() as u64);
    for (acc, count, component, kind, target) in [
        (accessor(&primitive["attributes"]["POSITION"]), vertices, 5126, "VEC3", 34962),
        (accessor(&primitive["attributes"]["NORMAL"]), vertices, 5126, "VEC3", 34962),
        (accessor(&primitive["indices"]), indices, 5125, "SCALAR", 34963),
    ] {
        assert_eq!(acc["count"].as_u64(), Some(count));
        assert_eq!(acc["componentType"], component);
        assert_eq!(acc["type"], kind);
        let view = &json["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
        assert_eq!(view["target"], target);
        let (offset, length) = (view["byteOffset"].as_u64().unwrap(), view["byteLength"].as_u64().unwrap());
        let width = if kind == "VEC3" { 12 } else { 4 };
        assert_eq!(length, count * width, "tightly packed view");
        assert_eq!(offset % 4, 0, "aligned view");
        assert!(offset + length <= buffer_len as u64);
    }
    let position = accessor(&primitive["attributes"]["POSITION"]);
    let (lo, hi) = bunny.bounds();
    let read3 = |v: &Value| Vec3::from_array([0, 1, 2].map(|k| v[k].as_f64().unwrap() as f32));
    assert_eq!(read3(&position["min"]), lo, "POSITION min is the mesh bounds, exactly");
    assert_eq!(read3(&position["max"]), hi, "POSITION max is the mesh bounds, exactly");
}

#[test]
fn scene_of_transformed_bodies_loads_back_as_their_union() {
    let dir = TempDir::new("gltf-scene");
    let bunny = mesh::builtin("bunny").unwrap();
    let ball = mesh::icosphere(0.5, 2).unwrap();
    let spin = Affine3A::from_scale_rotation_translation(
        Vec3::new(0.1, 0.1, 0.1),
        Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7),
        Vec3::new(3.0, -1.0, 0.5),
    );
    let bodies = [
        GltfNode { name: "rabbit", mesh: &bunny, transform: spin, color: [0.9, 0.5, 0.1] },
        GltfNode {
            name: "ball left",
            mesh: &ball,
            transform: Affine3A::from_translation(Vec3::X * -2.0),
            color: [0.0; 3],
        },
        GltfNode {
            name: "ball right",
            mesh: &ball,
            transform: Affine3A::from_translation(Vec3::X * 2.0),
            color: [1.0; 3],
        },
    ];
    let path = dir.path("frame.glb");
    mesh::save_glb_scene(&path, &bodies).unwrap();
    let (json, _) = split_glb(&std::fs::read(&path).unwrap());
    let names: Vec<&str> = json["nodes"].as_array().unwrap().iter().map(|n| n["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["rabbit", "ball left", "ball right"]);
    assert_eq!(json["accessors"].as_array().unwrap().len(), 6, "the two balls share one mesh's data");
    assert_eq!(json["scenes"][0]["nodes"], json!([0, 1, 2]));

    let loaded = mesh::load(&path).unwrap();
    let mut expected_positions = Vec::new();
    let mut expected_faces = Vec::new();
    for body in &bodies {
        let base = expected_positions.len() as u32;
        expected_faces.extend(body.mesh.faces().iter().map(|f| f.map(|v| v + base)));
        expected_positions.extend(body.mesh.positions().iter().map(|&p| (p, body.transform)));
    }
    assert_eq!(loaded.faces(), &expected_faces[..]);
    assert_eq!(loaded.vertex_count(), expected_positions.len());
    for (i, (&got, &(p, transform))) in loaded.positions().iter().zip(&expected_positions).enumerate() {
        let want = transform.transform_point3(p);
        // The reader rebuilds each world matrix from the stored f32 matrix (times its parent's,
        // the identity here) and applies it in its own order of operations, so the sum of three
        // products plus the translation may round differently: allow a few ulps of the largest
        // term, the linear part's magnitude times the local coordinate plus the translation.
        let linear = transform.matrix3.to_cols_array().iter().fold(0.0f32, |m, v| m.max(v.abs()));
        let scale = 3.0 * linear * p.abs().max_element() + transform.translation.abs().max_element();
        let tolerance = 4.0 * f32::EPSILON * scale;
        assert!((got - want).abs().max_element() <= tolerance, "vertex {i}: {got} vs {want} (tolerance {tolerance})");
    }
}

/// Writes `doc` as `name` in `dir` and loads it.
fn load_json(dir: &TempDir, name: &str, doc: &Value) -> Result<TriMesh, MeshError> {
    let path = dir.path(name);
    std::fs::write(&path, serde_json::to_vec(doc).unwrap()).unwrap();
    mesh::load(&path)
}

/// A `.gltf` document over one buffer holding positions (VEC3 f32, accessor 0) and u16 indices
/// (accessor 1) with the given primitives and nodes.
fn document(
    buffer_uri: &str,
    buffer_len: usize,
    positions: &[f32],
    indices: u64,
    primitives: Value,
    nodes: Value,
) -> Value {
    let position_bytes = 4 * positions.len() as u64;
    json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": nodes,
        "meshes": [{"primitives": primitives}],
        "buffers": [{"uri": buffer_uri, "byteLength": buffer_len}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": position_bytes},
            {"buffer": 0, "byteOffset": position_bytes, "byteLength": 2 * indices},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": positions.len() / 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5123, "count": indices, "type": "SCALAR"},
        ],
    })
}

#[test]
fn hand_written_gltf_with_hierarchy_strips_fans_and_lines() {
    let dir = TempDir::new("gltf-hand");
    // A unit square in z = 0, as a strip (0 1 2 3) and as a fan (0 1 3 2), counter-clockwise
    // seen from +z.
    let positions = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0];
    let indices: [u16; 8] = [0, 1, 2, 3, 0, 1, 3, 2];
    let mut bin = f32_bytes(&positions);
    bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    let primitives = json!([
        {"attributes": {"POSITION": 0}, "indices": 1, "mode": 5},
        {"attributes": {"POSITION": 0}, "mode": 1},
    ]);
    // Node 0 moves by +10 x; its child node 1 doubles the size; node 2, a sibling, mirrors z.
    let nodes = json!([
        {"translation": [10, 0, 0], "children": [1, 2]},
        {"scale": [2, 2, 2], "mesh": 0},
        {"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1], "mesh": 0},
    ]);
    std::fs::write(dir.path("square data.bin"), &bin).unwrap();
    // The strip reads the first 4 indices.
    let external = document("square%20data.bin", bin.len(), &positions, 4, primitives.clone(), nodes.clone());
    let embedded_uri = format!("data:application/octet-stream;base64,{}", base64(&bin));
    let embedded = document(&embedded_uri, bin.len(), &positions, 4, primitives, nodes);
    for (name, doc) in [("external.gltf", external), ("embedded.gltf", embedded)] {
        let square = load_json(&dir, name, &doc).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(square.vertex_count(), 8, "{name}: the lines primitive is skipped");
        let p = square.positions();
        assert_eq!(p[3], Vec3::new(12.0, 2.0, 0.0), "{name}: child scale then parent translation");
        assert_eq!(p[7], Vec3::new(11.0, 1.0, 0.0), "{name}: mirrored node");
        // Strip triangles 0 1 2 and (odd, reordered) 2 1 3; the mirrored copy is re-wound.
        assert_eq!(square.faces(), &[[0, 1, 2], [2, 1, 3], [4, 6, 5], [6, 7, 5]], "{name}");
        assert!(square.normals()[0].z > 0.99 && square.normals()[4].z < -0.99, "{name}: outward normals");
    }
    // The same square as a fan: the first vertex is shared by every triangle.
    let fan = json!([{"attributes": {"POSITION": 0}, "indices": 2, "mode": 6}]);
    let mut doc = document("square%20data.bin", bin.len(), &positions, 8, fan, json!([{"mesh": 0}]));
    doc["bufferViews"].as_array_mut().unwrap().push(json!({"buffer": 0, "byteOffset": 56, "byteLength": 8}));
    doc["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({"bufferView": 2, "componentType": 5123, "count": 4, "type": "SCALAR"}));
    let square = load_json(&dir, "fan.gltf", &doc).unwrap();
    assert_eq!(square.faces(), &[[1, 3, 0], [3, 2, 0]]);
}

/// Asserts `result` is a [`MeshError::Parse`] whose message names `path` and contains `needle`.
fn assert_parse_error(result: Result<TriMesh, MeshError>, path: &Path, needle: &str) {
    match result {
        Err(error @ MeshError::Parse { .. }) => {
            let message = error.to_string();
            assert!(message.contains(&path.display().to_string()), "{message:?} does not name {}", path.display());
            assert!(message.contains(needle), "{message:?} lacks {needle:?}");
        }
        other => panic!("{}: expected a parse error containing {needle:?}, got {other:?}", path.display()),
    }
}

#[test]
fn malformed_files_are_errors_not_panics() {
    let dir = TempDir::new("gltf-malformed");
    for name in ["empty.glb", "empty.gltf"] {
        std::fs::write(dir.path(name), b"").unwrap();
        assert_parse_error(mesh::load(dir.path(name)), &dir.path(name), "empty");
    }
    assert!(matches!(mesh::load(dir.path("missing.glb")), Err(MeshError::Io { .. })));

    // Every truncation of a valid file, and single-byte corruptions of its headers and JSON.
    let good = dir.path("good.glb");
    mesh::save(&good, &mesh::icosphere(1.0, 1).unwrap()).unwrap();
    let bytes = std::fs::read(&good).unwrap();
    let cut = dir.path("cut.glb");
    for len in (1..bytes.len()).step_by(7).chain([11, 12, 19, 20, bytes.len() - 1]) {
        std::fs::write(&cut, &bytes[..len]).unwrap();
        assert!(matches!(mesh::load(&cut), Err(MeshError::Parse { .. })), "prefix of {len} bytes");
    }
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    for at in 0..20 + json_len {
        for value in [0x00, 0x7f, 0xff, b'9', b'"', b'}'] {
            let mut bad = bytes.clone();
            bad[at] = value;
            std::fs::write(&cut, &bad).unwrap();
            // Some corruptions still make a valid file; none may panic.
            let _ = mesh::load(&cut);
        }
    }

    let positions = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let mut bin = f32_bytes(&positions);
    bin.extend([0u16, 1, 2, 5].iter().flat_map(|i| i.to_le_bytes()));
    std::fs::write(dir.path("tri.bin"), &bin).unwrap();
    let triangle = |count: u64| {
        let primitives = json!([{"attributes": {"POSITION": 0}, "indices": 1}]);
        document("tri.bin", bin.len(), &positions, count, primitives, json!([{"mesh": 0}]))
    };
    // Indices 1 2 5 with 3 vertices.
    let mut doc = triangle(4);
    doc["accessors"][1]["byteOffset"] = json!(2);
    doc["accessors"][1]["count"] = json!(3);
    match load_json(&dir, "bad_index.gltf", &doc) {
        Err(MeshError::IndexOutOfRange { face: 0, index: 5, vertex_count: 3 }) => {}
        other => panic!("expected IndexOutOfRange, got {other:?}"),
    }
    let mut doc = triangle(3);
    doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(7);
    assert_parse_error(load_json(&dir, "bad_accessor.gltf", &doc), &dir.path("bad_accessor.gltf"), "accessor 7");
    let mut doc = triangle(3);
    doc["nodes"][0]["mesh"] = json!(3);
    assert_parse_error(load_json(&dir, "bad_mesh.gltf", &doc), &dir.path("bad_mesh.gltf"), "mesh 3");
    let mut doc = triangle(3);
    doc["nodes"] = json!([{"children": [1]}, {"children": [0], "mesh": 0}]);
    assert_parse_error(load_json(&dir, "cycle.gltf", &doc), &dir.path("cycle.gltf"), "not a tree");
    let mut doc = triangle(3);
    doc["scene"] = json!(4);
    assert_parse_error(load_json(&dir, "bad_scene.gltf", &doc), &dir.path("bad_scene.gltf"), "scene 4");
    // Accessors and views that run past their data.
    assert_parse_error(load_json(&dir, "long.gltf", &triangle(9)), &dir.path("long.gltf"), "runs past");
    let mut doc = triangle(3);
    doc["bufferViews"][1]["byteOffset"] = json!(1u64 << 62);
    assert_parse_error(load_json(&dir, "far.gltf", &doc), &dir.path("far.gltf"), "runs past");
    let mut doc = triangle(3);
    doc["bufferViews"][0]["byteStride"] = json!(4);
    assert_parse_error(load_json(&dir, "stride.gltf", &doc), &dir.path("stride.gltf"), "byteStride");
    let mut doc = triangle(3);
    doc["buffers"][0]["byteLength"] = json!(1000);
    assert_parse_error(load_json(&dir, "short.gltf", &doc), &dir.path("short.gltf"), "declares 1000 bytes");
    let mut doc = triangle(3);
    doc["buffers"][0]["uri"] = json!("nowhere.bin");
    assert_parse_error(load_json(&dir, "no_bin.gltf", &doc), &dir.path("no_bin.gltf"), "nowhere.bin");
    for uri in ["%ZZ.bin", "%FF.bin", "https://example.com/tri.bin", "data:application/octet-stream;base64,A"] {
        let mut doc = triangle(3);
        doc["buffers"][0]["uri"] = json!(uri);
        assert_parse_error(load_json(&dir, "bad_uri.gltf", &doc), &dir.path("bad_uri.gltf"), "buffer 0");
    }
    let mut doc = triangle(3);
    doc["accessors"][0]["componentType"] = json!(5121);
    assert_parse_error(load_json(&dir, "bytes.gltf", &doc), &dir.path("bytes.gltf"), "expected VEC3 of f32");
    let mut doc = triangle(3);
    doc["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    assert_parse_error(load_json(&dir, "draco.gltf", &doc), &dir.path("draco.gltf"), "KHR_draco_mesh_compression");
    let mut doc = triangle(3);
    doc["meshes"][0]["primitives"][0]["mode"] = json!(0);
    assert_parse_error(load_json(&dir, "points.gltf", &doc), &dir.path("points.gltf"), "no triangles");
    assert_parse_error(load_json(&dir, "not_gltf.gltf", &json!({"hello": 1})), &dir.path("not_gltf.gltf"), "JSON");

    // A NaN position, caught by the mesh validation.
    let mut nan = bin.clone();
    nan[12..16].copy_from_slice(&f32::NAN.to_le_bytes());
    std::fs::write(dir.path("tri.bin"), &nan).unwrap();
    assert!(matches!(load_json(&dir, "nan.gltf", &triangle(3)), Err(MeshError::NonFinite { index: 1, .. })));
}

#[test]
fn failed_saves_leave_nothing_behind() {
    let dir = TempDir::new("gltf-save-fail");
    let ball = mesh::icosphere(1.0, 1).unwrap();
    let missing_dir = dir.path("no such dir");
    let target = missing_dir.join("ball.glb");
    for result in [mesh::save(&target, &ball), mesh::save(&target, &ball), mesh::save(&target, &ball)] {
        match result {
            Err(MeshError::Io { path, .. }) => assert_eq!(path, target),
            other => panic!("expected Io, got {other:?}"),
        }
    }
    assert!(!missing_dir.exists(), "the missing directory is not created");

    // A rename onto a directory fails after the data was written: the temporary file goes too.
    let occupied = dir.path("occupied.glb");
    std::fs::create_dir(&occupied).unwrap();
    assert!(matches!(mesh::save(&occupied, &ball), Err(MeshError::Io { .. })));
    assert!(matches!(mesh::save(dir.path("occupied.obj/"), &ball), Err(MeshError::Io { .. })));
    let names: Vec<_> = std::fs::read_dir(dir.root()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names, ["occupied.glb"], "no temporary file is left behind");

    let stl = dir.path("ball.stl");
    assert!(matches!(mesh::save(&stl, &ball), Err(MeshError::UnsupportedSaveFormat { .. })));
    let bad_color = GltfNode { color: [1.5, 0.0, 0.0], ..GltfNode::new("red", &ball) };
    let bad_transform =
        GltfNode { transform: Affine3A::from_scale(Vec3::splat(f32::NAN)), ..GltfNode::new("nan", &ball) };
    let cases: [&[GltfNode]; 3] = [&[], &[bad_color], &[bad_transform]];
    for bodies in cases {
        let result = mesh::save_glb_scene(dir.path("scene.glb"), bodies);
        assert!(matches!(result, Err(MeshError::InvalidParameter(_))), "{result:?}");
    }
    assert!(!stl.exists() && !dir.path("scene.glb").exists());
}

/// JSON pointers (`/a/0/b`) of every number in `value`.
fn number_pointers(value: &Value, prefix: String, out: &mut Vec<String>) {
    match value {
        Value::Object(map) => map.iter().for_each(|(k, v)| number_pointers(v, format!("{prefix}/{k}"), out)),
        Value::Array(items) => {
            items.iter().enumerate().for_each(|(i, v)| number_pointers(v, format!("{prefix}/{i}"), out))
        }
        Value::Number(_) => out.push(prefix),
        _ => {}
    }
}

#[test]
fn random_indices_counts_and_offsets_never_panic() {
    let dir = TempDir::new("gltf-fields");
    let positions = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let mut bin = f32_bytes(&positions);
    bin.extend([0u16, 1, 2, 5].iter().flat_map(|i| i.to_le_bytes()));
    std::fs::write(dir.path("tri.bin"), &bin).unwrap();
    let primitives = json!([{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}, {"attributes": {"POSITION": 0}}]);
    let nodes = json!([{"children": [1], "translation": [1, 2, 3]}, {"mesh": 0, "rotation": [0, 0, 0, 1]}]);
    let base = document("tri.bin", bin.len(), &positions, 3, primitives, nodes);
    let mut pointers = Vec::new();
    number_pointers(&base, String::new(), &mut pointers);
    // Small values hit neighbouring objects and element boundaries; large ones, overflow.
    let values: Vec<u64> =
        (0..13).chain([36, 40, 44, 255, 65535, 1 << 31, u32::MAX.into(), 1 << 32, 1 << 53, u64::MAX]).collect();
    let mut rng = common::SplitMix64::new(7);
    let path = dir.path("mutant.gltf");
    let mut loaded = 0;
    for _ in 0..2000 {
        let mut doc = base.clone();
        for _ in 0..1 + rng.below(3) {
            let pointer = &pointers[rng.below(pointers.len() as u64) as usize];
            *doc.pointer_mut(pointer).unwrap() = json!(values[rng.below(values.len() as u64) as usize]);
        }
        std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
        loaded += usize::from(mesh::load(&path).is_ok());
    }
    assert!(loaded > 0, "some mutants are still valid files");
}
