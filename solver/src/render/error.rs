//! Errors of the renderer.

/// Why a picture could not be made.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A side is zero or larger than [`MAX_IMAGE_SIDE`](super::MAX_IMAGE_SIDE).
    #[error("image size {width}×{height} is outside 1..=8192 pixels per side")]
    ImageSize {
        /// Requested width, pixels.
        width: u32,
        /// Requested height, pixels.
        height: u32,
    },
    /// The camera is unusable.
    #[error("unusable camera: {0}")]
    Camera(String),
    /// A bending body's rest pictures could not be made (a non-finite pose, a bone without a
    /// surface).
    #[error("bending body: {0}")]
    Body(String),
    /// The GPU renderer failed: no adapter (when the GPU was asked for), a validation or
    /// out-of-memory error, a lost device or a failed read-back.
    #[error("GPU renderer: {0}")]
    Gpu(#[from] dentbend::gpu::GpuError),
}
