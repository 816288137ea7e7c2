//! Every WGSL kernel, and the render shader, parses and validates with naga, on any machine (no
//! GPU needed).

use dentbend::gpu::{SHADERS, SHARED_WGSL, shader_source};
use dentbend::render::RENDER_WGSL;

/// The stem of the render shader: vertex and fragment stages, not a compute kernel, so it is not
/// in `gpu::SHADERS` and has no dispatch geometry.
const RENDER_STEM: &str = "render";

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
fn the_render_shader_validates_with_its_entry_points() {
    let module =
        naga::front::wgsl::parse_str(RENDER_WGSL).unwrap_or_else(|e| panic!("{}", e.emit_to_string(RENDER_WGSL)));
    validate("render.wgsl", RENDER_WGSL);
    for (name, stage) in [
        ("vs_background", naga::ShaderStage::Vertex),
        ("fs_background", naga::ShaderStage::Fragment),
        ("vs_mesh", naga::ShaderStage::Vertex),
        ("fs_mesh", naga::ShaderStage::Fragment),
    ] {
        assert!(module.entry_points.iter().any(|e| e.name == name && e.stage == stage), "render.wgsl lacks {name}");
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
            if stem == RENDER_STEM {
                // The render shader opens with what it draws, its bindings and vertex layout.
                assert_eq!(text, RENDER_WGSL, "render.wgsl is embedded as render::RENDER_WGSL");
                for topic in ["bindings", "vertex layout"] {
                    assert!(text.to_lowercase().contains(topic), "render.wgsl must state its {topic}");
                }
                continue;
            }
            assert!(SHADERS.iter().any(|(s, _)| *s == stem), "{stem}.wgsl is not in gpu::SHADERS");
            // Each kernel opens with what it computes and how it is dispatched.
            assert!(text.to_lowercase().contains("dispatch"), "{stem}.wgsl must state its dispatch geometry");
        }
    }
}
