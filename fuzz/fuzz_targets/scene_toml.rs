//! Scene-file text → scene: parsed, every field checked and the world built, or one typed
//! error. Meshes come from `parse_scene_with_meshes` with small stand-ins for the built-in names
//! (nothing is read from disk, and a valid scene builds in well under a millisecond).
//!
//! A bending body's level set costs resolution³ cells (up to 17.6 M), so inputs whose
//! `[body.bend]` would build one finer than `MAX_FUZZ_BEND_RESOLUTION` are skipped: the fuzzer
//! learns to write a small `resolution` to reach the bending code.
#![no_main]

use std::path::Path;

use dentbend_fuzz::scene_meshes::{MAX_FUZZ_BEND_RESOLUTION, stand_in};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(table) = toml::from_str::<toml::Table>(text)
        && !bend_resolutions_at_most(&table, MAX_FUZZ_BEND_RESOLUTION)
    {
        return;
    }
    let result = dentbend_solver::scene::parse_scene_with_meshes(text, Path::new("fuzz.toml"), &mut stand_in);
    if let Ok(scene) = result {
        assert!(scene.frames > 0, "a scene with no frames was accepted");
        assert!(scene.camera.eye.is_finite() && scene.camera.target.is_finite(), "a non-finite camera");
    }
});

/// Whether every `[body.bend]` table gives a `resolution` of at most `max` (its default, 64,
/// is more). Anything that is not such a table is left to the parser to refuse.
fn bend_resolutions_at_most(table: &toml::Table, max: i64) -> bool {
    let Some(toml::Value::Array(bodies)) = table.get("body") else { return true };
    bodies.iter().filter_map(|body| body.get("bend")).all(|bend| match bend.get("resolution") {
        Some(toml::Value::Integer(n)) => *n <= max,
        Some(_) => true,
        None => !bend.is_table(),
    })
}
