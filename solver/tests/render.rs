//! The offscreen CPU renderer draws what it is given where the camera says, and refuses
//! unusable sizes and cameras.

use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_solver::render::{Camera, RenderError, Shaded, render};

fn is_background(p: &image::Rgb<u8>) -> bool {
    p.0.iter().all(|&c| c > 235)
}

#[test]
fn a_framed_sphere_fills_the_centre_and_leaves_the_corners() {
    let sphere = mesh::builtin("sphere").unwrap();
    let camera = Camera::framing(sphere.bounds(), -Vec3::Z, Vec3::Y);
    let picture = render(&[Shaded { mesh: &sphere, colour: [0.8, 0.3, 0.2] }], &camera, 64, 48).unwrap();
    assert_eq!(picture.dimensions(), (64, 48));
    assert!(!is_background(picture.get_pixel(32, 24)), "the sphere covers the centre");
    for (x, y) in [(0, 0), (63, 0), (0, 47), (63, 47)] {
        assert!(is_background(picture.get_pixel(x, y)), "corner ({x}, {y}) should be background");
    }
    // The bounding sphere of the box has radius √3 and is framed with 5 % margin: the unit
    // sphere's silhouette spans 1/√3 ≈ 58 % of the height, give or take the perspective.
    let covered = (0..48).filter(|&y| !is_background(picture.get_pixel(32, y))).count();
    assert!((20..=34).contains(&covered), "sphere spans {covered} of 48 rows");
    if let Ok(dir) = std::env::var("DENTBEND_TEST_PICTURES") {
        picture.save(std::path::Path::new(&dir).join("render_sphere.png")).unwrap();
    }
}

#[test]
fn nearer_surfaces_hide_farther_ones() {
    let near = mesh::icosphere(0.5, 3).unwrap();
    let mut far = mesh::icosphere(1.0, 3).unwrap();
    far.transform(dentbend::glam::Affine3A::from_translation(Vec3::new(0.0, 0.0, -3.0))).unwrap();
    let camera = Camera { eye: Vec3::new(0.0, 0.0, 5.0), target: Vec3::ZERO, up: Vec3::Y, fov_y_deg: 40.0 };
    let meshes = [Shaded { mesh: &far, colour: [0.0, 0.0, 1.0] }, Shaded { mesh: &near, colour: [1.0, 0.0, 0.0] }];
    let picture = render(&meshes, &camera, 40, 40).unwrap();
    let centre = picture.get_pixel(20, 20).0;
    assert!(centre[0] > centre[2], "the red near sphere must cover the blue far one: {centre:?}");
}

#[test]
fn bad_sizes_and_cameras_are_errors() {
    let sphere = mesh::builtin("sphere").unwrap();
    let meshes = [Shaded { mesh: &sphere, colour: [1.0; 3] }];
    let ok = Camera::framing(sphere.bounds(), -Vec3::Z, Vec3::Y);
    for (w, h) in [(0, 10), (10, 0), (100_000, 10)] {
        assert!(matches!(render(&meshes, &ok, w, h), Err(RenderError::ImageSize { .. })));
    }
    let bad = [
        Camera { eye: Vec3::NAN, ..ok },
        Camera { eye: ok.target, ..ok },
        Camera { fov_y_deg: 0.0, ..ok },
        Camera { fov_y_deg: f32::INFINITY, ..ok },
    ];
    for camera in bad {
        assert!(matches!(render(&meshes, &camera, 8, 8), Err(RenderError::Camera(_))));
    }
}
