//! The write-then-rename helper every file dentbend writes goes through, so that a failed save
//! never leaves a partial file behind.

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use super::MeshError;

/// Writes a file through `write`, atomically as far as the file system allows: the bytes go to a
/// hidden temporary file in the same directory, which is renamed over `path` only once
/// everything was written. On any error the temporary file is removed and `path` is left as it
/// was (absent, or with its old contents). The data is not `fsync`ed. Every file dentbend writes
/// (meshes, arrays, pictures, the command line's JSON) goes through here.
///
/// # Errors
/// The [`io::Error`] of creating (for example because the directory does not exist), writing or
/// renaming the temporary file.
///
/// # Example
/// ```
/// use std::io::Write;
/// let path = std::env::temp_dir().join(format!("dentbend-doc-{}.txt", std::process::id()));
/// dentbend::mesh::write_file_atomically(&path, |out| out.write_all(b"complete")).unwrap();
/// let failed = dentbend::mesh::write_file_atomically(&path, |out| {
///     out.write_all(b"partial")?;
///     Err(std::io::Error::other("the writer failed half-way"))
/// });
/// assert!(failed.is_err());
/// assert_eq!(std::fs::read(&path).unwrap(), b"complete"); // the old contents survive
/// # std::fs::remove_file(&path).unwrap();
/// ```
pub fn write_file_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> io::Result<()> {
    let temp = temp_sibling(path)?;
    let file = OpenOptions::new().write(true).create_new(true).open(&temp)?;
    fill_and_rename(file, &temp, path, write).inspect_err(|_| {
        // Best effort: the rename did not happen, so the temporary file is ours to remove.
        let _ = fs::remove_file(&temp);
    })
}

/// [`write_file_atomically`] with its error as [`MeshError::Io`] naming `path`.
pub(crate) fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> Result<(), MeshError> {
    write_file_atomically(path, write).map_err(|source| MeshError::Io { path: path.to_path_buf(), source })
}

/// Writes and flushes `file` (open at `temp`), closes it, then renames `temp` to `path`.
fn fill_and_rename(
    file: File,
    temp: &Path,
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> io::Result<()> {
    let mut out = BufWriter::new(file);
    write(&mut out)?;
    let file = out.into_inner().map_err(io::IntoInnerError::into_error)?;
    // Closed before the rename, which some platforms refuse on an open file.
    drop(file);
    fs::rename(temp, path)
}

/// A fresh hidden file name next to `path`: `.<name>.<process id>-<counter>.tmp`.
fn temp_sibling(path: &Path) -> io::Result<PathBuf> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name =
        path.file_name().ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "the path does not name a file"))?;
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let temp_name = format!(".{}.{}-{n}.tmp", name.to_string_lossy(), std::process::id());
    Ok(path.with_file_name(temp_name))
}
