//! `dentbend run` writes the rest state of every bending body once, under `rest/`: pictures of
//! its skeleton, sub-bodies and level set (paper Figure 12) and its sub-body meshes, all listed
//! in `summary.json`; nothing for scenes without bending bodies.

mod common;

use std::collections::HashMap;
use std::path::Path;

use common::temp::TempDir;
use common::{dentbend, text};
use dentbend_solver::render::bone_colour;

/// Runs `dentbend run` with `args` into `out`, failing on an error; returns `summary.json`.
fn run(args: &[&str], out: &Path) -> serde_json::Value {
    let output = dentbend(&[&["run"], args, &["--out", out.to_str().unwrap()]].concat());
    assert!(output.status.success(), "{}", text(&output.stderr));
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

/// The strings of a JSON array.
fn strings(value: &serde_json::Value) -> Vec<&str> {
    value.as_array().unwrap().iter().map(|v| v.as_str().unwrap()).collect()
}

/// 8-bit sRGB of a linear colour, as the pictures store it.
fn srgb8(linear: [f32; 3]) -> [u8; 3] {
    linear.map(|c| {
        let s = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
        (s * 255.0).round() as u8
    })
}

/// Pixel counts per colour.
fn histogram(picture: &image::RgbImage) -> HashMap<[u8; 3], usize> {
    let mut counts = HashMap::new();
    picture.pixels().for_each(|p| *counts.entry(p.0).or_insert(0) += 1);
    counts
}

/// Whether `picture` has a pixel within 1 of `colour` in every channel.
fn has_colour(picture: &image::RgbImage, colour: [u8; 3]) -> bool {
    picture.pixels().any(|p| p.0.iter().zip(colour).all(|(&a, b)| a.abs_diff(b) <= 1))
}

#[test]
fn bunny_bones_writes_its_skeleton_sub_bodies_and_level_set() {
    let dir = TempDir::new("run-rest");
    let out = dir.path("bunny");
    let summary =
        run(&["bunny-bones", "--size", "demo", "--frames", "2", "--every", "2", "--picture", "240,160"], &out);
    let pictures = ["rest/bunny_skeleton.png", "rest/bunny_sub_bodies.png", "rest/bunny_level_set.png"];
    assert_eq!(strings(&summary["rest_pictures"]), pictures);
    let meshes: Vec<String> = (0..4).map(|k| format!("rest/bunny_sub{k}.obj")).collect();
    assert_eq!(strings(&summary["rest_meshes"]), meshes);
    let bones: Vec<[u8; 3]> = (0..4).map(|k| srgb8(bone_colour(k))).collect();
    for file in pictures {
        let picture = image::open(out.join(file)).unwrap_or_else(|e| panic!("{file}: {e}")).to_rgb8();
        assert_eq!(picture.dimensions(), (240, 160), "{file}");
        // Not one colour: the background covers less than 95 % and there are many shades.
        let counts = histogram(&picture);
        let most = counts.values().max().copied().unwrap_or(0);
        let pixels = (picture.width() * picture.height()) as usize;
        assert!(counts.len() > 20, "{file}: only {} colours", counts.len());
        assert!(most < pixels * 95 / 100, "{file}: one colour covers {most} of {pixels} pixels");
    }
    // Drawn flat in the bones' own colours: the bone lines and the level-set cells inside.
    for file in ["rest/bunny_skeleton.png", "rest/bunny_level_set.png"] {
        let picture = image::open(out.join(file)).unwrap().to_rgb8();
        for (k, &colour) in bones.iter().enumerate() {
            assert!(has_colour(&picture, colour), "{file}: no pixel in bone {k}'s colour {colour:?}");
        }
    }
    // The sub-body surfaces partition the bunny's 3,674 triangles, at its place in the world.
    let bunny = dentbend::mesh::builtin("bunny").unwrap();
    let mut faces = 0;
    let (mut lo, mut hi) = (dentbend::glam::Vec3::INFINITY, dentbend::glam::Vec3::NEG_INFINITY);
    for file in &meshes {
        let mesh = dentbend::mesh::load(out.join(file)).unwrap();
        assert!(mesh.face_count() > 50, "{file}: {} triangles", mesh.face_count());
        faces += mesh.face_count();
        let (a, b) = mesh.bounds();
        (lo, hi) = (lo.min(a), hi.max(b));
    }
    assert_eq!(faces, bunny.face_count());
    let (a, b) = bunny.bounds();
    let scale = dentbend_solver::scene::BUNNY_SCALE;
    assert!((lo - a * scale).abs().max_element() < 1e-4 && (hi - b * scale).abs().max_element() < 1e-4);
}

#[test]
fn rest_files_follow_the_picture_and_mesh_options_and_need_a_bending_body() {
    let dir = TempDir::new("run-rest-options");
    // No pictures: the spring's two sub-body meshes only.
    let out = dir.path("spring");
    let summary = run(&["spring", "--size", "demo", "--frames", "1", "--picture", "0,0"], &out);
    assert!(strings(&summary["rest_pictures"]).is_empty());
    assert_eq!(strings(&summary["rest_meshes"]), ["rest/bar_sub0.obj", "rest/bar_sub1.obj"]);
    let names: Vec<String> = std::fs::read_dir(out.join("rest"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
    // No meshes and no pictures: nothing at all.
    let out = dir.path("spring-bare");
    let summary = run(&["spring", "--size", "demo", "--frames", "1", "--picture", "0,0", "--meshes", "none"], &out);
    assert!(strings(&summary["rest_meshes"]).is_empty() && !out.join("rest").exists());
    // No bending body: no rest folder.
    let out = dir.path("pair");
    let summary = run(&["pair", "--size", "demo", "--frames", "1", "--picture", "0,0"], &out);
    assert!(strings(&summary["rest_pictures"]).is_empty() && strings(&summary["rest_meshes"]).is_empty());
    assert!(!out.join("rest").exists());
}

/// The tetrahedra's 96 struts are built alike and share one rest state: it is written once,
/// under the first strut's name, and every file name holds the body name with its `/` as `_`.
#[test]
fn bodies_built_alike_share_one_set_of_rest_files_and_slashes_leave_file_names() {
    let dir = TempDir::new("run-rest-tetrahedra");
    let out = dir.path("tetrahedra");
    let summary = run(&["tetrahedra", "--size", "demo", "--frames", "1", "--every", "1", "--meshes", "all"], &out);
    let mut rest: Vec<&str> = strings(&summary["rest_pictures"]);
    rest.extend(strings(&summary["rest_meshes"]));
    rest.sort_unstable();
    assert_eq!(
        rest,
        [
            "rest/tetra000_strut0_level_set.png",
            "rest/tetra000_strut0_skeleton.png",
            "rest/tetra000_strut0_sub0.obj",
            "rest/tetra000_strut0_sub_bodies.png"
        ]
    );
    for file in &rest {
        assert!(out.join(file).is_file(), "{file} listed but not written");
    }
    let meshes = out.join("meshes");
    for name in ["tetra015_strut5_0001.obj", "tetra015_ball3_0001.glb"] {
        assert!(meshes.join(name).is_file(), "{name} not written");
    }
}
