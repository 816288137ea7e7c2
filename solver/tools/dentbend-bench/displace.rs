//! `dentbend-bench displace`: applying one dent map to a target of about 100,000 vertices.

use std::time::Duration;

use dentbend::cpu;
use serde::Serialize;

use crate::setup::DisplaceScene;
use crate::timing::median_seconds;

/// What the JSON reports; keys are the interface.
#[derive(Debug, Serialize)]
pub struct Report {
    /// Target vertices.
    pub vertices: usize,
    /// Target triangles.
    pub faces: usize,
    /// Vertices the dent moves.
    pub moved: usize,
    /// Dent-map side, cells.
    pub map_res: u32,
    /// Median seconds of the `displace` kernel alone (positions in place).
    pub displace_s: f64,
    /// Median seconds of `DentMap::apply`: kernel, finiteness check and normal refresh near the dent.
    pub apply_s: f64,
}

/// Times the kernel and the whole `DentMap::apply` on a block gridded to `cells` per axis.
pub fn run(cells: [u32; 3], min_time: Duration) -> Result<Report, String> {
    let scene = DisplaceScene::new(cells)?;
    let target = &scene.target;
    let mut positions = target.positions().to_vec();
    let mut moved = vec![false; positions.len()];
    let displace_s = median_seconds(10, min_time, || {
        positions.copy_from_slice(target.positions());
        cpu::displace(&scene.kernel_params, &scene.map.cells, &scene.table, &mut positions, &mut moved);
    });

    let mut dented = target.clone();
    let apply_s = median_seconds(10, min_time, || {
        dented.clone_from(target);
        std::hint::black_box(scene.map.apply(&mut dented, &scene.params.attenuation).ok());
    });
    // `apply_s` includes restoring the undented copy; measure that alone and take it off.
    let restore_s = median_seconds(10, min_time, || dented.clone_from(target));

    Ok(Report {
        vertices: target.vertex_count(),
        faces: target.face_count(),
        moved: moved.iter().filter(|&&m| m).count(),
        map_res: scene.map.grid.res,
        displace_s,
        apply_s: (apply_s - restore_s).max(0.0),
    })
}
