//! Mesh input and output: OBJ round trips, PLY in all three encodings, the built-in meshes.

use std::path::PathBuf;

use dentbend::TriMesh;
use dentbend::glam::{Affine3A, Vec3};
use dentbend::mesh::{self, BUILTIN_NAMES};

/// A fresh path in the system temp directory, unique to this process and `name`.
fn temp_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("dentbend-mesh-io-{}-{name}", std::process::id()))
}

/// Asserts same faces and positions within `rel` of the larger magnitude involved.
fn assert_same_mesh(a: &TriMesh, b: &TriMesh, rel: f32) {
    assert_eq!(a.faces(), b.faces());
    assert_eq!(a.vertex_count(), b.vertex_count());
    for (i, (p, q)) in a.positions().iter().zip(b.positions()).enumerate() {
        let scale = p.abs().max(q.abs()).max_element().max(f32::MIN_POSITIVE);
        assert!((*p - *q).abs().max_element() <= rel * scale, "vertex {i}: {p} vs {q}");
    }
}

#[test]
fn obj_round_trip_preserves_positions_and_faces() {
    let mut ball = mesh::icosphere(0.7, 2).unwrap();
    ball.transform(Affine3A::from_translation(Vec3::new(12.345_678, -0.001_234_5, 1e4))).unwrap();
    for (name, original) in [("ball.obj", ball), ("bunny.OBJ", mesh::builtin("bunny").unwrap())] {
        let path = temp_path(name);
        mesh::save(&path, &original).unwrap();
        let via_load = mesh::load(path.to_str().unwrap());
        let via_load_obj = mesh::load(&path);
        std::fs::remove_file(&path).unwrap();
        // 1e-6 relative: the text form is the shortest that reads back to the same f32, so the
        // round trip is exact in practice; the tolerance only allows for other float formatting.
        assert_same_mesh(&original, &via_load.unwrap(), 1e-6);
        assert_same_mesh(&original, &via_load_obj.unwrap(), 1e-6);
    }
}

#[test]
fn obj_statements_corners_and_polygons() {
    let text = "\
# a unit square pyramid with every corner syntax
mtllib nothing.mtl
o pyramid
v 0 0 0
v 1 0 0 1.0
v 1 0 1 0.5 0.5 0.5
v 0 0 1   # trailing comment
v 0.5 1 0.5
vt 0 0
vn 0 1 0
g base
usemtl none
s off
f 1/1 2/1 3/1 4/1
g sides
f 1//1 5//1 2//1
f 2/1/1 5/1/1 3/1/1
f -2 -1 -3
l 1 2
f 4 5 1
";
    let m = mesh::parse_obj(text).unwrap();
    assert_eq!(m.vertex_count(), 5);
    // The quad base is fan-triangulated from its first corner.
    assert_eq!(m.faces(), &[[0, 1, 2], [0, 2, 3], [0, 4, 1], [1, 4, 2], [3, 4, 2], [3, 4, 0]]);
    assert_eq!(m.positions()[2], Vec3::new(1.0, 0.0, 1.0));
    // A pentagon gives three triangles.
    let pentagon = mesh::parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 2 0\nv 0 1 0\nf 1 2 3 4 5\n").unwrap();
    assert_eq!(pentagon.faces(), &[[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    // CRLF line endings read the same.
    let crlf = mesh::parse_obj(&text.replace('\n', "\r\n")).unwrap();
    assert_eq!(crlf, m);
}

// ---- PLY -------------------------------------------------------------------------------------

/// A typed PLY value, for writing test files in every encoding.
#[derive(Clone, Copy)]
enum V {
    U8(u8),
    I16(i16),
    I32(i32),
    U32(u32),
    F32(f32),
    F64(f64),
}

impl V {
    fn text(self) -> String {
        match self {
            V::U8(v) => v.to_string(),
            V::I16(v) => v.to_string(),
            V::I32(v) => v.to_string(),
            V::U32(v) => v.to_string(),
            V::F32(v) => v.to_string(),
            V::F64(v) => v.to_string(),
        }
    }

    fn bytes(self, big: bool) -> Vec<u8> {
        let le = match self {
            V::U8(v) => vec![v],
            V::I16(v) => v.to_le_bytes().to_vec(),
            V::I32(v) => v.to_le_bytes().to_vec(),
            V::U32(v) => v.to_le_bytes().to_vec(),
            V::F32(v) => v.to_le_bytes().to_vec(),
            V::F64(v) => v.to_le_bytes().to_vec(),
        };
        if big { le.into_iter().rev().collect() } else { le }
    }
}

/// A PLY file: `header_body` is the header between the format line and `end_header`; each entry
/// of `rows` is one element entry (one text line in ASCII).
fn ply(format: &str, header_body: &str, rows: &[Vec<V>]) -> Vec<u8> {
    let mut out =
        format!("ply\nformat {format} 1.0\ncomment written by mesh_io.rs\n{header_body}end_header\n").into_bytes();
    for row in rows {
        match format {
            "ascii" => {
                out.extend(row.iter().map(|v| v.text()).collect::<Vec<_>>().join(" ").bytes());
                out.push(b'\n');
            }
            "binary_little_endian" => row.iter().for_each(|v| out.extend(v.bytes(false))),
            "binary_big_endian" => row.iter().for_each(|v| out.extend(v.bytes(true))),
            _ => unreachable!(),
        }
    }
    out
}

/// Vertex `i` of the unit cube: bit 0 → x, bit 1 → y, bit 2 → z.
fn cube_corner(i: usize) -> [f32; 3] {
    [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32]
}

/// Unit cube quads, counter-clockwise seen from outside.
const CUBE_QUADS: [[u32; 4]; 6] = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]];

/// The unit cube with properties in an odd order, list properties to skip in every element, an
/// extra element in between, uchar/uint/int list types, double and float coordinates.
fn cube_ply(format: &str) -> Vec<u8> {
    let header = "\
element vertex 8
property float nx
property float z
property uchar red
property double x
property list uchar int neighbours
property float y
element edge 2
property int v1
property list uint short extra
property int v2
element face 6
property uchar flags
property list uchar uint vertex_indices
property list int float texcoord
";
    let mut rows = Vec::new();
    for i in 0..8 {
        let [x, y, z] = cube_corner(i);
        rows.push(vec![
            V::F32(0.5),
            V::F32(z),
            V::U8(200),
            V::F64(f64::from(x)),
            V::U8(2),
            V::I32(1),
            V::I32(2),
            V::F32(y),
        ]);
    }
    rows.push(vec![V::I32(0), V::U32(0), V::I32(1)]);
    rows.push(vec![V::I32(2), V::U32(3), V::I16(-1), V::I16(0), V::I16(1), V::I32(3)]);
    for quad in CUBE_QUADS {
        let mut row = vec![V::U8(7), V::U8(4)];
        row.extend(quad.map(V::U32));
        row.extend([V::I32(2), V::F32(0.25), V::F32(0.75)]);
        rows.push(row);
    }
    ply(format, header, &rows)
}

fn expected_cube() -> TriMesh {
    let positions = (0..8).map(|i| Vec3::from_array(cube_corner(i))).collect();
    let faces = CUBE_QUADS.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
    TriMesh::new(positions, faces).unwrap()
}

#[test]
fn ply_ascii_and_both_binaries_parse_to_the_same_mesh() {
    let expected = expected_cube();
    assert!((expected.volume() - 1.0).abs() < 1e-6);
    for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
        let m = mesh::parse_ply(&cube_ply(format)).unwrap_or_else(|e| panic!("{format}: {e}"));
        assert_eq!(m, expected, "{format}");
    }
}

