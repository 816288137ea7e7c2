//! Small stand-ins for the built-in meshes, for the `scene_toml` target: the same names and
//! rough shapes at a few dozen triangles, so that building a scene's world stays cheap.

use std::sync::OnceLock;

use dentbend::glam::Vec3;
use dentbend::mesh::{self, TriMesh};

/// Finest `[body.bend] resolution` the scene target builds, cells along the longest side.
pub const MAX_FUZZ_BEND_RESOLUTION: i64 = 16;

/// The stand-in for mesh spec `name`: a built-in name gives a coarse mesh of that shape,
/// `"triangle"` an open surface, anything else an error (no file is read).
///
/// # Errors
/// A message for a name outside that set.
pub fn stand_in(name: &str) -> Result<TriMesh, String> {
    static MESHES: OnceLock<Vec<(&str, TriMesh)>> = OnceLock::new();
    let meshes = MESHES.get_or_init(|| {
        let ball = mesh::icosphere(1.0, 1).expect("icosphere");
        let triangle = TriMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Z], vec![[0, 2, 1]]).expect("triangle");
        vec![
            ("bunny", ball.clone()),
            ("bunny-dense", ball.clone()),
            ("sphere", ball),
            ("uvsphere", mesh::uv_sphere(1.0, 8, 4).expect("uv sphere")),
            ("box", mesh::subdivided_box(Vec3::splat(2.0), [2; 3]).expect("box")),
            ("block", mesh::subdivided_box(Vec3::new(4.0, 1.0, 4.0), [2; 3]).expect("block")),
            ("block-fine", mesh::subdivided_box(Vec3::new(4.0, 1.0, 4.0), [3; 3]).expect("block")),
            ("plank", mesh::plank(8.0, 0.5, 0.25, 8).expect("plank")),
            ("cylinder", mesh::cylinder(0.5, 2.0, 8, 2).expect("cylinder")),
            ("triangle", triangle),
        ]
    });
    meshes
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, m)| m.clone())
        .ok_or_else(|| format!("no mesh named '{name}' among the fuzzer's stand-ins"))
}
