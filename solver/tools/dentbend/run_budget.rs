//! What a `dentbend run` will write, estimated before anything is written, and the budget it is
//! held to: a run over budget is refused with the estimate unless `--allow-large` says go ahead.

use crate::error::CliError;

/// Default budget of one run's output, bytes (1 GB).
pub const MAX_BYTES: u64 = 1_000_000_000;
/// Default budget of one run's output, files.
pub const MAX_FILES: u64 = 10_000;
/// Bodies a run accepts without `--allow-large`.
pub const MAX_BODIES: usize = 10_000;
/// Triangles of all bodies together a run accepts without `--allow-large` (about 3 GB of
/// meshes, colliders and skinning buffers at roughly 150 bytes a triangle).
pub const MAX_TRIANGLES: usize = 20_000_000;

/// One body's mesh as written at each output frame.
#[derive(Debug, Clone, Copy)]
pub struct BodyOutput {
    /// Vertices of its mesh.
    pub vertices: usize,
    /// Triangles of its mesh.
    pub triangles: usize,
    /// Whether it gets its own files at each output frame (`--meshes all|dentable`).
    pub own_files: bool,
    /// Whether it is a node of the frame's `.glb` scene (`--meshes frame`).
    pub in_frame_scene: bool,
    /// Whether its shape changes (dentable or bending): its damage goes into `damage.json`.
    pub changes: bool,
}

/// What a run will write.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct OutputEstimate {
    /// Bytes, all files together.
    pub bytes: u64,
    /// Files.
    pub files: u64,
    /// Output frames (meshes and pictures each).
    pub output_frames: u64,
}

/// The shape of a run: everything its output size depends on.
#[derive(Debug, Clone, Copy)]
pub struct RunShape {
    /// Steps.
    pub frames: u32,
    /// Output every `every` frames, and at the first and last.
    pub every: u32,
    /// Picture size, pixels (0 × 0: none).
    pub picture: (u32, u32),
}

impl RunShape {
    /// Output frames: 0, every, 2·every, … and the last.
    pub fn output_frames(&self) -> u64 {
        let (frames, every) = (u64::from(self.frames), u64::from(self.every.max(1)));
        frames / every + 1 + u64::from(frames % every != 0)
    }
}

/// Estimated bytes of one OBJ file as `mesh::save` writes it: a `v` and a `vn` line of
/// three shortest-form f32 (about 33 bytes each) per vertex, a `f a//a b//b c//c` line per
/// triangle.
fn obj_bytes(vertices: usize, triangles: usize) -> u64 {
    let digits = vertices.max(1).ilog10() as u64 + 1;
    66 * vertices as u64 + (2 + 3 * (2 * digits + 3)) * triangles as u64 + 64
}

/// Bytes of one mesh inside a `.glb`: f32 positions and normals, u32 indices, and about 400
/// bytes of JSON for its node, mesh, material and accessors.
fn glb_mesh_bytes(vertices: usize, triangles: usize) -> u64 {
    24 * vertices as u64 + 12 * triangles as u64 + 400
}

/// PNG bytes per pixel of a shaded frame (measured: 0.58 for the 960 × 640 `rain` frame; a
/// margin for busier pictures).
const PNG_BYTES_PER_PIXEL: f64 = 1.0;
/// Bytes of one step's record in `summary.json` (pretty-printed: about 190).
const STEP_RECORD_BYTES: u64 = 200;

/// Bytes of `damage.json` per vertex of a body whose shape changes: one edit of the whole mesh
/// (a delta-coded index and three zigzag steps, about 8 bytes, in base64). The file grows with
/// the dents; a run whose dents move each vertex several times writes more.
const DAMAGE_BYTES_PER_VERTEX: u64 = 12;
/// Bytes of `damage.json` per body: name, mesh stamps, pose.
const DAMAGE_BYTES_PER_BODY: u64 = 300;

