//! Every WGSL kernel parses and validates with naga, on any machine (no GPU needed).

use dentbend::gpu::{SHADERS, SHARED_WGSL, shader_source};

fn validate(label: &str, source: &str) {
    let module =
        naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{label}: {}", e.emit_to_string(source)));
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{label}: {}", e.emit_to_string(source)));
}

#[test]
fn every_shader_validates() {
    validate("shared/layout.wgsl", SHARED_WGSL);
    for (stem, _) in SHADERS {
        validate(stem, &shader_source(stem).unwrap());
    }
}

#[test]
fn every_shader_file_is_embedded_and_documented() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "wgsl") {
            let stem = path.file_stem().unwrap().to_str().unwrap().to_owned();
            let text = std::fs::read_to_string(&path).unwrap();
            assert!(text.starts_with("//"), "{stem}.wgsl must open with a comment");
            assert!(SHADERS.iter().any(|(s, _)| *s == stem), "{stem}.wgsl is not in gpu::SHADERS");
            // Each kernel opens with what it computes and how it is dispatched.
            assert!(text.to_lowercase().contains("dispatch"), "{stem}.wgsl must state its dispatch geometry");
        }
    }
}
