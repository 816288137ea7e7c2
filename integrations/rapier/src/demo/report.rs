//! The examples' command line (`--json FILE`) and their report: printed, and written to FILE
//! (its folder created) when given.

use std::path::{Path, PathBuf};

/// The FILE of `--json FILE` among the program's arguments, if given.
///
/// # Errors
/// A message for `--json` without a file name or any other argument.
pub fn json_arg() -> Result<Option<PathBuf>, String> {
    let mut args = std::env::args().skip(1);
    let mut path = None;
    while let Some(a) = args.next() {
        match a.as_str() {
            "--json" => path = Some(PathBuf::from(args.next().ok_or("--json needs a file name")?)),
            other => return Err(format!("unknown argument {other} (usage: --json FILE)")),
        }
    }
    Ok(path)
}

/// Prints `text` and writes it, with a final newline, to `path` when given.
///
/// # Errors
/// The folder or the file cannot be written.
pub fn publish(text: &str, path: Option<&Path>) -> std::io::Result<()> {
    println!("{text}");
    if let Some(path) = path {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)?;
        }
        std::fs::write(path, format!("{text}\n"))?;
    }
    Ok(())
}
