//! Cutting a batch into chunks whose buffers fit the device's limits.

use std::borrow::Borrow;
use std::ops::Range;

use crate::dent::{DentJob, DentPlan};
use crate::gpu::GpuContext;
use crate::mesh::TriMesh;

/// Bytes per grid cell across the map-building buffers of a chunk (profile 4, rows 4, envelope
/// 4, hull scratch 12, heat scratch 4): a chunk's largest binding is the 12-byte scratch.
const SCRATCH_BYTES_PER_CELL: u64 = 12;
/// Bytes per dent-map cell (`vec4<f32>`).
const MAP_BYTES_PER_CELL: u64 = 16;

/// Consecutive job ranges that one set of dispatches can serve: every buffer within the device's
/// storage binding limit (grid scratch 12 bytes per cell, map 16 bytes per cell, projectile
/// geometry 24 bytes per vertex and triangle), and at most as many dents as workgroups per
/// dispatch dimension. A single dent too large on its own still gets a chunk, which its
/// kernels then refuse with [`GpuError::OverLimit`](crate::gpu::GpuError::OverLimit).
pub(super) fn chunks<P: Borrow<DentPlan>>(
    plans: &[P],
    jobs: &[DentJob<'_>],
    context: &GpuContext,
) -> Vec<Range<usize>> {
    let limit = context.limits.max_storage_buffer_binding_size;
    let max_dents = context.limits.max_compute_workgroups_per_dimension as usize;
    let mut out = Vec::new();
    let (mut start, mut cells, mut map_cells, mut geometry) = (0, 0u64, 0u64, 0u64);
    let mut seen: std::collections::HashSet<*const TriMesh> = Default::default();
    for (k, plan) in plans.iter().map(Borrow::borrow).enumerate() {
        let (c, m) = (u64::from(plan.zbuffer_grid.res.pow(2)), u64::from(plan.map_grid.res.pow(2)));
        let projectile = jobs[k].projectile;
        let size = 12 * (projectile.vertex_count() + projectile.face_count()) as u64;
        let g = if seen.contains(&std::ptr::from_ref(projectile)) { 0 } else { size };
        let over = (cells + c) * SCRATCH_BYTES_PER_CELL > limit
            || (map_cells + m) * MAP_BYTES_PER_CELL > limit
            || geometry + g > limit
            || k - start >= max_dents;
        if over && k > start {
            out.push(start..k);
            (start, cells, map_cells, geometry) = (k, 0, 0, 0);
            seen.clear();
        }
        cells += c;
        map_cells += m;
        if seen.insert(std::ptr::from_ref(projectile)) {
            geometry += size;
        }
    }
    if start < plans.len() {
        out.push(start..plans.len());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dent::plan_dent;
    use crate::{DentParams, Impact, Resolution};

    fn plan(res: u32) -> DentPlan {
        let ball = crate::mesh::icosphere(1.0, 1).unwrap();
        let impact = Impact::head_on(ball.support_point(glam::Vec3::Y), glam::Vec3::Y);
        let params = DentParams { resolution: Resolution::Fixed(res), ..DentParams::new(0.2) };
        plan_dent(&ball, &impact, &params, None).unwrap()
    }

    /// Batches are cut where the next dent would push a chunk's largest buffer (12 bytes per
    /// grid cell, 16 per map cell) past the 128 MiB binding limit, keeping submission order.
    #[test]
    fn batches_split_at_the_binding_limit() {
        let Ok(context) = crate::gpu::shared_context() else {
            eprintln!("skipping: no GPU adapter");
            return;
        };
        let ball = crate::mesh::icosphere(1.0, 1).unwrap();
        let job = DentJob {
            target: 0,
            projectile: &ball,
            impact: Impact::head_on(glam::Vec3::ZERO, glam::Vec3::Y),
            params: DentParams::new(0.2),
        };
        let jobs = vec![job; 150];
        // Head-on, the map is as large as the grid and its 16 bytes per cell bind first: 52 dents.
        let per_chunk = (128u64 << 20) / (SCRATCH_BYTES_PER_CELL.max(MAP_BYTES_PER_CELL) * 400 * 400);
        let plans: Vec<DentPlan> = (0..150).map(|_| plan(400)).collect();
        let cut = chunks(&plans, &jobs, context);
        assert_eq!(cut.iter().map(|r| r.len() as u64).max().unwrap(), per_chunk);
        assert_eq!(cut.first().unwrap().start, 0);
        assert_eq!(cut.last().unwrap().end, 150);
        assert!(cut.windows(2).all(|w| w[0].end == w[1].start), "chunks are consecutive: {cut:?}");
        // One dent larger than the limit still gets its own chunk (and the kernels refuse it).
        assert_eq!(chunks(&[plan(2048)], &jobs[..1], context), vec![0..1]);
        assert!(chunks::<DentPlan>(&[], &[], context).is_empty());
    }
}
