//! Flat 2D marks drawn over a finished picture: anti-aliased thick line segments and discs,
//! blended in linear light, and the projection that places world points on the picture.

use glam::{Vec2, Vec3, Vec4Swizzles};
use image::RgbImage;

use super::Camera;

/// Where the world point `p` lands in a `width × height` picture taken by `camera`: pixel
/// coordinates (x right, y down, pixel centres at half-integers), or `None` behind the eye.
pub(crate) fn project_point(camera: &Camera, width: u32, height: u32, p: Vec3) -> Option<Vec2> {
    let clip = camera.view_projection(width as f32 / height as f32) * p.extend(1.0);
    if clip.w <= 0.0 || !clip.is_finite() {
        return None;
    }
    let ndc = clip.xy() / clip.w;
    Some(Vec2::new((ndc.x + 1.0) * 0.5 * width as f32, (1.0 - ndc.y) * 0.5 * height as f32))
}

/// Draws the segment `a`–`b` (pixels) as a capsule `width` pixels wide in linear RGB `colour`,
/// over what is there (anti-aliased edges, `opacity` in [0, 1]).
pub(crate) fn draw_segment(image: &mut RgbImage, a: Vec2, b: Vec2, width: f32, colour: [f32; 3], opacity: f32) {
    let radius = 0.5 * width.max(0.0);
    let coverage = |p: Vec2| {
        let ab = b - a;
        let t = if ab.length_squared() > 0.0 { ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
        (radius + 0.5 - p.distance(a + ab * t)).clamp(0.0, 1.0)
    };
    paint(image, a.min(b) - radius - 1.0, a.max(b) + radius + 1.0, colour, opacity, coverage);
}

/// Draws a disc of `radius` pixels about `centre` (pixels) in linear RGB `colour`.
pub(crate) fn draw_disc(image: &mut RgbImage, centre: Vec2, radius: f32, colour: [f32; 3], opacity: f32) {
    draw_segment(image, centre, centre, 2.0 * radius, colour, opacity);
}

/// Blends `colour` over every pixel of the box `lo`..`hi` (pixels, clipped to the picture) by
/// `opacity` × `coverage(pixel centre)`.
fn paint(image: &mut RgbImage, lo: Vec2, hi: Vec2, colour: [f32; 3], opacity: f32, coverage: impl Fn(Vec2) -> f32) {
    if !(lo.is_finite() && hi.is_finite()) {
        return;
    }
    let (w, h) = (image.width() as f32, image.height() as f32);
    let (x0, y0) = (lo.x.max(0.0).floor() as u32, lo.y.max(0.0).floor() as u32);
    let (x1, y1) = (hi.x.min(w).ceil() as u32, hi.y.min(h).ceil() as u32);
    let opacity = opacity.clamp(0.0, 1.0);
    for y in y0..y1 {
        for x in x0..x1 {
            let alpha = opacity * coverage(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
            if alpha <= 0.0 {
                continue;
            }
            let pixel = image.get_pixel_mut(x, y);
            for (channel, &c) in pixel.0.iter_mut().zip(&colour) {
                let under = srgb8_to_linear(*channel);
                *channel = super::raster::to_srgb8(under + (c - under) * alpha);
            }
        }
    }
}

/// Linear value of an 8-bit sRGB channel.
pub(super) fn srgb8_to_linear(value: u8) -> f32 {
    let s = f32::from(value) / 255.0;
    if s <= 0.040_45 { s / 12.92 } else { ((s + 0.055) / 1.055).powf(2.4) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_segment_covers_its_capsule_only() {
        let mut image = RgbImage::from_pixel(40, 20, image::Rgb([255, 255, 255]));
        draw_segment(&mut image, Vec2::new(5.0, 10.0), Vec2::new(35.0, 10.0), 4.0, [0.0; 3], 1.0);
        // On the line: black; 2 px past the 2 px radius and beyond the caps: untouched.
        assert_eq!(image.get_pixel(20, 10).0, [0, 0, 0]);
        assert_eq!(image.get_pixel(20, 5).0, [255, 255, 255]);
        assert_eq!(image.get_pixel(39, 10).0, [255, 255, 255]);
        // Half opacity over white is half-way in linear light.
        let mut grey = RgbImage::from_pixel(8, 8, image::Rgb([255, 255, 255]));
        draw_disc(&mut grey, Vec2::new(4.0, 4.0), 3.0, [0.0; 3], 0.5);
        assert!((srgb8_to_linear(grey.get_pixel(4, 4).0[0]) - 0.5).abs() < 0.01);
    }

    #[test]
    fn projection_puts_the_target_in_the_middle() {
        let camera = Camera { eye: Vec3::new(0.0, 0.0, 5.0), target: Vec3::ZERO, up: Vec3::Y, fov_y_deg: 30.0 };
        let p = project_point(&camera, 200, 100, Vec3::ZERO).unwrap();
        assert!((p - Vec2::new(100.0, 50.0)).length() < 1e-3, "{p}");
        let above = project_point(&camera, 200, 100, Vec3::Y).unwrap();
        assert!(above.y < 50.0);
        assert!(project_point(&camera, 200, 100, Vec3::new(0.0, 0.0, 9.0)).is_none());
    }
}
