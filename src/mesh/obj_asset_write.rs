//! Wavefront OBJ output of an [`Asset`]: `mtllib`, then a `v`, `vt` and `vn` line per vertex,
//! then the faces in order, each run of one group opened by the `o`, `g`, `usemtl` and `s`
//! statements that changed.

use std::io::Write;
use std::path::Path;

use super::asset::FaceGroup;
use super::atomic_write::write_atomically;
use super::{Asset, MeshError};

/// Writes `asset` as OBJ: `mtllib` lines, a `v` line per vertex (shortest text that reads back
/// to the same f32), a `vt` line per vertex (its first UV set, if it has one), a `vn` line per
/// vertex (its authored normals, else the mesh's smooth ones), and an `f a/a/a b/b/b c/c/c`
/// line per triangle (`a//a` without UVs), each run of faces of one group preceded by the
/// group's `o`, `g`, `usemtl` (a glTF material without a name as `material_<index>`) and `s`
/// statements that differ from the previous group's. [`parse_obj_asset`](super::parse_obj_asset)
/// reads the file back to the same asset (vertices no face uses come back without a UV). The
/// file is written through a temporary sibling, so a failed save leaves no partial file.
///
/// # Errors
/// [`MeshError::Io`] naming `path` if the file cannot be created or written.
pub fn save_obj_asset(asset: &Asset, path: impl AsRef<Path>) -> Result<(), MeshError> {
    write_atomically(path.as_ref(), |out| write_obj_asset(asset, out))
}

/// The OBJ text of `asset`, as [`save_asset`](super::save_asset) writes it for an `.obj` path.
pub fn obj_asset_text(asset: &Asset) -> String {
    let mut out = Vec::new();
    write_obj_asset(asset, &mut out).expect("writing to memory cannot fail");
    String::from_utf8(out).expect("the writer writes UTF-8")
}

fn write_obj_asset(asset: &Asset, out: &mut impl Write) -> std::io::Result<()> {
    let mesh = asset.mesh();
    writeln!(out, "# dentbend asset: {} vertices, {} triangles", mesh.vertex_count(), mesh.face_count())?;
    for library in asset.material_libraries() {
        writeln!(out, "mtllib {library}")?;
    }
    for p in mesh.positions() {
        writeln!(out, "v {} {} {}", p.x, p.y, p.z)?;
    }
    let uvs = asset.attributes().uvs.first();
    for uv in uvs.into_iter().flatten() {
        writeln!(out, "vt {} {}", uv.x, uv.y)?;
    }
    for n in asset.shading_normals() {
        writeln!(out, "vn {} {} {}", n.x, n.y, n.z)?;
    }
    let mut previous: Option<&FaceGroup> = None;
    let default = FaceGroup::default();
    for (f, &g) in mesh.faces().iter().zip(asset.face_groups()) {
        let group = &asset.groups()[g as usize];
        if previous != Some(group) {
            write_group_change(out, previous.unwrap_or(&default), group)?;
            previous = Some(group);
        }
        let [a, b, c] = f.map(|v| u64::from(v) + 1);
        match uvs {
            Some(_) => writeln!(out, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}")?,
            None => writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}")?,
        }
    }
    Ok(())
}

/// The statements that take the reader from group `from` to group `to`.
fn write_group_change(out: &mut impl Write, from: &FaceGroup, to: &FaceGroup) -> std::io::Result<()> {
    if to.object != from.object
        && let Some(object) = &to.object
    {
        writeln!(out, "o {object}")?;
    }
    if to.group != from.group
        && let Some(group) = &to.group
    {
        writeln!(out, "g {group}")?;
    }
    let material = |g: &FaceGroup| g.material.clone().or_else(|| g.material_index.map(|i| format!("material_{i}")));
    if let (Some(name), true) = (material(to), material(to) != material(from)) {
        writeln!(out, "usemtl {name}")?;
    }
    if to.smoothing != from.smoothing
        && let Some(smoothing) = &to.smoothing
    {
        writeln!(out, "s {smoothing}")?;
    }
    Ok(())
}
