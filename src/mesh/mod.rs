//! Triangle meshes: the [`TriMesh`] type, file input and output, procedural primitives and the
//! built-in meshes that work wherever a mesh path is accepted.

mod error;
mod trimesh;

pub use error::MeshError;
pub use trimesh::{TriMesh, validate};

/// Loads a built-in mesh by name.
pub fn builtin(name: &str) -> Result<TriMesh, MeshError> {
    let _ = name;
    todo!("builtin meshes: being written")
}
