//! The rasterizer's shader parses and validates with naga, on any machine (no GPU needed), has
//! its vertex and fragment entry points, and opens with what it draws, its bindings and vertex
//! layout.

use dentbend_solver::render::RENDER_WGSL;

fn validate(source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
    module
}

#[test]
fn the_render_shader_validates_with_its_entry_points() {
    let module = validate(RENDER_WGSL);
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
fn the_render_shader_file_is_embedded_and_documented() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders/render.wgsl");
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text, RENDER_WGSL, "render.wgsl is embedded as render::RENDER_WGSL");
    assert!(text.starts_with("//"), "render.wgsl must open with a comment");
    for topic in ["bindings", "vertex layout"] {
        assert!(text.to_lowercase().contains(topic), "render.wgsl must state its {topic}");
    }
}
