//! The uniforms and vertices of `shaders/render.wgsl`: camera, lights and background of one
//! picture tile, the per-mesh material, and the interleaved vertex layout.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4};

use super::Camera;

/// Key light intensity (multiplies the base colour).
const KEY_INTENSITY: f32 = 0.75;
/// Fill light intensity.
const FILL_INTENSITY: f32 = 0.22;
/// Blinn–Phong exponent of the highlight (larger: smaller highlight).
const SHININESS: f32 = 48.0;
/// Peak brightness of the highlight added to the lit colour (linear).
const SPECULAR: f32 = 0.22;
/// Ambient from the sky side of the hemisphere (linear RGB).
const SKY: [f32; 3] = [0.15, 0.16, 0.18];
/// Ambient from the ground side of the hemisphere (linear RGB).
const GROUND: [f32; 3] = [0.05, 0.045, 0.04];
/// Background at the top of the picture (linear RGB; sRGB ≈ 247, 248, 250).
const BACKGROUND_TOP: [f32; 3] = [0.93, 0.94, 0.955];
/// Background at the bottom of the picture (linear RGB; sRGB ≈ 236, 238, 242).
const BACKGROUND_BOTTOM: [f32; 3] = [0.84, 0.855, 0.89];

/// One vertex of `shaders/render.wgsl` (keep in sync with its vertex layout): 24 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(super) struct GpuVertex {
    /// Position, world units (`@location(0)`).
    pub position: [f32; 3],
    /// Normal, world space, unit or zero (`@location(1)`).
    pub normal: [f32; 3],
}

/// The vertex buffer layout matching [`GpuVertex`].
pub(super) const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];

/// `Frame` of `shaders/render.wgsl` (keep in sync): 224 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(super) struct FrameUniform {
    /// World → clip of this tile.
    pub view_proj: [[f32; 4]; 4],
    /// xyz: camera position, world units.
    pub eye: [f32; 4],
    /// xyz: unit vector towards the key light (world); w: intensity.
    pub key: [f32; 4],
    /// xyz: unit vector towards the fill light (world); w: intensity.
    pub fill: [f32; 4],
    /// xyz: the picture's up direction (world, unit); w: Blinn–Phong exponent.
    pub up: [f32; 4],
    /// rgb: sky ambient (linear); a: specular strength.
    pub sky: [f32; 4],
    /// rgb: ground ambient (linear).
    pub ground: [f32; 4],
    /// rgb: background at the top (linear).
    pub background_top: [f32; 4],
    /// rgb: background at the bottom (linear).
    pub background_bottom: [f32; 4],
    /// x, y: tile corner in the picture, pixels; z: picture height, pixels.
    pub tile: [f32; 4],
}

/// `Material` of `shaders/render.wgsl` (keep in sync): 16 bytes, placed at a dynamic offset.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(super) struct MaterialUniform {
    /// rgb: base colour, linear in [0, 1].
    pub colour: [f32; 4],
}

/// A rectangle of the picture rendered in one pass, pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Tile {
    /// Left column.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
}

/// The camera's orthonormal frame: (right, up, towards the eye), world space.
pub(super) fn camera_axes(camera: &Camera) -> (Vec3, Vec3, Vec3) {
    let back = (camera.eye - camera.target).normalize();
    let right = camera.up.cross(back).normalize();
    (right, back.cross(right), back)
}

/// The key light's direction (towards the light, world space): from the upper left of the
/// picture and a little in front (raking light), so that dents facing the viewer catch light on
/// their lower right slope and fall into shade on their upper left one.
pub(super) fn key_light(camera: &Camera) -> Vec3 {
    let (right, up, back) = camera_axes(camera);
    (-0.6 * right + 0.6 * up + 0.38 * back).normalize()
}

