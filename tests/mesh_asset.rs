//! Assets in OBJ: a round trip keeps texture coordinates, normals, objects, groups, materials,
//! smoothing groups and material libraries exactly; a `v` used with two `vt`s becomes two
//! vertices; bad attributes and hostile files give typed errors and change nothing.

use dentbend::MeshError;
use dentbend::glam::{Vec2, Vec3, Vec4};
use dentbend::mesh::{Asset, FaceGroup, VertexAttributes, obj_asset_text, parse_obj, parse_obj_asset};

/// Two quads folded along x = 1 (a hard edge: each side has its own `vn`), the right one
/// textured from a second island so vertex 2 and 3 are used with two `vt`s each.
const FOLDED: &str = "\
# folded card
mtllib card.mtl extra.mtl
o card
v 0 0 0
v 0 1 0
v 1 0 0
v 1 1 0
v 1.5 0 -0.8660254
v 1.5 1 -0.8660254
vt 0 0
vt 0 1
vt 0.5 0
vt 0.5 1
vt 0.25 0.125
vt 0.25 0.875
vt 0.75 0.125
vt 0.75 0.875
vn 0 0 1
vn 0.8660254 0 0.5
g left
usemtl paper
s off
f 1/1/1 3/3/1 4/4/1 2/2/1
g right
usemtl ink
s 1
f 3/5/2 5/7/2 6/8/2 4/6/2
";

#[test]
fn obj_round_trip_keeps_uvs_normals_groups_and_materials_exactly() {
    let asset = parse_obj_asset(FOLDED).unwrap();
    // v 3 and v 4 are used with two vt/vn pairs: two more vertices, at the same positions.
    assert_eq!(asset.mesh().vertex_count(), 8);
    assert_eq!(asset.mesh().face_count(), 4);
    let positions = asset.mesh().positions();
    assert_eq!(positions[6].to_array().map(f32::to_bits), positions[2].to_array().map(f32::to_bits));
    assert_eq!(positions[7].to_array().map(f32::to_bits), positions[3].to_array().map(f32::to_bits));
    let uvs = &asset.attributes().uvs[0];
    assert_eq!((uvs[2], uvs[6]), (Vec2::new(0.5, 0.0), Vec2::new(0.25, 0.125)));
    let normals = asset.attributes().normals.as_ref().unwrap();
    assert_eq!((normals[2], normals[6]), (Vec3::Z, Vec3::new(0.866_025_4, 0.0, 0.5)));
    let groups = asset.groups();
    assert_eq!(groups.len(), 2);
    let left = FaceGroup {
        object: Some("card".into()),
        group: Some("left".into()),
        material: Some("paper".into()),
        material_index: None,
        smoothing: Some("off".into()),
    };
    assert_eq!(groups[0], left);
    assert_eq!((groups[1].material.as_deref(), groups[1].smoothing.as_deref()), (Some("ink"), Some("1")));
    assert_eq!(asset.face_groups(), [0, 0, 1, 1]);
    assert_eq!(asset.material_libraries(), ["card.mtl extra.mtl"]);

    // Written and read again: the same asset, bit for bit, statements in order.
    let text = obj_asset_text(&asset);
    assert_eq!(parse_obj_asset(&text).unwrap(), asset, "{text}");
    let statements: Vec<&str> =
        text.lines().filter(|l| ["mtllib", "o ", "g ", "usemtl", "s "].iter().any(|k| l.starts_with(k))).collect();
    assert_eq!(
        statements,
        ["mtllib card.mtl extra.mtl", "o card", "g left", "usemtl paper", "s off", "g right", "usemtl ink", "s 1"]
    );
    assert_eq!(text.lines().filter(|l| l.starts_with("vt ")).count(), 8);
    assert_eq!(text.lines().filter(|l| l.starts_with("vn ")).count(), 8);
    // The plain reader still reads the same file as before: one vertex per `v`.
    assert_eq!(parse_obj(FOLDED).unwrap().vertex_count(), 6);
}

