//! `dentbend-bench displace`: applying one dent map to a target of about 100,000 vertices.

use std::time::Duration;

use dentbend::cpu;
use dentbend::glam::{Affine3A, Vec3};
use dentbend::{Attenuation, DentParams, Impact, dent_map, mesh};
use serde::Serialize;

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

/// A 4 × 1 × 4 block gridded to `cells` per axis, dented on its top face by a unit ball.
pub fn run(cells: [u32; 3], min_time: Duration) -> Result<Report, String> {
    let target = mesh::subdivided_box(Vec3::new(4.0, 1.0, 4.0), cells).map_err(|e| e.to_string())?;
    let mut ball = mesh::builtin("sphere").map_err(|e| e.to_string())?;
    ball.transform(Affine3A::from_translation(Vec3::new(0.0, 1.5, 0.0))).map_err(|e| e.to_string())?;
    let impact = Impact { point: Vec3::new(0.0, 0.5, 0.0), normal: -Vec3::Y, relative_velocity: -Vec3::Y };
    let params = DentParams::new(0.2);
    let map = dent_map(&ball, &impact, &params, Some(target.mean_edge_length())).map_err(|e| e.to_string())?;

    let (falloff, falloff_scale, table) = cpu::falloff_table(&params.attenuation, params.dent_distance);
    let kernel_params = cpu::DisplaceParams {
        grid: map.grid.uniform(),
        dent_distance: params.dent_distance,
        falloff,
        falloff_scale,
        vertex_count: target.vertex_count() as u32,
    };
    let mut positions = target.positions().to_vec();
    let mut moved = vec![false; positions.len()];
    let displace_s = median_seconds(10, min_time, || {
        positions.copy_from_slice(target.positions());
        cpu::displace(&kernel_params, &map.cells, &table, &mut positions, &mut moved);
    });

    let mut dented = target.clone();
    let apply_s = median_seconds(10, min_time, || {
        dented.clone_from(&target);
        std::hint::black_box(map.apply(&mut dented, &Attenuation::Logistic).ok());
    });
    // `apply_s` includes restoring the undented copy; measure that alone and take it off.
    let restore_s = median_seconds(10, min_time, || dented.clone_from(&target));

    Ok(Report {
        vertices: target.vertex_count(),
        faces: target.face_count(),
        moved: moved.iter().filter(|&&m| m).count(),
        map_res: map.grid.res,
        displace_s,
        apply_s: (apply_s - restore_s).max(0.0),
    })
}
