//! Every file the command line writes goes through here: written whole to a hidden temporary
//! file beside its destination and renamed into place, so an error or an unsupported format
//! leaves an existing file untouched and no partial file behind.

use std::io::Write;
use std::path::Path;

use dentbend::mesh::write_file_atomically;
use image::RgbImage;
use serde::Serialize;

use crate::error::CliError;

/// Writes `value` as pretty-printed JSON (with a final line break) to `path`, streaming it to
/// the file (a value that serializes lazily, like the run's step log, is never held whole).
pub fn write_json(path: &Path, value: &impl Serialize) -> Result<(), CliError> {
    write_file_atomically(path, |out| {
        serde_json::to_writer_pretty(&mut *out, value).map_err(std::io::Error::from)?;
        out.write_all(b"\n")
    })
    .map_err(|source| CliError::Write { path: path.to_path_buf(), source })
}

/// Writes `text` to `path`.
pub fn write_text(path: &Path, text: &str) -> Result<(), CliError> {
    write_file_atomically(path, |out| out.write_all(text.as_bytes()))
        .map_err(|source| CliError::Write { path: path.to_path_buf(), source })
}

/// Writes `picture` as a PNG file to `path`.
pub fn write_picture(path: &Path, picture: &RgbImage) -> Result<(), CliError> {
    dentbend::io::write_png(path, picture).map_err(CliError::Io)
}

/// Writes `mesh` in the format its extension names (`.obj` or `.glb`).
pub fn write_mesh(path: &Path, mesh: &dentbend::TriMesh) -> Result<(), CliError> {
    dentbend::mesh::save(path, mesh).map_err(|source| CliError::Save { path: path.to_path_buf(), source })
}

/// Creates the folder `path` will be written into, if missing (like `dentmap --out` and `run
/// --out` create theirs), and refuses a `path` that is a folder.
pub fn prepare_file(path: &Path) -> Result<(), CliError> {
    if path.is_dir() {
        return Err(CliError::Usage(format!("{} is a directory, not a file", path.display())));
    }
    match path.parent().filter(|p| !p.as_os_str().is_empty()) {
        Some(parent) => {
            std::fs::create_dir_all(parent).map_err(|source| CliError::CreateDir { path: parent.to_path_buf(), source })
        }
        None => Ok(()),
    }
}

/// Refuses an output path whose extension is not one of `extensions` (compared without case),
/// before anything is computed or written: `flag` names the option in the message.
pub fn require_extension(path: &Path, flag: &str, extensions: &[&str]) -> Result<(), CliError> {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if extension.as_deref().is_some_and(|e| extensions.contains(&e)) {
        return Ok(());
    }
    let wanted = extensions.iter().map(|e| format!(".{e}")).collect::<Vec<_>>().join(" or ");
    Err(CliError::Usage(format!(
        "{flag} {}: only {wanted} files can be written (the file name must end in {wanted})",
        path.display()
    )))
}
