//! PLY bytes (ASCII or binary) → mesh: a mesh or a typed error, and memory bounded by the input
//! whatever counts the header declares.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = dentbend::mesh::parse_ply(data) {
        dentbend_fuzz::assert_valid_mesh(&mesh);
    }
});
