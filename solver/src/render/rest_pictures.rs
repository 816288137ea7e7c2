//! Pictures of a bending body's rest state (paper Figure 12): its skeleton inside the body, its
//! sub-bodies' surfaces in their bones' colours, and its level set divided among the bones.

use glam::{Affine3A, Vec3};
use image::RgbImage;

use super::level_slices::{SliceInput, draw_level_slices};
use super::overlay::{draw_disc, draw_segment, project_point};
use super::palette::{bone_colour, lighten};
use super::{Camera, RenderError, Renderer, Shaded};
use crate::coupling::ArticulatedBody;
use crate::sim::SimError;
use dentbend::mesh::TriMesh;

/// Bone pieces drawn per bone in the skeleton picture, each solid where its middle is inside the
/// mesh and hollow where it is outside.
const BONE_PIECES: usize = 32;

/// The three pictures of a bending body at rest.
#[derive(Debug, Clone)]
pub struct RestPictures {
    /// The rest mesh, light, with the bones drawn over it in their colours: solid where inside
    /// the mesh, hollow where they poke out; dots at the joints.
    pub skeleton: RgbImage,
    /// Every bone's sub-body surface in the bone's colour.
    pub sub_bodies: RgbImage,
    /// Slices through the level set, cells in their owners' colours
    /// (`draw_level_slices`).
    pub level_set: RgbImage,
}

/// Draws the rest pictures of `body` placed in the world by `pose` (model → world), each
/// `width × height`, the 3D ones with `renderer` from a camera looking along `view` (world, eye
/// towards the body) that fits the body.
///
/// # Errors
/// [`RenderError::ImageSize`], [`RenderError::Camera`] for a zero or non-finite view,
/// [`RenderError::Body`] for a non-finite pose, or as [`Renderer::render`].
pub fn rest_pictures(
    body: &ArticulatedBody,
    pose: Affine3A,
    view: Vec3,
    renderer: &Renderer<'_>,
    (width, height): (u32, u32),
) -> Result<RestPictures, RenderError> {
    super::check::image_size(width, height)?;
    if !(view.is_finite() && view.length_squared() > 0.0) {
        return Err(RenderError::Camera(format!("view direction {view}")));
    }
    let mesh = posed(body.rest_mesh(), pose)?;
    let camera = crate::scene::fit_camera(mesh.bounds(), view);
    super::check::camera(&camera)?;

    let light = lighten(body.color(), 0.55);
    let mut skeleton = renderer.render(&[Shaded { mesh: &mesh, colour: light }], &camera, width, height)?;
    draw_skeleton(&mut skeleton, body, pose, &camera);

    let subs = body.sub_meshes().map_err(body_error)?;
    let subs = subs.iter().map(|m| posed(m, pose)).collect::<Result<Vec<_>, _>>()?;
    let shaded: Vec<Shaded<'_>> =
        subs.iter().enumerate().map(|(k, mesh)| Shaded { mesh, colour: bone_colour(k) }).collect();
    let sub_bodies = renderer.render(&shaded, &camera, width, height)?;

    let to_model = pose.inverse();
    let forward = view.normalize();
    let screen_up = forward.cross(camera.up).cross(forward);
    let input = SliceInput {
        level_set: body.level_set(),
        cell_bones: body.sub_bodies().cell_bones(),
        skeleton: body.skeleton(),
        bounds: body.rest_mesh().bounds(),
        view: to_model.transform_vector3(forward),
        up: to_model.transform_vector3(screen_up),
    };
    let level_set = draw_level_slices(&input, width, height)?;
    Ok(RestPictures { skeleton, sub_bodies, level_set })
}

/// `mesh` (model frame) moved into the world by `pose`.
fn posed(mesh: &TriMesh, pose: Affine3A) -> Result<TriMesh, RenderError> {
    let mut moved = mesh.clone();
    moved.transform(pose).map_err(|e| RenderError::Body(e.to_string()))?;
    Ok(moved)
}

/// A bending body's error as a picture error.
fn body_error(error: SimError) -> RenderError {
    RenderError::Body(error.to_string())
}

/// Draws `body`'s bones over `image` (taken by `camera`): a dark edge, then the bone's colour,
/// white-cored where the bone is outside the mesh (by the level set's sign); dots at joints.
fn draw_skeleton(image: &mut RgbImage, body: &ArticulatedBody, pose: Affine3A, camera: &Camera) {
    let (width, height) = image.dimensions();
    let line = (width.min(height) as f32 / 110.0).max(2.0);
    let set = body.level_set();
    let to_pixel = |p: Vec3| project_point(camera, width, height, pose.transform_point3(p));
    for (k, bone) in body.skeleton().bones().iter().enumerate() {
        let (Some(head), Some(tail)) = (to_pixel(bone.head), to_pixel(bone.tail)) else { continue };
        draw_segment(image, head, tail, line + 2.0, [0.01; 3], 1.0);
        draw_segment(image, head, tail, line, bone_colour(k), 1.0);
        for i in 0..BONE_PIECES {
            let (t0, t1) = (i as f32 / BONE_PIECES as f32, (i + 1) as f32 / BONE_PIECES as f32);
            let middle = bone.point_at(0.5 * (t0 + t1));
            if set.cell_of(middle).is_some_and(|c| set.is_inside(c)) {
                continue;
            }
            if let (Some(a), Some(b)) = (to_pixel(bone.point_at(t0)), to_pixel(bone.point_at(t1))) {
                draw_segment(image, a, b, 0.45 * line, [1.0; 3], 1.0);
            }
        }
    }
    for bone in body.skeleton().bones() {
        for (end, radius) in [(bone.head, 0.9), (bone.tail, 0.6)] {
            if let Some(p) = to_pixel(end) {
                draw_disc(image, p, radius * line + 1.0, [0.01; 3], 1.0);
                draw_disc(image, p, radius * line, [1.0; 3], 1.0);
            }
        }
    }
}
