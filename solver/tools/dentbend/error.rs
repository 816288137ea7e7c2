//! The command line's error type: every failure is one sentence and exit code 2.

use std::path::PathBuf;

use dentbend::io::IoError;
use dentbend::{DentError, MeshError};

/// Why a command failed.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// An argument is unusable (a zero normal, a parameter out of range).
    #[error("{0}")]
    Usage(String),
    /// A mesh could not be loaded.
    #[error("cannot load the {role} '{spec}': {source}")]
    Load {
        /// `"projectile"` or `"target"`.
        role: &'static str,
        /// The path or built-in name given.
        spec: String,
        /// What went wrong.
        #[source]
        source: MeshError,
    },
    /// `--rotate`/`--translate` moved the projectile out of finite space.
    #[error("cannot place the projectile: {0}")]
    Place(#[source] MeshError),
    /// The dent pipeline refused the input.
    #[error("{0}")]
    Dent(#[from] DentError),
    /// A result file could not be written.
    #[error("{0}")]
    Io(#[from] IoError),
    /// The output directory could not be created.
    #[error("cannot create the output directory {path}: {source}")]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A file could not be written.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file or directory.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The dented mesh could not be saved.
    #[error("cannot save {path}: {source}")]
    Save {
        /// The output file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: MeshError,
    },
}

impl CliError {
    /// The message on one line (embedded line breaks become spaces).
    pub fn one_line(&self) -> String {
        self.to_string().split_whitespace().collect::<Vec<_>>().join(" ")
    }
}

/// Rewords a [`DentError::InvalidParameter`] in terms of the command-line flag that set it.
pub fn flag_error(error: DentError) -> CliError {
    let DentError::InvalidParameter { name, value, reason } = &error else {
        return CliError::Dent(error);
    };
    let flag = match *name {
        "dent_distance" => "--dent-distance",
        "sigma" => "--sigma",
        "resolution" => "--res",
        "heat_iters" => "--heat-iters",
        "clamp_iters" => "--clamp-iters",
        "heat_rate" => "--heat-rate",
        "widen" => "--widen",
        "min_cos" => "--min-cos",
        "attenuation.scale" => "--falloff-scale",
        "refine" => "--refine",
        _ => return CliError::Dent(error),
    };
    CliError::Usage(format!("{flag} {value} is out of range: it {reason}"))
}
