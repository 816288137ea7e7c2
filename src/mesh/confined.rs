//! Paths that files name (a glTF buffer's URI, a scene file's mesh) followed only inside the
//! naming file's own folder: no absolute paths, no `..`, and no symbolic link that leads out.

use std::path::{Component, Path, PathBuf};

/// `relative` resolved against `folder`, refused unless it stays inside `folder`: it must be a
/// relative path without `..` components, and its canonical form (symbolic links followed) must
/// lie under `folder`'s. The file must exist.
///
/// # Errors
/// A sentence saying why the path is refused or cannot be read.
pub fn resolve_inside(folder: &Path, relative: &str) -> Result<PathBuf, String> {
    let candidate = Path::new(relative);
    for component in candidate.components() {
        match component {
            Component::Normal(_) | Component::CurDir => {}
            Component::ParentDir => {
                return Err(format!("'{relative}' goes up with '..': only files in this folder or below may be read"));
            }
            Component::RootDir | Component::Prefix(_) => {
                return Err(format!(
                    "'{relative}' is an absolute path: only files in this folder or below may be read"
                ));
            }
        }
    }
    let folder = if folder.as_os_str().is_empty() { Path::new(".") } else { folder };
    let joined = folder.join(candidate);
    let canonical = joined.canonicalize().map_err(|e| format!("cannot read {}: {e}", joined.display()))?;
    let canonical_folder = folder.canonicalize().map_err(|e| format!("cannot read {}: {e}", folder.display()))?;
    if !canonical.starts_with(&canonical_folder) {
        return Err(format!(
            "'{relative}' leads out of {} through a symbolic link: only files in this folder or below may be read",
            folder.display()
        ));
    }
    Ok(canonical)
}

#[cfg(test)]
mod tests {
    use super::resolve_inside;

    #[test]
    fn paths_that_leave_the_folder_are_refused() {
        let root = std::env::temp_dir().join(format!("dentbend-confined-{}", std::process::id()));
        let inner = root.join("assets");
        std::fs::create_dir_all(inner.join("sub")).unwrap();
        std::fs::write(inner.join("sub/a.bin"), b"x").unwrap();
        std::fs::write(root.join("secret.bin"), b"y").unwrap();
        assert!(resolve_inside(&inner, "sub/a.bin").is_ok());
        assert!(resolve_inside(&inner, "./sub/a.bin").is_ok());
        for bad in ["../secret.bin", "sub/../../secret.bin", "/etc/passwd"] {
            assert!(resolve_inside(&inner, bad).is_err(), "{bad} was accepted");
        }
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(root.join("secret.bin"), inner.join("link.bin")).unwrap();
            let message = resolve_inside(&inner, "link.bin").unwrap_err();
            assert!(message.contains("symbolic link"), "{message}");
        }
        assert!(resolve_inside(&inner, "missing.bin").unwrap_err().contains("cannot read"));
        std::fs::remove_dir_all(&root).unwrap();
    }
}