impl FrameUniform {
    /// The uniforms for `tile` of a `width × height` picture seen by `camera` (already validated).
    pub fn new(camera: &Camera, width: u32, height: u32, tile: Tile) -> Self {
        let (right, up, back) = camera_axes(camera);
        let fill = (0.6 * right - 0.25 * up + 0.75 * back).normalize();
        let view_proj = crop(tile, width, height) * camera.view_projection(width as f32 / height as f32);
        let rgb = |c: [f32; 3], a: f32| [c[0], c[1], c[2], a];
        Self {
            view_proj: view_proj.to_cols_array_2d(),
            eye: camera.eye.extend(1.0).to_array(),
            key: key_light(camera).extend(KEY_INTENSITY).to_array(),
            fill: fill.extend(FILL_INTENSITY).to_array(),
            up: up.extend(SHININESS).to_array(),
            sky: rgb(SKY, SPECULAR),
            ground: rgb(GROUND, 0.0),
            background_top: rgb(BACKGROUND_TOP, 1.0),
            background_bottom: rgb(BACKGROUND_BOTTOM, 1.0),
            tile: [tile.x as f32, tile.y as f32, height as f32, 0.0],
        }
    }
}

/// The clip-space transform that maps `tile` of a `width × height` picture onto the whole
/// viewport: x' = sx·x + ox·w, y' = sy·y + oy·w (NDC y up, pixel rows down).
fn crop(tile: Tile, width: u32, height: u32) -> Mat4 {
    let (w, h) = (width as f32, height as f32);
    let (tw, th) = (tile.width as f32, tile.height as f32);
    let (sx, sy) = (w / tw, h / th);
    let ox = (w - 2.0 * tile.x as f32) / tw - 1.0;
    let oy = 1.0 - (h - 2.0 * tile.y as f32) / th;
    Mat4::from_cols(Vec4::new(sx, 0.0, 0.0, 0.0), Vec4::new(0.0, sy, 0.0, 0.0), Vec4::Z, Vec4::new(ox, oy, 0.0, 1.0))
}

/// A base colour made safe for the shader: non-finite channels become 0, the rest are clamped
/// to [0, 1].
pub(super) fn material(colour: [f32; 3]) -> MaterialUniform {
    let c = colour.map(|v| if v.is_finite() { v.clamp(0.0, 1.0) } else { 0.0 });
    MaterialUniform { colour: [c[0], c[1], c[2], 1.0] }
}

/// Splits a `width × height` picture into tiles of at most `side × side` pixels, row by row.
pub(super) fn tiles(width: u32, height: u32, side: u32) -> Vec<Tile> {
    let side = side.max(1);
    let mut out = Vec::new();
    for y in (0..height).step_by(side as usize) {
        for x in (0..width).step_by(side as usize) {
            out.push(Tile { x, y, width: side.min(width - x), height: side.min(height - y) });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tile_maps_its_pixels_onto_the_viewport() {
        let tile = Tile { x: 30, y: 10, width: 20, height: 40 };
        let m = crop(tile, 100, 80);
        // NDC of pixel corners (30, 10) and (50, 50) in the whole picture.
        let ndc = |px: f32, py: f32| Vec4::new(px / 100.0 * 2.0 - 1.0, 1.0 - py / 80.0 * 2.0, 0.5, 1.0);
        let a = m * ndc(30.0, 10.0);
        let b = m * ndc(50.0, 50.0);
        assert!((a - Vec4::new(-1.0, 1.0, 0.5, 1.0)).abs().max_element() < 1e-5, "{a}");
        assert!((b - Vec4::new(1.0, -1.0, 0.5, 1.0)).abs().max_element() < 1e-5, "{b}");
    }

    #[test]
    fn tiles_cover_the_picture_once() {
        let all = tiles(70, 33, 32);
        assert_eq!(all.len(), 6);
        let area: u32 = all.iter().map(|t| t.width * t.height).sum();
        assert_eq!(area, 70 * 33);
        assert_eq!(all[5], Tile { x: 64, y: 32, width: 6, height: 1 });
    }

    #[test]
    fn uniform_sizes_match_the_shader() {
        assert_eq!(size_of::<FrameUniform>(), 64 + 9 * 16);
        assert_eq!(size_of::<GpuVertex>(), 24);
    }
}
