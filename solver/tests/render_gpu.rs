//! The GPU renderer draws lit meshes where the CPU rasterizer does, shows dents as shading, tiles
//! large pictures seamlessly and refuses the same bad requests. Without an adapter the GPU
//! tests are reported as ignored (failed when `DENTBEND_REQUIRE_GPU=1`; tests/common/gpu.rs).

mod common;

use dentbend::glam::{Affine3A, Vec3};
use dentbend::gpu::GpuContext;
use dentbend::{DentParams, Impact, TriMesh, dent, mesh};
use dentbend_solver::render::{Camera, GpuRenderer, RenderError, Renderer, Shaded, render};
use image::RgbImage;

const COPPER: [f32; 3] = [0.8, 0.36, 0.16];
const STEEL: [f32; 3] = [0.42, 0.48, 0.58];

/// The GPU renderer.
fn renderer(context: &'static GpuContext) -> GpuRenderer<'static> {
    GpuRenderer::new(context).expect("the render pipelines build")
}

/// Saves `picture` as `name` under `$DENTBEND_TEST_PICTURES` when that is set.
fn keep(picture: &RgbImage, name: &str) {
    if let Ok(dir) = std::env::var("DENTBEND_TEST_PICTURES") {
        picture.save(std::path::Path::new(&dir).join(name)).unwrap();
    }
}

fn luminance(p: &image::Rgb<u8>) -> f32 {
    0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32
}

/// Pixels that differ from the background picture by more than half the contrast of a fully
/// covered pixel of a mid-tone mesh against it (summed over channels, 8-bit units).
fn coverage(picture: &RgbImage, background: &RgbImage) -> Vec<bool> {
    picture
        .pixels()
        .zip(background.pixels())
        .map(|(p, b)| p.0.iter().zip(b.0).map(|(&x, y)| (x as i32 - y as i32).abs()).sum::<i32>() > 60)
        .collect()
}

fn sphere_scene() -> (TriMesh, Camera) {
    let sphere = mesh::icosphere(1.0, 4).unwrap();
    let camera = Camera::framing(sphere.bounds(), -Vec3::Z, Vec3::Y);
    (sphere, camera)
}

fn a_lit_sphere_stands_out_and_is_brighter_on_the_light_side(context: &'static GpuContext) {
    let gpu = renderer(context);
    let (sphere, camera) = sphere_scene();
    let (w, h) = (160, 160);
    let picture = gpu.render(&[Shaded { mesh: &sphere, colour: STEEL }], &camera, w, h).unwrap();
    let background = gpu.render(&[], &camera, w, h).unwrap();
    keep(&picture, "render_gpu_sphere.png");
    assert_eq!(picture.dimensions(), (w, h));
    let mask = coverage(&picture, &background);
    let covered = mask.iter().filter(|&&m| m).count();
    // The unit sphere spans about 58 % of the side (see solver/tests/render.rs): π/4·0.58² ≈ 26 %.
    assert!((0.18..0.36).contains(&(covered as f32 / (w * h) as f32)), "sphere covers {covered} pixels");
    assert!(mask[(h / 2 * w + w / 2) as usize], "the sphere covers the centre");
    // The key light comes from the upper left: that quarter of the disc outshines the lower right.
    let mean = |quarter: fn(i32, i32) -> bool| {
        let (sum, n) = picture.enumerate_pixels().filter(|(x, y, _)| mask[(y * w + x) as usize]).fold(
            (0.0, 0),
            |(sum, n), (x, y, p)| {
                let (dx, dy) = (x as i32 - w as i32 / 2, y as i32 - h as i32 / 2);
                if quarter(dx, dy) { (sum + luminance(p), n + 1) } else { (sum, n) }
            },
        );
        sum / n.max(1) as f32
    };
    let (upper_left, lower_right) = (mean(|dx, dy| dx < 0 && dy < 0), mean(|dx, dy| dx > 0 && dy > 0));
    assert!(upper_left > lower_right + 20.0, "upper left {upper_left:.1} vs lower right {lower_right:.1}");
}

/// Coverage agrees, not pixels: the two differ in rasterization rules (the CPU tests 2×2
/// supersamples at pixel-quarter centres, the GPU 4 MSAA sample positions with top-left fill
/// rules), so pixels on the silhouette may land on either side of the threshold; the lighting
/// differs too (world-fixed lights on the CPU, camera-relative on the GPU), hence masks only.
fn gpu_and_cpu_pictures_cover_the_same_pixels(context: &'static GpuContext) {
    let gpu = renderer(context);
    let mut bunny = mesh::builtin("bunny").unwrap();
    bunny.transform(Affine3A::from_rotation_y(0.6)).unwrap();
    let camera = Camera::framing(bunny.bounds(), Vec3::new(-0.3, -0.4, -1.0), Vec3::Y);
    let meshes = [Shaded { mesh: &bunny, colour: COPPER }];
    let (w, h) = (200, 150);
    let on_gpu = coverage(&gpu.render(&meshes, &camera, w, h).unwrap(), &gpu.render(&[], &camera, w, h).unwrap());
    let on_cpu = coverage(&render(&meshes, &camera, w, h).unwrap(), &render(&[], &camera, w, h).unwrap());
    let both = on_gpu.iter().zip(&on_cpu).filter(|(a, b)| **a && **b).count();
    let either = on_gpu.iter().zip(&on_cpu).filter(|(a, b)| **a || **b).count();
    let iou = both as f32 / either as f32;
    assert!(either > 2000, "the bunny is visible ({either} pixels)");
    assert!(iou >= 0.95, "silhouette IoU {iou:.3}");
}

/// The block of tests/paper_fig02_block.rs dented by a small ball, seen from above at an angle.
fn dented_block() -> (TriMesh, TriMesh, Camera) {
    let block = mesh::builtin("block").unwrap();
    let mut dented = block.clone();
    let ball = common::sphere_at(Vec3::new(0.0, 0.5 + 0.5, 0.0), 0.5);
    let impact = Impact { point: Vec3::new(0.0, 0.5, 0.0), normal: -Vec3::Y, relative_velocity: -2.0 * Vec3::Y };
    dent(&mut dented, &ball, &impact, &DentParams::new(0.15)).unwrap();
    let camera =
        Camera { eye: Vec3::new(0.0, 3.2, 3.4), target: Vec3::new(0.0, 0.3, 0.0), up: Vec3::Y, fov_y_deg: 45.0 };
    (block, dented, camera)
}

/// Variance of the luminance in the square of half-side `half` pixels around where `point` lands.
fn variance_around(picture: &RgbImage, camera: &Camera, point: Vec3, half: i32) -> f32 {
    let (w, h) = picture.dimensions();
    let clip = camera.view_projection(w as f32 / h as f32) * point.extend(1.0);
    let (cx, cy) = ((clip.x / clip.w + 1.0) * 0.5 * w as f32, (1.0 - clip.y / clip.w) * 0.5 * h as f32);
    let values: Vec<f32> = (-half..=half)
        .flat_map(|dy| (-half..=half).map(move |dx| (cx as i32 + dx, cy as i32 + dy)))
        .map(|(x, y)| luminance(picture.get_pixel(x as u32, y as u32)))
        .collect();
    let mean = values.iter().sum::<f32>() / values.len() as f32;
    values.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / values.len() as f32
}

fn a_dent_shows_as_shading(context: &'static GpuContext) {
    let gpu = renderer(context);
    let (block, dented, camera) = dented_block();
    let far = Vec3::new(1.5, 0.5, 0.0);
    let untouched = |m: &TriMesh| m.positions().iter().filter(|p| p.distance(far) < 0.45).copied().collect::<Vec<_>>();
    assert_eq!(untouched(&block), untouched(&dented), "the flat region must be away from the dent");
    let (w, h) = (320, 240);
    let picture = gpu.render(&[Shaded { mesh: &dented, colour: STEEL }], &camera, w, h).unwrap();
    let plain = gpu.render(&[Shaded { mesh: &block, colour: STEEL }], &camera, w, h).unwrap();
    keep(&picture, "render_gpu_dented_block.png");
    let half = 12;
    let dent_region = variance_around(&picture, &camera, Vec3::new(0.0, 0.5, 0.0), half);
    let flat_region = variance_around(&picture, &camera, far, half);
    let before = variance_around(&plain, &camera, Vec3::new(0.0, 0.5, 0.0), half);
    assert!(dent_region > 10.0 * flat_region.max(1.0), "dent {dent_region:.1} vs flat {flat_region:.1}");
    assert!(dent_region > 10.0 * before.max(1.0), "dent {dent_region:.1} vs the same place undented {before:.1}");
}

/// Tiles meet without seams: a picture drawn in 37-pixel tiles matches the one drawn in one pass
/// up to pixels whose samples flip at f32 rounding of the cropped projection.
fn tiled_pictures_match_single_pass_ones(context: &'static GpuContext) {
    let gpu = renderer(context);
    let (sphere, camera) = sphere_scene();
    let meshes = [Shaded { mesh: &sphere, colour: COPPER }];
    let whole = gpu.render(&meshes, &camera, 150, 100).unwrap();
    let tiled = gpu.with_tile_side(37).render(&meshes, &camera, 150, 100).unwrap();
    let differ =
        whole.pixels().zip(tiled.pixels()).filter(|(a, b)| a.0.iter().zip(b.0).any(|(&x, y)| x.abs_diff(y) > 2));
    let count = differ.count();
    assert!(count <= 15, "{count} of 15,000 pixels differ");
}

fn an_empty_scene_is_the_background_gradient(context: &'static GpuContext) {
    let gpu = renderer(context);
    let (_, camera) = sphere_scene();
    let picture = gpu.render(&[], &camera, 40, 30).unwrap();
    for y in 0..30 {
        assert!((0..40).all(|x| picture.get_pixel(x, y) == picture.get_pixel(0, y)), "row {y} is uniform");
    }
    let (top, bottom) = (luminance(picture.get_pixel(0, 0)), luminance(picture.get_pixel(0, 29)));
    assert!(top > bottom && bottom > 230.0, "top {top}, bottom {bottom}");
}

fn bad_sizes_and_cameras_are_errors(context: &'static GpuContext) {
    let gpu = renderer(context);
    let (sphere, ok) = sphere_scene();
    let meshes = [Shaded { mesh: &sphere, colour: STEEL }];
    for (w, h) in [(0, 10), (10, 0), (100_000, 10), (10, u32::MAX)] {
        assert!(matches!(gpu.render(&meshes, &ok, w, h), Err(RenderError::ImageSize { .. })), "{w}×{h}");
    }
    let bad = [
        Camera { eye: Vec3::NAN, ..ok },
        Camera { target: Vec3::new(0.0, f32::INFINITY, 0.0), ..ok },
        Camera { up: Vec3::NAN, ..ok },
        Camera { up: Vec3::ZERO, ..ok },
        Camera { up: ok.target - ok.eye, ..ok },
        Camera { eye: ok.target, ..ok },
        Camera { fov_y_deg: 0.0, ..ok },
        Camera { fov_y_deg: f32::NAN, ..ok },
    ];
    for camera in bad {
        assert!(matches!(gpu.render(&meshes, &camera, 8, 8), Err(RenderError::Camera(_))), "{camera:?}");
    }
    // Larger than one texture of the device: drawn in tiles, not refused.
    let wide = gpu.tile_side() + 3;
    assert_eq!(gpu.render(&meshes, &ok, wide, 4).unwrap().dimensions(), (wide, 4));
}

/// Without a context the renderer is the CPU rasterizer (the same picture as `render`); with
/// one it draws on the GPU.
fn renderer_picks_the_gpu_for_a_context_and_the_cpu_without(context: Option<&'static GpuContext>) {
    let renderer = Renderer::new(context).unwrap();
    assert_eq!(renderer.is_gpu(), context.is_some());
    let (sphere, camera) = sphere_scene();
    let meshes = [Shaded { mesh: &sphere, colour: STEEL }];
    let picture = renderer.render(&meshes, &camera, 32, 24).unwrap();
    match context {
        None => assert_eq!(picture, render(&meshes, &camera, 32, 24).unwrap()),
        Some(_) => assert_eq!(picture.dimensions(), (32, 24)),
    }
}

gpu_test_main! {
    gpu: [
        a_lit_sphere_stands_out_and_is_brighter_on_the_light_side,
        gpu_and_cpu_pictures_cover_the_same_pixels,
        a_dent_shows_as_shading,
        tiled_pictures_match_single_pass_ones,
        an_empty_scene_is_the_background_gradient,
        bad_sizes_and_cameras_are_errors,
    ],
    both: [renderer_picks_the_gpu_for_a_context_and_the_cpu_without],
}
