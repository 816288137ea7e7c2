//! Errors of loading and building scenes.

use std::path::PathBuf;

use crate::sim::SimError;

/// What went wrong loading a scene file or building a built-in scene.
///
/// Problems inside a scene file are [`SceneError::Invalid`], printed as
/// `file:line:column: body "name": field: message` (the body part only inside a `[[body]]`).
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("cannot read scene file {}: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The scene file is malformed (TOML syntax, unknown field, wrong type) or a value in it is
    /// unusable (NaN, negative mass, missing mesh file, duplicate body name…).
    #[error("{}", located(file, *line, *column, body.as_deref(), field, message))]
    Invalid {
        /// The scene file.
        file: PathBuf,
        /// 1-based line of the offending text; 0 when the TOML parser gave no position.
        line: usize,
        /// 1-based column (in characters) of the offending text; 0 when unknown.
        column: usize,
        /// The `[[body]]` the problem is in, by name, when there is one.
        body: Option<String>,
        /// The field, as written in the file (`mass`, `dent.sigma`, `world.dt`, `camera.eye`);
        /// empty when the problem is not about one field.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// A name that is neither a built-in scene nor a `.toml` scene file.
    #[error("unknown scene \"{name}\": expected a built-in scene ({builtins}) or the path of a .toml scene file")]
    UnknownScene {
        /// The name or path given.
        name: String,
        /// The built-in scenes' names, comma-separated.
        builtins: String,
    },
    /// A built-in scene could not be built (a mesh or body the simulation refused).
    #[error("built-in scene \"{scene}\": {source}")]
    Builtin {
        /// The scene's name.
        scene: String,
        /// Why.
        #[source]
        source: SimError,
    },
}

/// `file:line:col: body "name": field: message`, leaving out the parts that are unknown.
fn located(
    file: &std::path::Path,
    line: usize,
    column: usize,
    body: Option<&str>,
    field: &str,
    message: &str,
) -> String {
    let mut out = file.display().to_string();
    if line > 0 {
        out += &format!(":{line}:{column}");
    }
    out += ": ";
    if let Some(body) = body {
        out += &format!("body \"{body}\": ");
    }
    if !field.is_empty() {
        out += &format!("{field}: ");
    }
    out + message
}
