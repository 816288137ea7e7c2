//! Input checks shared by the CPU and GPU renderers, so both refuse the same requests.

use super::{Camera, RenderError};

/// Largest image side accepted, pixels.
pub const MAX_IMAGE_SIDE: u32 = 8192;

/// Fails unless both sides are in `1..=MAX_IMAGE_SIDE` pixels.
///
/// # Errors
/// [`RenderError::ImageSize`].
pub(super) fn image_size(width: u32, height: u32) -> Result<(), RenderError> {
    if !(1..=MAX_IMAGE_SIDE).contains(&width) || !(1..=MAX_IMAGE_SIDE).contains(&height) {
        return Err(RenderError::ImageSize { width, height });
    }
    Ok(())
}

/// Fails for a non-finite camera, one whose eye sits on its target, one whose up direction is
/// zero or parallel to the view, or a vertical field of view outside 1..179°; the message names
/// which.
///
/// # Errors
/// [`RenderError::Camera`].
pub(super) fn camera(camera: &Camera) -> Result<(), RenderError> {
    let fail = |message: String| Err(RenderError::Camera(message));
    for (name, v) in [("eye", camera.eye), ("target", camera.target), ("up", camera.up)] {
        if !v.is_finite() {
            return fail(format!("its {name} {v} is not finite (are the meshes beyond the coordinate range?)"));
        }
    }
    let view = camera.target - camera.eye;
    if !(view.length_squared() > 0.0 && view.length_squared().is_finite()) {
        return fail(format!("its eye {} and target {} give no viewing direction", camera.eye, camera.target));
    }
    if view.normalize().cross(camera.up).length_squared() <= 1e-12 * camera.up.length_squared() {
        return fail(format!("its up direction {} is zero or along the view", camera.up));
    }
    if !(1.0..179.0).contains(&camera.fov_y_deg) {
        return fail(format!("its vertical field of view {}° is outside 1..179°", camera.fov_y_deg));
    }
    if !camera.view_projection(1.0).is_finite() {
        return fail(format!("its eye {} and target {} make no finite projection", camera.eye, camera.target));
    }
    Ok(())
}
