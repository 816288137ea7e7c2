//! Loading an [`Asset`] from a mesh spec (built-in name or file) and saving one in the format
//! its file extension names.

use std::path::Path;

use super::builtin::{BUILTIN_NAMES, builtin, unsupported};
use super::builtin_crate::crate_asset;
#[cfg(feature = "io")]
use super::gltf_asset_read::load_gltf_asset;
use super::obj_asset::load_obj_asset;
use super::ply::load_ply;
use super::{Asset, MeshError};

/// A built-in mesh as an asset: the `crate` with its split vertices, authored normals and UVs
/// (see [`builtin`]); every other one with no attributes but its mesh's.
///
/// # Errors
/// As [`builtin`].
pub fn builtin_asset(name: &str) -> Result<Asset, MeshError> {
    match name {
        "crate" => Ok(crate_asset()),
        _ => builtin(name).map(Asset::from_mesh),
    }
}

/// Loads an asset from a spec, as [`load`](super::load) loads a mesh: a built-in name
/// ([`builtin_asset`]), an `.obj` (UV sets, normals, face groups), a `.ply` (its mesh alone) or,
/// with the `io` feature, a `.gltf`/`.glb` (every attribute set, skins, split vertices).
///
/// # Errors
/// [`MeshError::UnsupportedFormat`] for anything else; otherwise as the format's reader.
pub fn load_asset(spec: impl AsRef<Path>) -> Result<Asset, MeshError> {
    let path = spec.as_ref();
    if let Some(name) = path.to_str().filter(|s| BUILTIN_NAMES.contains(s)) {
        return builtin_asset(name);
    }
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("obj") => load_obj_asset(path),
        Some("ply") => load_ply(path).map(Asset::from_mesh),
        #[cfg(feature = "io")]
        Some("gltf" | "glb") => load_gltf_asset(path),
        _ => Err(unsupported(path)),
    }
}

/// Writes `asset` in the format the extension of `path` names (case-insensitive): `.obj` (with
/// its UV sets, normals and face groups) or, with the `io` feature, `.glb` (every attribute set,
/// skins); [`obj_asset_text`](super::obj_asset_text) and `glb_asset_bytes` encode in memory.
///
/// # Errors
/// [`MeshError::UnsupportedSaveFormat`] for any other extension (nothing is written);
/// otherwise as the format's writer.
pub fn save_asset(path: impl AsRef<Path>, asset: &Asset) -> Result<(), MeshError> {
    let path = path.as_ref();
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("obj") => super::save_obj_asset(asset, path),
        #[cfg(feature = "io")]
        Some("glb") => super::save_glb_asset(asset, path),
        _ => Err(MeshError::UnsupportedSaveFormat { path: path.to_path_buf() }),
    }
}
