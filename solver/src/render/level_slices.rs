//! A picture of a bending body's level set divided among its bones (paper §4, Figure 12 bottom
//! right): [`SLICES`] parallel slices through the voxel grid, side by side, with every cell in
//! the colour of the bone whose sub-body owns it — full inside the mesh (φ < 0), pale outside
//! (the outside is divided too) — the inside/outside boundary (φ's sign change) drawn dark,
//! boundaries between owners darker, cell edges faint where cells are big enough to show, and
//! the skeleton projected onto each slice.

use glam::{Vec2, Vec3};
use image::{Rgb, RgbImage};

use super::overlay::{draw_disc, draw_segment};
use super::palette::{bone_colour, darken, lighten};
use super::{RenderError, check};
use dentbend::bend::{LevelSet, NO_BONE, Skeleton};

/// Number of slices.
pub(crate) const SLICES: usize = 4;
/// Where the slices cut, as fractions of the mesh's extent along the slicing axis.
const SLICE_FRACTIONS: [f32; SLICES] = [0.8, 0.6, 0.4, 0.2];
/// Least gap between panels and around them, pixels.
const GAP: u32 = 6;
/// Background (gaps and grid-less areas), linear RGB.
const BACKGROUND: [f32; 3] = [0.93, 0.94, 0.96];
/// Colour of cells no bone owns, linear RGB.
const UNOWNED: [f32; 3] = [0.5, 0.5, 0.5];

/// What is sliced and how it is seen: a level set, the bone of every cell, the skeleton, all in
/// the body's model frame, and the direction the body is looked at from.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SliceInput<'a> {
    /// The level set (model frame, m).
    pub level_set: &'a LevelSet,
    /// Owner bone of every cell ([`NO_BONE`] for none), indexed like the level set's cells.
    pub cell_bones: &'a [u32],
    /// The skeleton (model frame, m).
    pub skeleton: &'a Skeleton,
    /// Bounds of the mesh (model frame, m): the slices cut at fixed fractions of it.
    pub bounds: (Vec3, Vec3),
    /// Viewing direction, eye towards the body, in the model frame: the slices are seen from the
    /// side it comes from.
    pub view: Vec3,
    /// The viewer's up direction in the model frame: the slices' up is the grid axis nearest it.
    pub up: Vec3,
}

/// The grid axes of the slices: `normal` across them (towards the viewer), `right` and `up` in
/// them (unit, model frame).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Axes {
    normal_axis: usize,
    normal: Vec3,
    right: Vec3,
    up: Vec3,
}

/// Draws the [`SLICES`] slices of `input` into a `width × height` picture: the grid is cut
/// across the mesh's thinnest axis at 80, 60, 40 and 20 % of its extent, each seen from the
/// viewer's side, in panels of one size and scale laid out in the row, grid or column that shows
/// them largest, nearest to the viewer first (left to right, top to bottom).
///
/// # Errors
/// [`RenderError::ImageSize`] for a zero or oversized side.
pub(crate) fn draw_level_slices(input: &SliceInput<'_>, width: u32, height: u32) -> Result<RgbImage, RenderError> {
    check::image_size(width, height)?;
    let mut image = RgbImage::from_pixel(width, height, srgb(BACKGROUND));
    let set = input.level_set;
    let axes = slice_axes(input.bounds, input.view, input.up);
    let grid_lo = set.origin();
    let [nx, ny, nz] = set.dims();
    let grid_hi = grid_lo + Vec3::new(nx as f32, ny as f32, nz as f32) * set.cell_size();
    let centre = 0.5 * (grid_lo + grid_hi);
    let extent = grid_hi - grid_lo;
    let span = Vec2::new(extent.dot(axes.right.abs()), extent.dot(axes.up.abs()));
    let Some(layout) = layout(span, width, height) else { return Ok(image) };
    let (lo, hi) = input.bounds;
    let n = axes.normal_axis;
    let toward_viewer = axes.normal[n];
    for (k, fraction) in SLICE_FRACTIONS.into_iter().enumerate() {
        // Nearest the viewer first: the fraction is measured from the side the viewer is on.
        let along =
            if toward_viewer > 0.0 { lo[n] + fraction * (hi[n] - lo[n]) } else { hi[n] - fraction * (hi[n] - lo[n]) };
        let layer = ((along - grid_lo[n]) / set.cell_size()).floor().max(0.0);
        let mut plane_centre = centre;
        plane_centre[n] = grid_lo[n] + (layer + 0.5) * set.cell_size();
        let corner = layout.origin + Vec2::new((k % layout.columns) as f32, (k / layout.columns) as f32) * layout.step;
        let (panel, scale) = (layout.panel, layout.scale);
        let panel_centre = corner + 0.5 * panel;
        let to_model = |pixel: Vec2| {
            let d = (pixel - panel_centre) / scale;
            plane_centre + axes.right * d.x - axes.up * d.y
        };
        draw_panel(&mut image, input, (corner, panel), &to_model, scale * set.cell_size());
        let to_pixel = |p: Vec3| {
            panel_centre + Vec2::new((p - plane_centre).dot(axes.right), -(p - plane_centre).dot(axes.up)) * scale
        };
        draw_bones(&mut image, input.skeleton, &to_pixel, width.min(height));
    }
    Ok(image)
}