#[test]
fn a_plain_obj_keeps_its_vertex_order_and_gains_no_attributes() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4\nf 1 4 3\n";
    let asset = parse_obj_asset(text).unwrap();
    assert_eq!(asset.mesh(), &parse_obj(text).unwrap());
    assert_eq!(asset.attributes(), &VertexAttributes::default());
    assert_eq!(asset.groups(), [FaceGroup::default()]);
}

#[test]
fn wrong_attribute_lengths_and_values_are_typed_errors_and_change_nothing() {
    let mut asset = parse_obj_asset(FOLDED).unwrap();
    let before = asset.clone();
    let mesh = asset.mesh().clone();
    let short = VertexAttributes { uvs: vec![vec![Vec2::ZERO; 7]], ..VertexAttributes::default() };
    match asset.set_attributes(short.clone()) {
        Err(MeshError::AttributeLength { attribute, expected: 8, actual: 7 }) => assert_eq!(attribute, "uv set 0"),
        other => panic!("expected AttributeLength, got {other:?}"),
    }
    let groups = vec![FaceGroup::default()];
    assert!(matches!(
        Asset::new(mesh.clone(), short, groups.clone(), vec![0; 4]),
        Err(MeshError::AttributeLength { expected: 8, actual: 7, .. })
    ));
    let mut colours = vec![Vec4::ONE; 8];
    colours[5].y = f32::NAN;
    let nan = VertexAttributes { colors: vec![colours], ..VertexAttributes::default() };
    match asset.set_attributes(nan) {
        Err(MeshError::AttributeValue { attribute, index: 5, .. }) => assert_eq!(attribute, "colour set 0"),
        other => panic!("expected AttributeValue, got {other:?}"),
    }
    let tangents = VertexAttributes { tangents: Some(vec![Vec4::X; 9]), ..VertexAttributes::default() };
    assert!(matches!(asset.set_attributes(tangents), Err(MeshError::AttributeLength { expected: 8, actual: 9, .. })));
    assert!(matches!(
        Asset::new(mesh.clone(), VertexAttributes::default(), groups.clone(), vec![0; 3]),
        Err(MeshError::AttributeLength { expected: 4, actual: 3, .. })
    ));
    assert!(matches!(
        Asset::new(mesh, VertexAttributes::default(), groups, vec![0, 0, 0, 1]),
        Err(MeshError::AttributeValue { index: 3, .. })
    ));
    assert_eq!(asset, before, "a failed change left the asset changed");
}

#[test]
fn hostile_obj_gives_parse_errors_with_the_line() {
    let base = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
    let cases = [
        ("f 1/2 2/1 3/1\n", "line 6", "texture coordinate index 2"),
        ("f 1//2 2//1 3//1\n", "line 6", "normal index 2"),
        ("f 1/0 2/1 3/1\n", "line 6", "index 0"),
        ("f 1/-2 2/1 3/1\n", "line 6", "out of range"),
        ("f 1 2 9\n", "line 6", "vertex index 9"),
        ("f 1/1/1/1 2 3\n", "line 6", "more than three"),
        ("vt nan 0\n", "line 6", "not finite"),
        ("vn 0 inf 0\n", "line 6", "not finite"),
        ("v 1e39 0 0\n", "line 6", "not finite"),
        ("vt\n", "line 6", "at least 1"),
        ("f 1/x 2 3\n", "line 6", "not a texture coordinate index"),
        ("f 1 99999999999999999999 3\n", "line 6", "not a vertex index"),
    ];
    for (tail, line, what) in cases {
        match parse_obj_asset(&format!("{base}{tail}")) {
            Err(MeshError::Parse { message, .. }) => {
                assert!(message.contains(line) && message.contains(what), "{tail:?}: {message}")
            }
            other => panic!("{tail:?}: expected a parse error, got {other:?}"),
        }
    }
}
