//! The built-in meshes, usable wherever a mesh path is accepted, and [`load`], which resolves a
//! mesh spec (built-in name or file path) to a mesh.

use std::path::Path;

use glam::Vec3;

#[cfg(feature = "io")]
use super::gltf_read::load_gltf;
use super::obj::{load_obj, parse_obj_named};
use super::ply::load_ply;
use super::primitives::{cylinder, icosphere, plank, subdivided_box, uv_sphere};
use super::subdivide::subdivide_midpoint_n;
use super::{MeshError, TriMesh};

/// The Stanford bunny as shipped in the npm package `bunny` 1.0.1 (public domain).
const BUNNY_OBJ: &str = include_str!("../../assets/meshes/bunny.obj");

/// Names accepted by [`builtin`] and [`load`]; see [`builtin`] for each one's size.
pub const BUILTIN_NAMES: &[&str] =
    &["bunny", "bunny-dense", "sphere", "uvsphere", "box", "block", "block-fine", "plank", "cylinder", "crate"];

/// Builds a built-in mesh by name (world units; all but the bunny are closed and centred at the
/// origin):
///
/// | name          | shape                                                                  | triangles |
/// |---------------|------------------------------------------------------------------------|-----------|
/// | `bunny`       | Stanford bunny, about 10 across, y from 0 to 9.66, 1839 vertices       | 3,674     |
/// | `bunny-dense` | `bunny` midpoint-subdivided twice (same shape, a dent target)          | 58,784    |
/// | `sphere`      | icosphere of radius 1, 4 subdivisions, 2562 vertices                   | 5,120     |
/// | `uvsphere`    | latitude-longitude sphere of radius 1, 64 segments × 32 rings          | 3,968     |
/// | `box`         | 2 × 2 × 2 cube, 16 × 16 cells per face                                 | 3,072     |
/// | `block`       | slab 4 (x) × 1 (y) × 4 (z), top face y = +0.5, 64 × 16 × 64 cells      | 24,576    |
/// | `block-fine`  | `block` with 112 × 8 × 112 cells (0.036 apart), for detailed dents     | 57,344    |
/// | `plank`       | 8 (x) × 0.25 (y) × 0.5 (z), 128 cells along x (square cells)           | 6,272     |
/// | `cylinder`    | radius 0.5, height 2 along y, 48 segments, 16 stacks, 8-ring caps      | 2,976     |
/// | `crate`       | 2 × 2 × 2 cube, one cell per face, 24 vertices split at its hard edges | 12        |
///
/// # Errors
/// [`MeshError::UnsupportedFormat`] for any other name (its message lists the valid ones).
///
/// # Example
/// ```
/// let ball = dentbend::mesh::builtin("sphere").unwrap();
/// assert_eq!(ball.face_count(), 5120);
/// ```
pub fn builtin(name: &str) -> Result<TriMesh, MeshError> {
    match name {
        "bunny" => parse_obj_named(BUNNY_OBJ, Path::new("<built-in bunny>")),
        "bunny-dense" => Ok(subdivide_midpoint_n(&builtin("bunny")?, 2)),
        "sphere" => icosphere(1.0, 4),
        "uvsphere" => uv_sphere(1.0, 64, 32),
        "box" => subdivided_box(Vec3::splat(2.0), [16; 3]),
        "block" => subdivided_box(Vec3::new(4.0, 1.0, 4.0), [64, 16, 64]),
        "block-fine" => subdivided_box(Vec3::new(4.0, 1.0, 4.0), [112, 8, 112]),
        "plank" => plank(8.0, 0.5, 0.25, 128),
        "cylinder" => cylinder(0.5, 2.0, 48, 16),
        "crate" => Ok(super::builtin_crate::crate_asset().into_parts().0),
        _ => Err(unsupported(Path::new(name))),
    }
}

/// Loads a mesh from a spec: a built-in name (see [`builtin`]; a name wins over a file of the same
/// name) or the path of a `.obj`, `.ply`, `.gltf` or `.glb` file (extension case-insensitive),
/// the one way to read a mesh file ([`parse_obj`](super::parse_obj),
/// [`parse_ply`](super::parse_ply) and `parse_gltf` read bytes already in memory).
///
/// # Errors
/// [`MeshError::UnsupportedFormat`] (listing the built-in names) for anything else;
/// [`MeshError::Io`] for a file that cannot be read; [`MeshError::Parse`] (with the file and line
/// or byte) or a validation error for its contents. glTF needs the `io` feature; without it a
/// glTF file is an unsupported format.
///
/// # Example
/// ```
/// let bunny = dentbend::mesh::load("bunny").unwrap();
/// assert_eq!(bunny.face_count(), 3674);
/// ```
pub fn load(spec: impl AsRef<Path>) -> Result<TriMesh, MeshError> {
    let path = spec.as_ref();
    if let Some(name) = path.to_str().filter(|s| BUILTIN_NAMES.contains(s)) {
        return builtin(name);
    }
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("obj") => load_obj(path),
        Some("ply") => load_ply(path),
        #[cfg(feature = "io")]
        Some("gltf" | "glb") => load_gltf(path),
        _ => Err(unsupported(path)),
    }
}

pub(crate) fn unsupported(spec: &Path) -> MeshError {
    MeshError::UnsupportedFormat { path: spec.to_path_buf(), builtins: BUILTIN_NAMES.join(", ") }
}
