//! The built-in `crate`: a 2 × 2 × 2 cube of 12 triangles with split vertices at its hard
//! edges, as game engines build a cube: four vertices per side, each with its side's normal and
//! UVs spanning the side.

use glam::{Vec2, Vec3};

use super::asset::{FaceGroup, VertexAttributes};
use super::{Asset, TriMesh};

/// Each side's outward normal and two axes u, v with u × v = normal.
const SIDES: [[Vec3; 3]; 6] = [
    [Vec3::X, Vec3::Y, Vec3::Z],
    [Vec3::NEG_X, Vec3::Z, Vec3::Y],
    [Vec3::Y, Vec3::Z, Vec3::X],
    [Vec3::NEG_Y, Vec3::X, Vec3::Z],
    [Vec3::Z, Vec3::X, Vec3::Y],
    [Vec3::NEG_Z, Vec3::Y, Vec3::X],
];

/// The crate as an asset: 24 vertices (side s has vertices 4s..4s + 4 at UVs (0, 0), (1, 0),
/// (1, 1), (0, 1) along its u and v axes), 12 triangles (side s has faces 2s and 2s + 1),
/// authored normals one per side, one unnamed group; centred at the origin, metres.
pub(crate) fn crate_asset() -> Asset {
    let mut positions = Vec::with_capacity(24);
    let (mut normals, mut uvs, mut faces) = (Vec::with_capacity(24), Vec::with_capacity(24), Vec::with_capacity(12));
    for (s, [n, u, v]) in SIDES.into_iter().enumerate() {
        let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        for (a, b) in corners {
            positions.push(n + a * u + b * v);
            normals.push(n);
            uvs.push(Vec2::new((a + 1.0) / 2.0, (b + 1.0) / 2.0));
        }
        let k = 4 * s as u32;
        faces.extend([[k, k + 1, k + 2], [k, k + 2, k + 3]]);
    }
    let mesh = TriMesh::from_valid(positions, faces);
    let attributes = VertexAttributes { uvs: vec![uvs], normals: Some(normals), ..VertexAttributes::default() };
    Asset::new(mesh, attributes, vec![FaceGroup::default()], vec![0; 12]).expect("the crate's attributes fit it")
}
