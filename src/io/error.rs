//! Errors raised while reading and writing `.npy` arrays and PNG images.

use std::path::PathBuf;

/// Everything that can go wrong in [`crate::io`].
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// A file could not be opened, read, created or written.
    #[error("cannot access {path}: {source}")]
    Io {
        /// The file involved.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A `.npy` file is not a little-endian f32, C-order NumPy array this crate can read.
    #[error("malformed .npy file {path}: {message}")]
    Npy {
        /// The file involved.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// An image could not be decoded or encoded.
    #[error("image {path}: {source}")]
    Image {
        /// The file involved.
        path: PathBuf,
        /// The underlying image error.
        #[source]
        source: image::ImageError,
    },
    /// The caller's array does not fit the shape or size it was given with.
    #[error("{0}")]
    InvalidArgument(String),
}

impl IoError {
    /// Wraps an [`std::io::Error`] with the file it happened on.
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io { path: path.into(), source }
    }

    /// A malformed-`.npy` error.
    pub(crate) fn npy(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Self::Npy { path: path.into(), message: message.into() }
    }

    /// Wraps an image error; I/O failures inside the image crate become [`IoError::Io`].
    pub(crate) fn image(path: impl Into<PathBuf>, source: image::ImageError) -> Self {
        match source {
            image::ImageError::IoError(e) => Self::Io { path: path.into(), source: e },
            other => Self::Image { path: path.into(), source: other },
        }
    }
}