#[test]
fn ply_vertex_index_name_int_coordinates_and_face_first() {
    // Faces before vertices, `vertex_index` with an int count, integer coordinates, a triangle and
    // a quad, CRLF header lines.
    let header = "element face 2\r\nproperty list int int vertex_index\r\nelement vertex 5\r\nproperty short x\r\nproperty short y\r\nproperty short z\r\n";
    let rows = vec![
        vec![V::I32(3), V::I32(0), V::I32(1), V::I32(4)],
        vec![V::I32(4), V::I32(0), V::I32(1), V::I32(2), V::I32(3)],
        vec![V::I16(0), V::I16(0), V::I16(0)],
        vec![V::I16(2), V::I16(0), V::I16(0)],
        vec![V::I16(2), V::I16(2), V::I16(0)],
        vec![V::I16(0), V::I16(2), V::I16(0)],
        vec![V::I16(1), V::I16(-1), V::I16(5)],
    ];
    let meshes: Vec<TriMesh> = ["ascii", "binary_little_endian", "binary_big_endian"]
        .iter()
        .map(|f| mesh::parse_ply(&ply(f, header, &rows)).unwrap())
        .collect();
    assert_eq!(meshes[0].faces(), &[[0, 1, 4], [0, 1, 2], [0, 2, 3]]);
    assert_eq!(meshes[0].positions()[4], Vec3::new(1.0, -1.0, 5.0));
    assert_eq!(meshes[0], meshes[1]);
    assert_eq!(meshes[0], meshes[2]);
}

#[test]
fn load_dispatches_on_case_insensitive_extension() {
    let expected = expected_cube();
    for (name, format) in
        [("cube.ply", "ascii"), ("cube.PLY", "binary_big_endian"), ("cube.Ply", "binary_little_endian")]
    {
        let path = temp_path(name);
        std::fs::write(&path, cube_ply(format)).unwrap();
        let loaded = mesh::load(path.to_str().unwrap());
        let direct = mesh::load(&path);
        std::fs::remove_file(&path).unwrap();
        assert_eq!(loaded.unwrap(), expected, "{name}");
        assert_eq!(direct.unwrap(), expected, "{name}");
    }
}

// ---- built-ins -------------------------------------------------------------------------------

#[test]
fn bunny_is_shipped_in_the_crate() {
    let bunny = mesh::load("bunny").unwrap();
    assert_eq!((bunny.vertex_count(), bunny.face_count()), (1839, 3674));
    let (lo, hi) = bunny.bounds();
    // The npm `bunny` coordinates: y from 0 to 9.66 (to within its 3e-3 rounding), ~10 across.
    assert!(lo.y.abs() < 0.01 && (hi.y - 9.66).abs() < 0.01, "{lo} {hi}");
    assert!((9.0..11.0).contains(&(hi.x - lo.x)), "{lo} {hi}");
    assert_eq!(bunny, mesh::builtin("bunny").unwrap());
}

#[test]
fn bunny_dense_is_the_bunny_subdivided_twice() {
    let dense = mesh::load("bunny-dense").unwrap();
    assert_eq!(dense.face_count(), 58_784);
    let bunny = mesh::builtin("bunny").unwrap();
    // Midpoint subdivision keeps the shape: same bounds, same first vertices.
    assert_eq!(dense.bounds(), bunny.bounds());
    assert_eq!(&dense.positions()[..1839], bunny.positions());
}

#[test]
fn every_builtin_name_loads() {
    for &name in BUILTIN_NAMES {
        let m = mesh::load(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(m.face_count() > 0, "{name}");
        dentbend::mesh::validate(m.positions(), m.faces()).unwrap();
    }
}
