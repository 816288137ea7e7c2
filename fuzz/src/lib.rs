//! Checks shared by the fuzz targets: what every mesh a loader returns must satisfy.

use dentbend::mesh::TriMesh;

/// Panics (a fuzzing failure) unless `mesh` keeps the invariants of [`TriMesh`]: at least one
/// face, every face index in range and every position and normal finite.
pub fn assert_valid_mesh(mesh: &TriMesh) {
    assert!(mesh.face_count() > 0, "a loader returned a mesh without faces");
    if let Err(e) = dentbend::mesh::validate(mesh.positions(), mesh.faces()) {
        panic!("a loader returned a mesh that fails validation: {e}");
    }
    assert_eq!(mesh.normals().len(), mesh.vertex_count(), "one normal per vertex");
    assert!(mesh.normals().iter().all(|n| n.is_finite()), "a loader returned a non-finite normal");
}

/// Panics unless every position and normal of `mesh` is finite.
pub fn assert_finite_mesh(mesh: &TriMesh) {
    if let Some(i) = mesh.positions().iter().position(|p| !p.is_finite()) {
        panic!("vertex {i} is not finite: {}", mesh.positions()[i]);
    }
    if let Some(i) = mesh.normals().iter().position(|n| !n.is_finite()) {
        panic!("normal {i} is not finite: {}", mesh.normals()[i]);
    }
}

/// Every bit of `mesh`: positions, normals and faces, for a bit-for-bit comparison.
pub fn fingerprint(mesh: &TriMesh) -> Vec<u32> {
    let vectors = mesh.positions().iter().chain(mesh.normals());
    let mut bits: Vec<u32> = vectors.flat_map(|v| v.to_array().map(f32::to_bits)).collect();
    bits.extend(mesh.faces().iter().flatten());
    bits
}

pub mod dent_input;
pub mod scene_meshes;
