//! A small CPU rasterizer: depth-buffered triangles with per-pixel normals, two lights and a
//! little specular so shallow dents read clearly. Renders at twice the size and averages 2×2
//! blocks for anti-aliasing.

use glam::{Vec3, Vec4Swizzles};
use image::RgbImage;

use super::{Camera, RenderError, check};
use dentbend::mesh::TriMesh;

/// One mesh to draw and its colour (linear RGB in [0, 1]).
#[derive(Debug, Clone, Copy)]
pub struct Shaded<'a> {
    /// The mesh, world coordinates.
    pub mesh: &'a TriMesh,
    /// Base colour, linear RGB in [0, 1].
    pub colour: [f32; 3],
}

/// Renders `meshes` seen by `camera` into a `width × height` picture.
///
/// # Errors
/// [`RenderError::ImageSize`] for a zero or oversized side, [`RenderError::Camera`] for a
/// non-finite camera, one whose eye sits on its target or whose up direction is parallel to the
/// view.
pub fn render(meshes: &[Shaded<'_>], camera: &Camera, width: u32, height: u32) -> Result<RgbImage, RenderError> {
    check::image_size(width, height)?;
    check::camera(camera)?;
    let (w, h) = (2 * width as usize, 2 * height as usize);
    let mut frame = Frame { w, h, depth: vec![f32::INFINITY; w * h], colour: vec![background(); w * h] };
    let clip = camera.view_projection(width as f32 / height as f32);
    let view_dir = (camera.target - camera.eye).normalize();
    for item in meshes {
        let screen: Vec<Vec3> = item
            .mesh
            .positions()
            .iter()
            .map(|&p| {
                let c = clip * p.extend(1.0);
                let ndc = c.xyz() / c.w;
                let behind = c.w <= 0.0;
                Vec3::new(
                    (ndc.x + 1.0) * 0.5 * w as f32,
                    (1.0 - ndc.y) * 0.5 * h as f32,
                    if behind { f32::NAN } else { ndc.z },
                )
            })
            .collect();
        for face in item.mesh.faces() {
            frame.triangle(
                face.map(|v| screen[v as usize]),
                face.map(|v| item.mesh.normals()[v as usize]),
                item.colour,
                view_dir,
            );
        }
    }
    Ok(frame.downsample(width, height))
}

struct Frame {
    w: usize,
    h: usize,
    depth: Vec<f32>,
    colour: Vec<Vec3>,
}

impl Frame {
    fn triangle(&mut self, s: [Vec3; 3], n: [Vec3; 3], colour: [f32; 3], view_dir: Vec3) {
        if s.iter().any(|p| !p.is_finite()) {
            return;
        }
        let area = edge(s[0], s[1], s[2]);
        if area.abs() < 1e-12 {
            return;
        }
        let lo = s[0].min(s[1]).min(s[2]);
        let hi = s[0].max(s[1]).max(s[2]);
        let (x0, x1) = (lo.x.floor().max(0.0) as usize, (hi.x.ceil() as usize).min(self.w));
        let (y0, y1) = (lo.y.floor().max(0.0) as usize, (hi.y.ceil() as usize).min(self.h));
        for y in y0..y1 {
            for x in x0..x1 {
                let p = Vec3::new(x as f32 + 0.5, y as f32 + 0.5, 0.0);
                let b = Vec3::new(edge(s[1], s[2], p), edge(s[2], s[0], p), edge(s[0], s[1], p)) / area;
                if b.min_element() < 0.0 {
                    continue;
                }
                let z = b.x * s[0].z + b.y * s[1].z + b.z * s[2].z;
                let k = y * self.w + x;
                if z < self.depth[k] && z >= -1.0 {
                    self.depth[k] = z;
                    let normal = (b.x * n[0] + b.y * n[1] + b.z * n[2]).normalize_or_zero();
                    self.colour[k] = shade(normal, Vec3::from_array(colour), view_dir);
                }
            }
        }
    }

    fn downsample(&self, width: u32, height: u32) -> RgbImage {
        RgbImage::from_fn(width, height, |x, y| {
            let (x, y) = (2 * x as usize, 2 * y as usize);
            let sum = self.colour[y * self.w + x]
                + self.colour[y * self.w + x + 1]
                + self.colour[(y + 1) * self.w + x]
                + self.colour[(y + 1) * self.w + x + 1];
            image::Rgb((0.25 * sum).to_array().map(to_srgb8))
        })
    }
}

/// Twice the signed area of the screen-space triangle (a, b, c).
fn edge(a: Vec3, b: Vec3, c: Vec3) -> f32 {
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
}

/// A low key light from the upper left (world space, so dents cast readable shading), a dim fill
/// from the opposite side, a little ambient and Blinn–Phong specular; two-sided.
fn shade(normal: Vec3, base: Vec3, view_dir: Vec3) -> Vec3 {
    let normal = if normal.dot(view_dir) > 0.0 { -normal } else { normal };
    let key = Vec3::new(-0.75, 0.55, 0.35).normalize();
    let fill = Vec3::new(0.6, 0.5, -0.6).normalize();
    let diffuse = 0.85 * normal.dot(key).max(0.0) + 0.2 * normal.dot(fill).max(0.0);
    let half = (key - view_dir).normalize();
    let specular = 0.2 * normal.dot(half).max(0.0).powf(50.0);
    base * (0.1 + diffuse) + Vec3::splat(specular)
}

fn background() -> Vec3 {
    Vec3::new(0.93, 0.94, 0.96)
}

pub(super) fn to_srgb8(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0).round() as u8
}