/// Estimates what a run of `shape` over `bodies` writes.
pub fn estimate(shape: &RunShape, bodies: &[BodyOutput]) -> OutputEstimate {
    let mut per_frame_bytes = 0u64;
    let mut per_frame_files = 0u64;
    let mut frame_scene = 0u64;
    for body in bodies {
        if body.own_files {
            per_frame_bytes += obj_bytes(body.vertices, body.triangles) + glb_mesh_bytes(body.vertices, body.triangles);
            per_frame_files += 2;
        }
        if body.in_frame_scene {
            frame_scene += glb_mesh_bytes(body.vertices, body.triangles);
        }
    }
    if frame_scene > 0 {
        per_frame_bytes += frame_scene + 64;
        per_frame_files += 1;
    }
    let (width, height) = shape.picture;
    if width > 0 && height > 0 {
        per_frame_bytes += (f64::from(width) * f64::from(height) * PNG_BYTES_PER_PIXEL) as u64;
        per_frame_files += 1;
    }
    let output_frames = shape.output_frames();
    let damage: u64 = bodies
        .iter()
        .map(|b| DAMAGE_BYTES_PER_BODY + if b.changes { DAMAGE_BYTES_PER_VERTEX * b.vertices as u64 } else { 0 })
        .sum();
    OutputEstimate {
        bytes: per_frame_bytes
            .saturating_mul(output_frames)
            .saturating_add(STEP_RECORD_BYTES.saturating_mul(u64::from(shape.frames)))
            .saturating_add(damage),
        // summary.json and damage.json.
        files: per_frame_files.saturating_mul(output_frames).saturating_add(2),
        output_frames,
    }
}

/// Refuses a run over the budget (bodies, triangles, output bytes or files) with what it would
/// cost and how to shrink it, unless `allow_large`.
pub fn check(estimate: &OutputEstimate, bodies: &[BodyOutput], allow_large: bool) -> Result<(), CliError> {
    if allow_large {
        return Ok(());
    }
    let triangles: usize = bodies.iter().map(|b| b.triangles).sum();
    let over = if bodies.len() > MAX_BODIES {
        format!("it has {} bodies (more than {MAX_BODIES})", bodies.len())
    } else if triangles > MAX_TRIANGLES {
        format!("its bodies have {triangles} triangles together (more than {MAX_TRIANGLES})")
    } else if estimate.bytes > MAX_BYTES || estimate.files > MAX_FILES {
        format!(
            "it would write about {} in {} files ({} output frames; the budget is {} and {MAX_FILES} files)",
            human_bytes(estimate.bytes),
            estimate.files,
            estimate.output_frames,
            human_bytes(MAX_BYTES)
        )
    } else {
        return Ok(());
    };
    Err(CliError::Usage(format!(
        "this run is too large: {over}; write less (a larger --every, fewer --frames, --meshes frame or none, \
         --picture 0,0) or pass --allow-large to go ahead"
    )))
}

/// `1.2 GB`, `340 MB`, `12 kB`, `800 B` (powers of 1000).
pub fn human_bytes(bytes: u64) -> String {
    let b = bytes as f64;
    match bytes {
        0..1_000 => format!("{bytes} B"),
        1_000..1_000_000 => format!("{:.0} kB", b / 1e3),
        1_000_000..1_000_000_000 => format!("{:.0} MB", b / 1e6),
        1_000_000_000..1_000_000_000_000 => format!("{:.1} GB", b / 1e9),
        _ => format!("{:.1} TB", b / 1e12),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn body(triangles: usize, own_files: bool) -> BodyOutput {
        BodyOutput { vertices: triangles / 2 + 2, triangles, own_files, in_frame_scene: !own_files, changes: false }
    }

    #[test]
    fn output_frames_count_the_first_and_last() {
        let shape = |frames, every| RunShape { frames, every, picture: (0, 0) };
        assert_eq!(shape(60, 10).output_frames(), 7); // 0, 10, …, 60
        assert_eq!(shape(65, 10).output_frames(), 8); // … 60 and 65
        assert_eq!(shape(1, 10).output_frames(), 2);
    }

    #[test]
    fn the_issue_runs_are_refused_and_the_builtin_defaults_are_not() {
        // 20,000 bodies with default options.
        let many = vec![body(1_280, true); 20_000];
        let shape = RunShape { frames: 240, every: 10, picture: (960, 640) };
        assert!(check(&estimate(&shape, &many), &many, false).is_err());
        assert!(check(&estimate(&shape, &many), &many, true).is_ok());
        // A billion frames: the step records alone are 200 GB.
        let pair = vec![body(1_280, false); 2];
        let huge = RunShape { frames: 1_000_000_000, every: 1_000_000_000, picture: (0, 0) };
        let message = check(&estimate(&huge, &pair), &pair, false).unwrap_err().to_string();
        assert!(message.contains("200.0 GB"), "{message}");
        // A 4,049-body scene writing one .glb a frame, 25 output frames.
        let tetrahedra = vec![body(240, false); 4_049];
        assert!(check(&estimate(&shape, &tetrahedra), &tetrahedra, false).is_ok());
    }

    #[test]
    fn bytes_read_as_people_write_them() {
        assert_eq!(human_bytes(999), "999 B");
        assert_eq!(human_bytes(9_000_000_000), "9.0 GB");
        assert_eq!(human_bytes(340_000_000), "340 MB");
    }
}
