//! Malformed mesh input and bad generator parameters give the right typed error, never a panic.

use dentbend::MeshError;
use dentbend::glam::Vec3;
use dentbend::mesh::{self, BUILTIN_NAMES};

/// The message of a `Parse` error, failing on any other outcome.
fn parse_message(result: Result<dentbend::TriMesh, MeshError>, format: &str) -> String {
    match result {
        Err(MeshError::Parse { format: f, message, .. }) => {
            assert_eq!(f, format);
            message
        }
        other => panic!("expected a {format} parse error, got {other:?}"),
    }
}

// ---- OBJ ---------------------------------------------------------------------------------------

#[test]
fn obj_non_finite_coordinates() {
    for (text, index) in [
        ("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 0),
        ("v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n", 1),
        ("v 0 0 0\nv 1 0 0\nv 0 -infinity 0\nf 1 2 3\n", 2),
        // Beyond f32 range: reads as infinity.
        ("v 0 0 1e39\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 0),
    ] {
        match mesh::parse_obj(text) {
            Err(MeshError::NonFinite { index: i, .. }) => assert_eq!(i, index, "{text}"),
            other => panic!("{text}: expected NonFinite, got {other:?}"),
        }
    }
}

#[test]
fn obj_index_out_of_range() {
    match mesh::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n") {
        Err(MeshError::IndexOutOfRange { face: 1, index: 3, vertex_count: 3 }) => {}
        other => panic!("expected IndexOutOfRange, got {other:?}"),
    }
}

#[test]
fn obj_empty_and_faceless() {
    assert!(matches!(mesh::parse_obj(""), Err(MeshError::Empty { vertices: 0, faces: 0 })));
    assert!(matches!(mesh::parse_obj("# nothing\n\n"), Err(MeshError::Empty { vertices: 0, faces: 0 })));
    let points = mesh::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    assert!(matches!(points, Err(MeshError::Empty { vertices: 3, faces: 0 })), "{points:?}");
}

#[test]
fn obj_malformed_statements_name_their_line() {
    let head = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    for (body, needle) in [
        ("v 1 2\n", "line 4"),
        ("v 1 x 2\n", "'x'"),
        ("f 1 2\n", "at least 3"),
        ("f 0 1 2\n", "index 0"),
        ("f -4 1 2\n", "before the first vertex"),
        ("f 1 2 99999999999\n", "too large"),
        ("f 1 2 three\n", "'three'"),
        ("f 1 2 /3\n", "line 4"),
    ] {
        let message = parse_message(mesh::parse_obj(&format!("{head}{body}")), "OBJ");
        assert!(message.contains(needle), "{body:?}: message {message:?} lacks {needle:?}");
        assert!(message.starts_with("line 4:"), "{message}");
    }
}

// ---- PLY ---------------------------------------------------------------------------------------

const TRIANGLE_ASCII: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

/// A little-endian binary triangle: three float vertices and one uchar/int face.
fn triangle_binary() -> Vec<u8> {
    let mut out = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
    for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        v.iter().for_each(|c| out.extend(c.to_le_bytes()));
    }
    out.push(3);
    [0i32, 1, 2].iter().for_each(|i| out.extend(i.to_le_bytes()));
    out
}

#[test]
fn ply_reference_files_parse() {
    // The fixtures below are broken copies of these; make sure the originals are fine.
    assert_eq!(mesh::parse_ply(TRIANGLE_ASCII.as_bytes()).unwrap().face_count(), 1);
    assert_eq!(mesh::parse_ply(&triangle_binary()).unwrap(), mesh::parse_ply(TRIANGLE_ASCII.as_bytes()).unwrap());
}

