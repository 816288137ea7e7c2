//! OBJ text → mesh: any bytes (lossily decoded as `load_obj` does) give a mesh or a typed error.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = dentbend::mesh::parse_obj(&String::from_utf8_lossy(data)) {
        dentbend_fuzz::assert_valid_mesh(&mesh);
    }
});
