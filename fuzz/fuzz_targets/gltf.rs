//! glTF JSON or GLB bytes → mesh, read from memory: a mesh or a typed error, and no file is ever
//! opened (a buffer URI naming a file is refused).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = dentbend::mesh::parse_gltf(data) {
        dentbend_fuzz::assert_valid_mesh(&mesh);
    }
});