#[test]
fn ply_non_finite_coordinates() {
    let ascii = TRIANGLE_ASCII.replace("1 0 0\n0 1 0", "1 0 0\n0 nan 0");
    assert!(matches!(mesh::parse_ply(ascii.as_bytes()), Err(MeshError::NonFinite { index: 2, .. })));
    let ascii = TRIANGLE_ASCII.replace("\n1 0 0\n", "\n-inf 0 0\n");
    assert!(matches!(mesh::parse_ply(ascii.as_bytes()), Err(MeshError::NonFinite { index: 1, .. })));
    let mut binary = triangle_binary();
    let at = binary.len() - 13 - 4; // z of the third vertex
    binary[at..at + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
    assert!(matches!(mesh::parse_ply(&binary), Err(MeshError::NonFinite { index: 2, .. })));
    // A double beyond f32 range is infinite once stored.
    let big = TRIANGLE_ASCII.replace("property float x", "property double x").replace("\n1 0 0\n", "\n1e300 0 0\n");
    assert!(matches!(mesh::parse_ply(big.as_bytes()), Err(MeshError::NonFinite { index: 1, .. })));
}

#[test]
fn ply_bad_indices() {
    let out_of_range = TRIANGLE_ASCII.replace("3 0 1 2", "3 0 1 3");
    match mesh::parse_ply(out_of_range.as_bytes()) {
        Err(MeshError::IndexOutOfRange { index: 3, vertex_count: 3, .. }) => {}
        other => panic!("expected IndexOutOfRange, got {other:?}"),
    }
    let negative = TRIANGLE_ASCII.replace("3 0 1 2", "3 0 -1 2");
    assert!(parse_message(mesh::parse_ply(negative.as_bytes()), "PLY").contains("-1"));
    let two = TRIANGLE_ASCII.replace("3 0 1 2", "2 0 1");
    assert!(parse_message(mesh::parse_ply(two.as_bytes()), "PLY").contains("at least 3"));
}

#[test]
fn ply_empty_meshes() {
    let none = TRIANGLE_ASCII.replace("vertex 3", "vertex 0").replace("face 1", "face 0");
    let none = &none[..none.find("end_header\n").unwrap() + 11];
    assert!(matches!(mesh::parse_ply(none.as_bytes()), Err(MeshError::Empty { vertices: 0, faces: 0 })));
    let points = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n";
    assert!(matches!(mesh::parse_ply(points.as_bytes()), Err(MeshError::Empty { vertices: 1, faces: 0 })));
}

#[test]
fn ply_bad_headers() {
    for (bytes, needle) in [
        (&b""[..], "not a PLY file"),
        (b"\x00\xff\x13garbage\x7f\n\x01\x02", "not a PLY file"),
        (b"solid ascii\nfacet normal 0 0 1\n", "not a PLY file"),
        (b"ply\nformat ascii 1.0\nelement vertex 3\n", "end_header"),
        (b"ply\nformat ascii 2.0\nend_header\n", "version"),
        (b"ply\nformat utf16 1.0\nend_header\n", "unknown format"),
        (b"ply\nelement vertex 1\nproperty float x\nend_header\n", "format"),
        (b"ply\nformat ascii 1.0\nproperty float x\nend_header\n", "before any element"),
        (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n", "unknown property type"),
        (b"ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", "element count"),
        (b"ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\nend_header\n", "element count"),
        (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n", "'z'"),
        (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty list uchar float z\nend_header\n", "list"),
        (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list float int vertex_indices\nend_header\n", "integer"),
        (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n", "integers"),
        (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty int flags\nend_header\n", "vertex_indices"),
        (b"ply\nformat ascii 1.0\nelement colour 1\nend_header\n", "no properties"),
        (b"ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n", "no 'vertex' element"),
        (b"ply\nformat ascii 1.0\nbogus line\nend_header\n", "unknown"),
        (b"ply\nformat ascii 1.0\nelement vertex 1\nelement vertex 1\nend_header\n", "duplicate"),
    ] {
        let message = parse_message(mesh::parse_ply(bytes), "PLY");
        assert!(message.contains(needle), "{:?}: {message:?} lacks {needle:?}", String::from_utf8_lossy(bytes));
    }
}

#[test]
fn ply_count_mismatches() {
    // Fewer vertex lines than declared: the face line is read as a vertex and has 4 values.
    let fewer = TRIANGLE_ASCII.replace("vertex 3", "vertex 4");
    assert!(parse_message(mesh::parse_ply(fewer.as_bytes()), "PLY").contains("entries"));
    // More vertex lines than declared: a vertex line is read as a face.
    let more = TRIANGLE_ASCII.replace("0 1 0\n3 0 1 2", "0 1 0\n0 0 1\n3 0 1 2");
    parse_message(mesh::parse_ply(more.as_bytes()), "PLY");
    // Extra or missing values on a line name the line.
    let extra = TRIANGLE_ASCII.replace("\n1 0 0\n", "\n1 0 0 7\n");
    assert!(parse_message(mesh::parse_ply(extra.as_bytes()), "PLY").contains("line 11"));
    let short = TRIANGLE_ASCII.replace("\n1 0 0\n", "\n1 0\n");
    assert!(parse_message(mesh::parse_ply(short.as_bytes()), "PLY").contains("line 11: too few"));
    let list = TRIANGLE_ASCII.replace("3 0 1 2", "4 0 1 2");
    assert!(parse_message(mesh::parse_ply(list.as_bytes()), "PLY").contains("list of 4"));
    let value = TRIANGLE_ASCII.replace("3 0 1 2", "3 0 1 2.5");
    assert!(parse_message(mesh::parse_ply(value.as_bytes()), "PLY").contains("'2.5'"));
    let uchar = TRIANGLE_ASCII.replace("3 0 1 2", "300 0 1 2");
    assert!(parse_message(mesh::parse_ply(uchar.as_bytes()), "PLY").contains("'300'"));
    // Trailing bytes after the last element in binary.
    let mut trailing = triangle_binary();
    trailing.extend([0, 0, 0, 0]);
    assert!(parse_message(mesh::parse_ply(&trailing), "PLY").contains("after the last"));
}

#[test]
fn ply_truncated_binary_at_every_length() {
    let full = triangle_binary();
    let header_len = full.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    for len in 0..full.len() {
        let result = mesh::parse_ply(&full[..len]);
        assert!(matches!(result, Err(MeshError::Parse { .. })), "prefix of {len} bytes: {result:?}");
        if len >= header_len {
            let message = parse_message(result, "PLY");
            assert!(message.contains("truncated"), "prefix of {len} bytes: {message}");
        }
    }
    assert!(mesh::parse_ply(&full).is_ok());
}

/// `binary` with `from` replaced by `to` in its header (the data bytes are left alone).
fn edit_header(binary: &[u8], from: &str, to: &str) -> Vec<u8> {
    let header_end = binary.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let header = std::str::from_utf8(&binary[..header_end]).unwrap();
    assert!(header.contains(from));
    let mut bytes = header.replace(from, to).into_bytes();
    bytes.extend(&binary[header_end..]);
    bytes
}

#[test]
fn ply_huge_declared_counts_fail_fast() {
    // Each would need gigabytes if believed; the checks against the data size reject them first.
    for count in ["4000000000", "4294967295", "18446744073709551615"] {
        let bytes = edit_header(&triangle_binary(), "vertex 3", &format!("vertex {count}"));
        let message = parse_message(mesh::parse_ply(&bytes), "PLY");
        assert!(message.contains("truncated") || message.contains("more than"), "{count}: {message}");
        let bytes = edit_header(&triangle_binary(), "face 1", &format!("face {count}"));
        assert!(parse_message(mesh::parse_ply(&bytes), "PLY").contains("truncated"), "{count}");
        let ascii = TRIANGLE_ASCII.replace("face 1", &format!("face {count}"));
        let message = parse_message(mesh::parse_ply(ascii.as_bytes()), "PLY");
        assert!(message.contains("truncated"), "{count}: {message}");
    }
    // A huge list length in a binary face is rejected before its items are read.
    let mut bytes = triangle_binary();
    let count_at = bytes.len() - 13;
    bytes[count_at] = 255;
    let message = parse_message(mesh::parse_ply(&bytes), "PLY");
    assert!(message.contains("255 items"), "{message}");
    // Same with a 32-bit count of 4e9 (the count grows from 1 to 4 bytes).
    let mut bytes = edit_header(&triangle_binary(), "list uchar int", "list uint int");
    let count_at = bytes.len() - 13;
    bytes.splice(count_at..=count_at, 4_000_000_000u32.to_le_bytes());
    let message = parse_message(mesh::parse_ply(&bytes), "PLY");
    assert!(message.contains("4000000000 items"), "{message}");
    // And in ASCII.
    let ascii = TRIANGLE_ASCII.replace("list uchar int", "list uint int").replace("3 0 1 2", "4000000000 0 1 2");
    assert!(parse_message(mesh::parse_ply(ascii.as_bytes()), "PLY").contains("list of 4000000000"));
}

#[test]
fn ply_random_corruption_never_panics() {
    let sources = [triangle_binary(), TRIANGLE_ASCII.as_bytes().to_vec()];
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for source in &sources {
        for _ in 0..2000 {
            let mut bytes = source.clone();
            for _ in 0..1 + next() % 3 {
                let at = (next() % bytes.len() as u64) as usize;
                bytes[at] = next() as u8;
            }
            // Any outcome but a panic (or a hang) is acceptable for random damage.
            let _ = mesh::parse_ply(&bytes);
            let _ = mesh::parse_obj(&String::from_utf8_lossy(&bytes));
        }
    }
}

// ---- files and names ---------------------------------------------------------------------------

#[test]
fn missing_files_are_io_errors() {
    let dir = std::env::temp_dir().join(format!("dentbend-no-such-dir-{}", std::process::id()));
    let obj = dir.join("missing.obj");
    let ply = dir.join("missing.ply");
    assert!(matches!(mesh::load(&obj), Err(MeshError::Io { .. })));
    assert!(matches!(mesh::load(&ply), Err(MeshError::Io { .. })));
    assert!(matches!(mesh::load(obj.to_str().unwrap()), Err(MeshError::Io { .. })));
    assert!(matches!(mesh::load(ply.to_str().unwrap()), Err(MeshError::Io { .. })));
    let ball = mesh::builtin("sphere").unwrap();
    match mesh::save(&obj, &ball) {
        Err(MeshError::Io { path, .. }) => assert_eq!(path, obj),
        other => panic!("expected Io, got {other:?}"),
    }
}

#[test]
fn unknown_names_and_extensions_list_the_builtins() {
    for spec in ["teapot", "mesh.stl", "mesh.fbx", "objfile", "bunny.obj.bak", ""] {
        let error = mesh::load(spec).unwrap_err();
        assert!(matches!(error, MeshError::UnsupportedFormat { .. }), "{spec}: {error:?}");
        let message = error.to_string();
        for name in BUILTIN_NAMES {
            assert!(message.contains(name), "{spec}: message {message:?} lacks {name}");
        }
    }
    assert!(matches!(mesh::builtin("bunny.obj"), Err(MeshError::UnsupportedFormat { .. })));
    assert!(matches!(mesh::builtin("Sphere"), Err(MeshError::UnsupportedFormat { .. })));
}

// ---- generator parameters ----------------------------------------------------------------------

#[test]
fn primitive_parameters_are_validated() {
    let invalid = |r: Result<dentbend::TriMesh, MeshError>, what: &str| {
        assert!(matches!(r, Err(MeshError::InvalidParameter(_))), "{what}: {r:?}");
    };
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        invalid(mesh::icosphere(bad, 2), "icosphere radius");
        invalid(mesh::uv_sphere(bad, 8, 4), "uv_sphere radius");
        invalid(mesh::subdivided_box(Vec3::new(1.0, bad, 1.0), [1, 1, 1]), "box size");
        invalid(mesh::plank(bad, 1.0, 1.0, 4), "plank length");
        invalid(mesh::plank(1.0, bad, 1.0, 4), "plank width");
        invalid(mesh::plank(1.0, 1.0, bad, 4), "plank thickness");
        invalid(mesh::cylinder(bad, 1.0, 8, 1), "cylinder radius");
        invalid(mesh::cylinder(1.0, bad, 8, 1), "cylinder height");
    }
    invalid(mesh::icosphere(1.0, 9), "icosphere subdivisions");
    invalid(mesh::uv_sphere(1.0, 2, 4), "uv_sphere segments");
    invalid(mesh::uv_sphere(1.0, 8, 1), "uv_sphere rings");
    invalid(mesh::uv_sphere(1.0, u32::MAX, u32::MAX), "uv_sphere size");
    invalid(mesh::subdivided_box(Vec3::ONE, [1, 0, 1]), "box cells");
    invalid(mesh::subdivided_box(Vec3::ONE, [u32::MAX; 3]), "box size");
    invalid(mesh::plank(1.0, 1.0, 1.0, 0), "plank segments");
    invalid(mesh::plank(1e30, 1e30, 1e-30, u32::MAX), "plank size");
    invalid(mesh::cylinder(1.0, 1.0, 2, 1), "cylinder segments");
    invalid(mesh::cylinder(1.0, 1.0, 8, 0), "cylinder stacks");
    invalid(mesh::cylinder(1.0, 1.0, u32::MAX, u32::MAX), "cylinder size");
}
