//! Input checks shared by the CPU and GPU renderers, so both refuse the same requests.

use super::{Camera, MAX_IMAGE_SIDE, RenderError};

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
/// zero or parallel to the view, or a vertical field of view outside 1..179°.
///
/// # Errors
/// [`RenderError::Camera`].
pub(super) fn camera(camera: &Camera) -> Result<(), RenderError> {
    let finite = camera.eye.is_finite() && camera.target.is_finite() && camera.up.is_finite();
    let view = camera.target - camera.eye;
    let usable = finite
        && view.length_squared() > 0.0
        && view.normalize().cross(camera.up).length_squared() > 1e-12 * camera.up.length_squared()
        && (1.0..179.0).contains(&camera.fov_y_deg)
        && camera.view_projection(1.0).is_finite();
    if !usable {
        return Err(RenderError::Camera(format!("{camera:?}")));
    }
    Ok(())
}