/// Where the panels go: `columns` per row, the first panel's corner `origin`, the offset `step`
/// from one panel to the next (pixels), each panel `panel` pixels large, `scale` pixels per metre.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Layout {
    columns: usize,
    origin: Vec2,
    step: Vec2,
    panel: Vec2,
    scale: f32,
}

/// The arrangement of the [`SLICES`] panels (4 × 1, 2 × 2 or 1 × 4) that shows a slice of
/// `span` metres largest in a `width × height` picture, centred; `None` when nothing fits.
fn layout(span: Vec2, width: u32, height: u32) -> Option<Layout> {
    let gap = GAP as f32;
    let room = |count: usize, side: u32| (side as f32 - gap * (count as f32 + 1.0)) / count as f32;
    let (columns, scale) = [1, 2, 4]
        .into_iter()
        .map(|columns| {
            let rows = SLICES.div_ceil(columns);
            (columns, (room(columns, width) / span.x).min(room(rows, height) / span.y))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    if !(scale.is_finite() && scale > 0.0) {
        return None;
    }
    let panel = (span * scale).floor().max(Vec2::ONE);
    let rows = SLICES.div_ceil(columns);
    let step = panel + gap;
    let used = Vec2::new(columns as f32, rows as f32) * step - gap;
    let origin = ((Vec2::new(width as f32, height as f32) - used) * 0.5).floor();
    Some(Layout { columns, origin, step, panel, scale })
}

/// Chooses the slicing axis (the mesh's thinnest, the lowest index on ties), seen from the side
/// `view` comes from, and the in-slice axes: up is the grid axis nearest `up`.
fn slice_axes((lo, hi): (Vec3, Vec3), view: Vec3, up: Vec3) -> Axes {
    let extent = hi - lo;
    let normal_axis = (0..3).fold(0, |best, a| if extent[a] < extent[best] { a } else { best });
    let unit = |a: usize| Vec3::AXES[a];
    let normal = if view[normal_axis] > 0.0 { -unit(normal_axis) } else { unit(normal_axis) };
    let (a, b) = ((normal_axis + 1) % 3, (normal_axis + 2) % 3);
    let up_axis = if up[b].abs() > up[a].abs() { b } else { a };
    let up = if up[up_axis] < 0.0 { -unit(up_axis) } else { unit(up_axis) };
    Axes { normal_axis, normal, right: up.cross(normal), up }
}

/// Fills one panel (`corner`, `size` in pixels): each pixel takes its cell's colour, then cell
/// boundaries are drawn where neighbouring pixels fall in different cells.
fn draw_panel(
    image: &mut RgbImage,
    input: &SliceInput<'_>,
    (corner, size): (Vec2, Vec2),
    to_model: &impl Fn(Vec2) -> Vec3,
    cell_pixels: f32,
) {
    let set = input.level_set;
    let (x0, y0) = (corner.x as u32, corner.y as u32);
    let (w, h) = (size.x as u32, size.y as u32);
    let cells: Vec<Option<usize>> = (0..w * h)
        .map(|i| set.cell_of(to_model(Vec2::new((x0 + i % w) as f32 + 0.5, (y0 + i / w) as f32 + 0.5))))
        .collect();
    let owner = |c: usize| input.cell_bones.get(c).copied().unwrap_or(NO_BONE);
    let colour_of = |c: usize| {
        let base = match owner(c) {
            NO_BONE => UNOWNED,
            b => bone_colour(b as usize),
        };
        if set.is_inside(c) { base } else { lighten(base, 0.72) }
    };
    for y in 0..h {
        for x in 0..w {
            let Some(cell) = cells[(y * w + x) as usize] else { continue };
            let right = (x + 1 < w).then(|| cells[(y * w + x + 1) as usize]).flatten();
            let below = (y + 1 < h).then(|| cells[((y + 1) * w + x) as usize]).flatten();
            // 3: φ changes sign, 2: another owner, 1: another cell of the same owner.
            let edge = [right, below]
                .into_iter()
                .flatten()
                .filter(|&other| other != cell)
                .map(|other| match () {
                    () if set.is_inside(other) != set.is_inside(cell) => 3,
                    () if owner(other) != owner(cell) => 2,
                    () => 1,
                })
                .max();
            let colour = match edge {
                Some(3) => [0.02; 3],
                Some(2) => darken(colour_of(cell), 0.55),
                Some(_) if cell_pixels >= 5.0 => darken(colour_of(cell), 0.12),
                _ => colour_of(cell),
            };
            image.put_pixel(x0 + x, y0 + y, srgb(colour));
        }
    }
}

/// Draws every bone, projected by `to_pixel`, as a thin light line with a dark edge in a
/// lightened bone colour, with dots at its ends.
fn draw_bones(image: &mut RgbImage, skeleton: &Skeleton, to_pixel: &impl Fn(Vec3) -> Vec2, side: u32) {
    let width = (side as f32 / 320.0).max(1.5);
    for (k, bone) in skeleton.bones().iter().enumerate() {
        let (a, b) = (to_pixel(bone.head), to_pixel(bone.tail));
        draw_segment(image, a, b, width + 2.0, [0.02; 3], 0.85);
        draw_segment(image, a, b, width, lighten(bone_colour(k), 0.55), 1.0);
        for end in [a, b] {
            draw_disc(image, end, width + 1.0, [0.02; 3], 0.85);
        }
    }
}

/// Linear RGB to an 8-bit sRGB pixel.
fn srgb(colour: [f32; 3]) -> Rgb<u8> {
    Rgb(colour.map(super::raster::to_srgb8))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_fit_the_picture_in_the_best_arrangement() {
        for (span, size, columns) in [
            (Vec2::new(1.5, 1.5), (960, 640), 2),  // square slices: 2 × 2
            (Vec2::new(4.2, 0.4), (960, 640), 1),  // a plank: one above the other
            (Vec2::new(0.4, 4.2), (960, 640), 4),  // a post: side by side
            (Vec2::new(1.0, 1.0), (2000, 300), 4), // a wide picture: side by side
        ] {
            let l = layout(span, size.0, size.1).unwrap();
            assert_eq!(l.columns, columns, "{span} in {size:?}");
            let rows = SLICES.div_ceil(l.columns);
            let end = l.origin + Vec2::new(l.columns as f32 - 1.0, rows as f32 - 1.0) * l.step + l.panel;
            assert!(l.origin.min_element() >= 0.0 && end.x <= size.0 as f32 && end.y <= size.1 as f32, "{l:?}");
            assert!(l.step.x >= l.panel.x + GAP as f32 && l.step.y >= l.panel.y + GAP as f32);
            assert!((l.panel - span * l.scale).abs().max_element() <= 1.0);
        }
        assert!(layout(Vec2::ONE, 10, 10).is_none());
    }

    #[test]
    fn slices_cut_the_thinnest_axis_seen_from_the_viewer() {
        let bounds = (Vec3::new(-2.0, -0.1, -0.3), Vec3::new(2.0, 0.1, 0.3));
        // Looking down and along −z from above: slices across y, seen from +y, up along −z.
        let axes = slice_axes(bounds, Vec3::new(0.0, -0.35, -1.0), Vec3::new(0.0, 0.94, -0.33));
        assert_eq!((axes.normal_axis, axes.normal, axes.up), (1, Vec3::Y, Vec3::NEG_Z));
        assert_eq!(axes.right, Vec3::X);
        // A bunny-like box, thinnest along z, seen from +z with y up: x to the right.
        let axes = slice_axes((Vec3::splat(-1.0), Vec3::new(1.0, 1.0, 0.5)), Vec3::new(0.7, -0.3, -1.0), Vec3::Y);
        assert_eq!((axes.normal, axes.right, axes.up), (Vec3::Z, Vec3::X, Vec3::Y));
        // Seen from −z instead: x to the left.
        let axes = slice_axes((Vec3::splat(-1.0), Vec3::new(1.0, 1.0, 0.5)), Vec3::Z, Vec3::Y);
        assert_eq!((axes.normal, axes.right), (Vec3::NEG_Z, Vec3::NEG_X));
    }
}
