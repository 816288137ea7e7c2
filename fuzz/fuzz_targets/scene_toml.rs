//! Scene-file text → scene: parsed, every field checked, meshes resolved (built-in names; a
//! path resolves against a folder that does not exist) and the world built, or one typed error.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(scene) = dentbend::scene::parse_scene(text, Path::new("/nonexistent-fuzz-folder/fuzz.toml")) {
        assert!(scene.frames > 0, "a scene with no frames was accepted");
        assert!(scene.camera.eye.is_finite() && scene.camera.target.is_finite(), "a non-finite camera");
    }
});
