//! What fuzzing (fuzz/, cargo-fuzz) relies on and what it found, as plain stable tests: the
//! in-memory entry points read what the file loaders read and touch no file, the committed seed
//! corpus holds the valid and near-valid files it claims to, and every input that once crashed a
//! target is now a typed error.

mod common;

use common::TempDir;
use dentbend::glam::Vec3;
use dentbend::mesh::{self, MeshError};
use dentbend::{DentError, DentMap, DentParams, Impact};

/// A seed of the committed corpus, `fuzz/corpus/<target>/<name>`.
fn seed(target: &str, name: &str) -> Vec<u8> {
    let path = format!("{}/../fuzz/corpus/{target}/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read(&path).unwrap_or_else(|e| panic!("seed {path}: {e}"))
}

/// The bits of a mesh's positions and faces, for exact comparison.
fn bits(mesh: &dentbend::TriMesh) -> (Vec<[u32; 3]>, Vec<[u32; 3]>) {
    (mesh.positions().iter().map(|p| p.to_array().map(f32::to_bits)).collect(), mesh.faces().to_vec())
}

#[test]
fn parse_gltf_reads_what_load_gltf_reads() {
    let dir = TempDir::new("fuzz-gltf");
    for name in ["tetra_data_uri.gltf", "tetra_two_nodes.gltf", "tetra.glb", "tetra_strip.glb"] {
        let bytes = seed("gltf", name);
        let path = dir.path(name);
        std::fs::write(&path, &bytes).unwrap();
        let from_file = mesh::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let from_memory = mesh::parse_gltf(&bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(bits(&from_memory), bits(&from_file), "{name}");
    }
}

#[test]
fn parse_gltf_refuses_a_buffer_that_names_a_file() {
    // The same document with a buffer URI pointing up and out of any folder: from memory there
    // is no folder, so the URI is refused before any path is built.
    let error = mesh::parse_gltf(&seed("gltf", "outside_uri.gltf")).unwrap_err();
    let MeshError::Parse { format: "glTF", message, .. } = &error else { panic!("{error:?}") };
    assert!(message.contains("buffer 0") && message.contains("names a file"), "{message}");
    assert!(!message.contains("root:"), "the message must not hold file contents: {message}");
}

#[test]
fn seeds_of_the_mesh_targets_parse_as_labelled() {
    let faces = |result: Result<dentbend::TriMesh, MeshError>| result.map(|m| m.face_count());
    let obj = |name| faces(mesh::parse_obj(&String::from_utf8_lossy(&seed("obj", name))));
    let ply = |name| faces(mesh::parse_ply(&seed("ply", name)));
    let gltf = |name| faces(mesh::parse_gltf(&seed("gltf", name)));
    assert_eq!(obj("triangle.obj").unwrap(), 1);
    assert_eq!(obj("cube_quads.obj").unwrap(), 12);
    assert_eq!(obj("crlf.obj").unwrap(), 1);
    assert_eq!(obj("relative.obj").unwrap(), 3);
    for name in ["exponents.obj", "index_zero.obj", "index_huge.obj", "short_vertex.obj"] {
        assert!(obj(name).is_err(), "{name} is a near-valid seed and must be refused");
    }
    for name in ["tetra_ascii.ply", "tetra_le.ply", "tetra_be.ply"] {
        assert_eq!(ply(name).unwrap(), 4, "{name}");
    }
    assert_eq!(ply("quad_mixed.ply").unwrap(), 2);
    for name in ["huge_count.ply", "huge_list.ply", "negative_index.ply", "truncated.ply"] {
        assert!(ply(name).is_err(), "{name} is a near-valid seed and must be refused");
    }
    assert_eq!(gltf("tetra_data_uri.gltf").unwrap(), 4);
    assert_eq!(gltf("tetra_two_nodes.gltf").unwrap(), 8);
    assert_eq!(gltf("tetra.glb").unwrap(), 4);
    for name in ["outside_uri.gltf", "huge_count.gltf", "cycle.gltf"] {
        assert!(gltf(name).is_err(), "{name} is a near-valid seed and must be refused");
    }
}

#[test]
fn png_bytes_give_the_dent_map_the_png_file_gives() {
    let dir = TempDir::new("fuzz-png");
    let impact = Impact { point: Vec3::new(0.0, 0.5, 0.0), normal: -Vec3::Y, relative_velocity: -Vec3::Y };
    let params = DentParams::new(0.1);
    // The dentmap_png seeds start with two bytes of the target's own (extent and angle).
    for name in ["gray8_16.png", "gray16_8.png", "rgb8_5.png", "graya8_4.png", "rgba16_3.png", "gray1_8.png"] {
        let png = seed("dentmap_png", name)[2..].to_vec();
        let path = dir.path(name);
        std::fs::write(&path, &png).unwrap();
        let from_file = DentMap::from_png(&path, 0.5, &impact, &params).unwrap_or_else(|e| panic!("{name}: {e}"));
        let from_bytes = DentMap::from_png_bytes(&png, 0.5, &impact, &params).unwrap();
        assert_eq!(from_bytes, from_file, "{name}");
    }
    for name in ["black_4.png", "not_square.png", "huge_header.png"] {
        let png = seed("dentmap_png", name)[2..].to_vec();
        let error = DentMap::from_png_bytes(&png, 0.5, &impact, &params).unwrap_err();
        assert!(matches!(error, DentError::Image { .. }), "{name}: {error:?}");
    }
}

#[test]
fn a_key_after_multibyte_text_is_a_scene_error_not_a_panic() {
    // Found by the scene_toml target: a syntax error after `ʎ=` made the error locator slice the
    // text inside the two-byte character while looking for the key before the `=`.
    for text in ["ʎ=\nf", "name = \"x\"\nbodyʎ= [\n", "a = { ʎ= 1 }\n[[[", "\u{1}\u{0}jʎ = \"a\"stic\nf"] {
        let error = dentbend_solver::scene::parse_scene(text, std::path::Path::new("fuzz.toml")).unwrap_err();
        assert!(matches!(error, dentbend_solver::scene::SceneError::Invalid { .. }), "{text:?}: {error:?}");
    }
}

#[test]
fn parse_scene_with_meshes_asks_the_resolver_once_per_mesh_and_reads_nothing() {
    let text = "[[body]]\nname = \"a\"\nmesh = \"ball\"\n[[body]]\nname = \"b\"\nmesh = \"ball\"\nposition = [3, 0, 0]\n\
                [[body]]\nname = \"c\"\nmesh = \"../../etc/passwd\"\n";
    let mut asked = Vec::new();
    let mut resolve = |name: &str| {
        asked.push(name.to_owned());
        match name {
            "ball" => mesh::icosphere(0.5, 1).map_err(|e| e.to_string()),
            other => Err(format!("no mesh '{other}' here")),
        }
    };
    let error = dentbend_solver::scene::parse_scene_with_meshes(text, std::path::Path::new("s.toml"), &mut resolve)
        .unwrap_err();
    assert_eq!(asked, ["ball", "../../etc/passwd"], "each distinct mesh spec is asked for once");
    let message = error.to_string();
    assert!(message.starts_with("s.toml:10:8: body \"c\": mesh:") && message.contains("no mesh"), "{message}");

    let scene = dentbend_solver::scene::parse_scene_with_meshes(
        &text[..text.find("[[body]]\nname = \"c\"").unwrap()],
        std::path::Path::new("s.toml"),
        &mut |_: &str| mesh::icosphere(0.5, 1).map_err(|e| e.to_string()),
    )
    .unwrap();
    assert_eq!(scene.world.bodies().len(), 2);
    assert_eq!(scene.world.bodies()[0].mesh().face_count(), 80, "the resolver's mesh is used as given");
}

/// An 8-bit grey PNG of `side × side` black pixels but one white one, compressed by zlib.
fn big_black_png(side: u32) -> Vec<u8> {
    let mut png = Vec::new();
    let encoder = image::codecs::png::PngEncoder::new(&mut png);
    let mut pixels = vec![0u8; (side * side) as usize];
    pixels[0] = 255;
    image::ImageEncoder::write_image(encoder, &pixels, side, side, image::ExtendedColorType::L8).unwrap();
    png
}

#[test]
fn a_dent_map_picture_over_the_largest_grid_is_refused_before_decoding() {
    // The dentmap_png target's memory peaked at 381 MB on inputs of at most 64 KB: a picture was
    // decoded whole (within the image crate's 512 MiB budget) before it was found too big for a
    // dent map. The header's size is now checked first.
    let impact = Impact { point: Vec3::ZERO, normal: -Vec3::Y, relative_velocity: -Vec3::Y };
    let params = DentParams::new(0.1);
    let png = big_black_png(dentbend::dent::MAX_RESOLUTION + 1);
    let error = DentMap::from_png_bytes(&png, 1.0, &impact, &params).unwrap_err();
    assert!(error.to_string().contains("larger than 2048×2048 pixels"), "{error}");
    let dir = TempDir::new("fuzz-big-png");
    std::fs::write(dir.path("big.png"), &png).unwrap();
    let error = DentMap::from_png(dir.path("big.png"), 1.0, &impact, &params).unwrap_err();
    assert!(error.to_string().contains("larger than 2048×2048 pixels"), "{error}");
    // A picture within the limit still reads.
    let png = big_black_png(64);
    assert_eq!(DentMap::from_png_bytes(&png, 1.0, &impact, &params).unwrap().dent_distance, 0.1);
}

#[test]
fn a_dent_of_huge_distance_reports_a_finite_displacement_or_is_refused() {
    // Found by the dent_api target: a dent distance of 4.7e35 moved vertices by about 1e35 (still
    // finite) and reported a max_displacement of inf, the f32 distance overflowing on the way.
    let mut target = mesh::icosphere(0.3, 1).unwrap();
    let mut projectile = mesh::builtin("sphere").unwrap();
    let offset = Vec3::new(3.0 / 256.0, 16633.0 / 256.0, f32::from_bits(1_289_252));
    projectile.transform(dentbend::glam::Affine3A::from_translation(offset)).unwrap();
    let impact = Impact {
        point: Vec3::new(10.0, f32::MIN_POSITIVE, 15973.0 / 256.0),
        normal: Vec3::new(0.0, 42252.0 / 256.0, f32::MAX),
        relative_velocity: Vec3::ZERO,
    };
    let params = DentParams {
        resolution: dentbend::Resolution::Auto { min: 8, max: 48 },
        heat_iters: 0,
        clamp_iters: 32,
        heat_rate: f32::MIN_POSITIVE,
        min_cos: 234.0 / 256.0,
        ..DentParams::new(f32::from_bits(2_058_848_511))
    };
    let before = bits(&target);
    match dentbend::dent(&mut target, &projectile, &impact, &params) {
        Ok(report) => {
            assert!(report.max_displacement.is_finite(), "{report:?}");
            assert!(target.positions().iter().all(|p| p.is_finite()));
        }
        Err(error) => {
            assert!(matches!(error, DentError::InvalidParameter { name: "dent_distance", .. }), "{error:?}");
            assert_eq!(bits(&target), before, "a refused dent leaves its target as it was");
        }
    }
}
