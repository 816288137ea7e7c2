//! Parity of the `displace` kernel (shaders/displace.wgsl) with its CPU twin `cpu::displace`:
//! real dent maps (a sphere on the dense bunny, every falloff on a block, a glancing hit), seeded
//! random maps at resolutions 1 to 200, off-map vertices left alone, and a batch of several dents
//! over three targets whose same-target dents must apply in submission order.
//!
//! Tolerance. The kernel runs the twin's f32 operations in the same order, so the results differ
//! only where the GPU rounds differently: `exp` of the logistic falloff and the divisions
//! (`1/h`, `z/d`) may be off by a few ulp (Vulkan allows 3 + 2|x| ulp for exp, 2.5 ulp for
//! division), and the driver may fuse a multiply-add (glam's dots, `p + a·Δ`) into one rounding.
//! Per dent, three effects bound the difference in each component:
//! - a few ulp of relative error in a (exp, z/d) or in the bilinear weights, times |a·Δ| ≤ d:
//!   well under `TOL_D·d` with `TOL_D = 1e-6` (the worst, (3 + 2z/d) ulp of exp times
//!   a(z) = 2/(1 + e^{z/d}), peaks near 0.2e-6 at z ≈ d);
//! - the grid coordinate (up to `res` cells) off by a few ulp of `res` after a differently
//!   rounded `1/h` or a fused dot product, which moves the sample by at most that times the
//!   largest step between neighbouring cells of the map: `COORD_ULPS·ulp(res)·step` (negligible
//!   for the smooth dent maps, ~1e-5·d at res 200 for the random test maps, whose cells jump by
//!   up to 2d);
//! - `p + a·Δ` rounded once more or less: `ULPS` ulp of the position.
//!
//! Dents applied one after the other on a target add up (a position off by an ulp shifts the
//! next dent's sample by ulp/h cells, inside the first two terms for these maps). On lavapipe
//! every falloff but the logistic is bit-exact and the logistic differs by one ulp of the
//! position. Moved flags must agree exactly, except for a vertex whose displacement on one side
//! rounds to no change: both results then lie within an ulp of the original position.

mod common;

use std::sync::Arc;

use common::{SplitMix64, sphere_at};
use dentbend::cpu::{self, DisplaceParams, GridUniform, falloff};
use dentbend::glam::Vec3;
use dentbend::gpu::displace::{Displace, DisplaceDent, DisplacedTarget, MAX_RUNS, runs};
use dentbend::gpu::{GpuContext, buffers};
use dentbend::{Attenuation, DentMap, DentParams, Impact, Resolution, TriMesh, dent_map, mesh};

/// Tolerance in dent distances per dent (see the module comment).
const TOL_D: f32 = 1e-6;
/// Ulps of the grid side by which the GPU's grid coordinate may differ (see the module comment).
const COORD_ULPS: f32 = 4.0;
/// Position roundings allowed per dent (see the module comment).
const ULPS: f32 = 2.0;

/// One dent of a test batch, owning its map.
struct Dent {
    target: usize,
    params: DisplaceParams,
    cells: Vec<[f32; 4]>,
    table: Vec<f32>,
}

impl Dent {
    fn from_map(target: usize, map: &DentMap, attenuation: &Attenuation) -> Self {
        let (params, table) = map.displace_params(attenuation, 0);
        Self { target, params, cells: map.cells.clone(), table }
    }

    /// This dent's share of the tolerance, world units, without the position roundings (see the
    /// module comment): `TOL_D·d + COORD_ULPS·ulp(res)·step`, with `step` the largest change of a
    /// displacement component between neighbouring cells (the grid reads as zero outside).
    fn tolerance(&self) -> f32 {
        let res = self.params.grid.res as usize;
        let cell = |i: usize, j: usize| if i < res && j < res { self.cells[j * res + i] } else { [0.0; 4] };
        let mut step: f32 = 0.0;
        for j in 0..=res {
            for i in 0..=res {
                let here = cell(i, j);
                for next in [cell(i + 1, j), cell(i, j + 1)] {
                    step = (0..3).map(|a| (here[a] - next[a]).abs()).fold(step, f32::max);
                }
                if i == 0 || j == 0 {
                    // The zero ring before the first row and column.
                    step = (0..3).map(|a| here[a].abs()).fold(step, f32::max);
                }
            }
        }
        TOL_D * self.params.dent_distance + COORD_ULPS * ulp(res as f32) * step
    }

    fn gpu(&self) -> DisplaceDent<'_> {
        DisplaceDent { target: self.target, params: self.params, cells: &self.cells, table: &self.table }
    }
}

/// The CPU twin applied dent after dent, in order.
fn cpu_batch(targets: &[Vec<Vec3>], dents: &[&Dent]) -> Vec<(Vec<Vec3>, Vec<bool>)> {
    let mut out: Vec<_> = targets.iter().map(|t| (t.clone(), vec![false; t.len()])).collect();
    for dent in dents {
        let (positions, moved) = &mut out[dent.target];
        cpu::displace(&dent.params, &dent.cells, &dent.table, positions, moved);
    }
    out
}

fn gpu_batch(context: &GpuContext, targets: &[Vec<Vec3>], dents: &[&Dent]) -> Vec<DisplacedTarget> {
    let displace = Displace::new(context).unwrap();
    let slices: Vec<&[Vec3]> = targets.iter().map(Vec::as_slice).collect();
    let batch: Vec<DisplaceDent> = dents.iter().map(|d| d.gpu()).collect();
    displace.run_batch(context, &slices, &batch).unwrap()
}

/// Distance from |x| to the next f32 up.
fn ulp(x: f32) -> f32 {
    let x = x.abs();
    f32::from_bits(x.to_bits() + 1) - x
}

/// What [`check_target`] saw on one target.
struct Report {
    /// Largest difference, in multiples of the tolerance.
    worst: f32,
    /// Vertices the CPU moved.
    moved: usize,
    /// Vertices moved on one side only, by less than an ulp.
    borderline: usize,
}

/// Asserts GPU ≈ CPU for one target to which `count` dents with tolerances summing to
/// `dent_tol` (world units) were applied; moved flags must agree except where a displacement is
/// within an ulp of zero.
fn check_target(
    what: &str,
    original: &[Vec3],
    gpu: &DisplacedTarget,
    cpu: &(Vec<Vec3>, Vec<bool>),
    dent_tol: f32,
    count: usize,
) -> Report {
    let (cpu_positions, cpu_moved) = cpu;
    assert_eq!(gpu.positions.len(), original.len(), "{what}: vertex count");
    let mut report = Report { worst: 0.0, moved: 0, borderline: 0 };
    for (k, ((g, c), o)) in gpu.positions.iter().zip(cpu_positions).zip(original).enumerate() {
        for axis in 0..3 {
            let (g, c, o) = (g[axis], c[axis], o[axis]);
            let tol = dent_tol + ULPS * count as f32 * ulp(o.abs().max(c.abs()));
            let excess = (g - c).abs() / tol;
            assert!(excess <= 1.0, "{what}: vertex {k} axis {axis}: GPU {g} vs CPU {c} (tolerance {tol}, was {o})");
            report.worst = report.worst.max(excess);
        }
        if gpu.moved[k] != cpu_moved[k] {
            // A displacement that rounds away against the position on one side only.
            let tiny = |p: Vec3| (0..3).all(|a| (p[a] - o[a]).abs() <= ulp(o[a]));
            assert!(
                tiny(gpu.positions[k]) && tiny(cpu_positions[k]),
                "{what}: vertex {k} moved on the {} only",
                if gpu.moved[k] { "GPU" } else { "CPU" }
            );
            report.borderline += 1;
        }
        report.moved += cpu_moved[k] as usize;
    }
    report
}

/// Runs `dents` over `targets` on both sides and checks every target; returns the reports.
fn parity(context: &GpuContext, what: &str, targets: &[Vec<Vec3>], dents: &[&Dent]) -> Vec<Report> {
    let gpu = gpu_batch(context, targets, dents);
    let cpu = cpu_batch(targets, dents);
    let reports: Vec<Report> = (0..targets.len())
        .map(|t| {
            let on_t = dents.iter().filter(|d| d.target == t);
            let dent_tol: f32 = on_t.clone().map(|d| d.tolerance()).sum();
            let count = on_t.count();
            check_target(&format!("{what}, target {t}"), &targets[t], &gpu[t], &cpu[t], dent_tol, count)
        })
        .collect();
    for (t, r) in reports.iter().enumerate() {
        eprintln!(
            "{what}, target {t}: {} of {} moved, {} borderline flags, worst {:.3} of tolerance",
            r.moved,
            targets[t].len(),
            r.borderline,
            r.worst
        );
    }
    reports
}

/// A unit ball hitting the top face (y = 0.5) of the built-in block at the origin, at
/// `theta_deg` from the normal.
fn block_map(theta_deg: f32, params: &DentParams, block: &TriMesh) -> DentMap {
    let theta = theta_deg.to_radians();
    let velocity = Vec3::new(theta.sin(), -theta.cos(), 0.0) * 3.0;
    let point = Vec3::new(0.0, 0.5, 0.0);
    let ball = sphere_at(point - velocity.normalize(), 1.0);
    let impact = Impact { point, normal: -Vec3::Y, relative_velocity: velocity };
    dent_map(&ball, &impact, params, Some(block.mean_edge_length())).unwrap()
}

/// A ball hitting the dense bunny on its side (+x), head on.
fn bunny_map(bunny: &TriMesh, d: f32, radius: f32) -> DentMap {
    let point = bunny.support_point(Vec3::X);
    let ball = sphere_at(point + Vec3::X * radius, radius);
    let impact = Impact::head_on(point, -Vec3::X);
    dent_map(&ball, &impact, &DentParams::new(d), Some(bunny.mean_edge_length())).unwrap()
}

/// A seeded random map of side `res` in a random frame around `centre`, with some exactly-zero
/// cells and a random falloff (one of the four codes).
fn random_dent(rng: &mut SplitMix64, target: usize, res: u32, centre: Vec3) -> Dent {
    let unit = |rng: &mut SplitMix64| {
        Vec3::new(rng.range_f32(-1.0, 1.0), rng.range_f32(-1.0, 1.0), rng.range_f32(-1.0, 1.0)).normalize()
    };
    let axis_z = unit(rng);
    let axis_x = axis_z.any_orthonormal_vector();
    let axis_y = axis_z.cross(axis_x);
    let d = rng.range_f32(0.05, 0.5);
    let cell_size = rng.range_f32(0.01, 0.1);
    let cells = (0..res * res)
        .map(|_| {
            if rng.next_f32() < 0.2 {
                [0.0; 4]
            } else {
                let h = rng.range_f32(0.0, d);
                [rng.range_f32(-d, d), rng.range_f32(-d, d), rng.range_f32(-d, d), h]
            }
        })
        .collect();
    let attenuation = match rng.below(4) {
        0 => Attenuation::Logistic,
        1 => Attenuation::Linear { scale: rng.range_f32(0.5, 2.0) },
        2 => Attenuation::None,
        _ => Attenuation::Custom(Arc::new(|z: f32, d: f32| 1.0 / (1.0 + (z / d) * (z / d)))),
    };
    let (falloff, falloff_scale, table) = cpu::falloff_table(&attenuation, d);
    let grid = GridUniform {
        origin: centre.to_array(),
        cell_size,
        axis_x: axis_x.to_array(),
        res,
        axis_y: axis_y.to_array(),
        _pad0: 0,
        axis_z: axis_z.to_array(),
        _pad1: 0,
    };
    let params = DisplaceParams {
        grid,
        dent_distance: d,
        falloff,
        falloff_scale,
        vertex_count: 0,
        vertex_offset: 0,
        cell_offset: 0,
        table_offset: 0,
        table_len: table.len() as u32,
    };
    Dent { target, params, cells, table }
}

/// Random points around a dent's grid: in the plane up to two cells past the border on each side
/// (so some are off the map), in depth from 2d in front to 9d behind (past the table's 8d).
fn cloud_around(rng: &mut SplitMix64, dent: &Dent, count: usize) -> Vec<Vec3> {
    let g = &dent.params.grid;
    let half = (0.5 * g.res as f32 + 2.0) * g.cell_size;
    let d = dent.params.dent_distance;
    let [o, x, y, z] = [g.origin, g.axis_x, g.axis_y, g.axis_z].map(Vec3::from_array);
    (0..count)
        .map(|_| {
            o + rng.range_f32(-half, half) * x + rng.range_f32(-half, half) * y + rng.range_f32(-2.0 * d, 9.0 * d) * z
        })
        .collect()
}

/// Grid coordinates (column, row) of `p` in f64, for telling off-map vertices apart.
fn grid_coords(g: &GridUniform, p: Vec3) -> (f64, f64) {
    let r = (p - Vec3::from_array(g.origin)).as_dvec3();
    let shift = 0.5 * g.res as f64 - 0.5;
    let h = g.cell_size as f64;
    (r.dot(Vec3::from_array(g.axis_x).as_dvec3()) / h + shift, r.dot(Vec3::from_array(g.axis_y).as_dvec3()) / h + shift)
}

fn a_sphere_dents_the_dense_bunny_like_the_cpu(context: &'static GpuContext) {
    let bunny = mesh::builtin("bunny-dense").unwrap();
    let map = bunny_map(&bunny, 0.3, 1.0);
    let dent = Dent::from_map(0, &map, &Attenuation::Logistic);
    let reports = parity(context, "bunny-dense", &[bunny.positions().to_vec()], &[&dent]);
    assert!(reports[0].moved > 100, "the dent must move a patch of the bunny");
}

fn every_falloff_on_a_block_matches_the_cpu(context: &'static GpuContext) {
    let block = mesh::builtin("block").unwrap();
    let map = block_map(0.0, &DentParams::new(0.3), &block);
    let attenuations = [
        Attenuation::Logistic,
        Attenuation::Linear { scale: 1.0 },
        Attenuation::Linear { scale: 0.5 },
        Attenuation::None,
        Attenuation::Custom(Arc::new(|z: f32, d: f32| (-(z / d) * (z / d)).exp())),
    ];
    // Five copies of the block, one falloff each, in one batch (one dispatch: one dent per target).
    let targets = vec![block.positions().to_vec(); attenuations.len()];
    let dents: Vec<Dent> = attenuations.iter().enumerate().map(|(t, a)| Dent::from_map(t, &map, a)).collect();
    assert_eq!(dents[4].params.falloff, falloff::TABLE);
    let reports = parity(context, "block falloffs", &targets, &dents.iter().collect::<Vec<_>>());
    // The back face (y = −0.5, depth 1 = 3.3d) moves under the logistic and no falloff only.
    let back = |t: usize| {
        let gpu = gpu_batch(context, &targets[t..t + 1], &[&Dent::from_map(0, &map, &attenuations[t])]);
        block.positions().iter().zip(&gpu[0].moved).any(|(p, &m)| m && p.y < -0.49)
    };
    assert!(back(0) && back(3) && !back(1) && !back(2));
    assert!(reports.iter().all(|r| r.moved > 100));
}

fn a_glancing_map_matches_the_cpu(context: &'static GpuContext) {
    let block = mesh::builtin("block-fine").unwrap();
    let params = DentParams { widen: 2.0, resolution: Resolution::Fixed(64), ..DentParams::new(0.25) };
    let map = block_map(60.0, &params, &block);
    assert!(map.grid.res > 64, "the glancing map is stretched");
    let dent = Dent::from_map(0, &map, &Attenuation::Logistic);
    let reports = parity(context, "glancing", &[block.positions().to_vec()], &[&dent]);
    assert!(reports[0].moved > 100);
}

fn random_maps_at_several_resolutions_match_the_cpu_and_leave_off_map_vertices_alone(context: &'static GpuContext) {
    let mut rng = SplitMix64::new(0x5eed_d15c);
    let mut falloffs_seen = [false; 4];
    for res in [1, 7, 64, 200] {
        for _ in 0..3 {
            let centre = Vec3::new(rng.range_f32(-5.0, 5.0), 2.0, 1.0);
            let dent = random_dent(&mut rng, 0, res, centre);
            let cloud = cloud_around(&mut rng, &dent, 4000);
            falloffs_seen[dent.params.falloff as usize] = true;
            let what = format!("random res {res}, falloff {}", dent.params.falloff);
            let reports = parity(context, &what, std::slice::from_ref(&cloud), &[&dent]);
            assert!(reports[0].moved > 100, "{what}: too few vertices on the map");
            // Off the map (with a margin for rounding): bit-for-bit unchanged, not flagged.
            let gpu = gpu_batch(context, std::slice::from_ref(&cloud), &[&dent]);
            let hi = res as f64;
            let mut off = 0;
            for (k, p) in cloud.iter().enumerate() {
                let (x, y) = grid_coords(&dent.params.grid, *p);
                if x < -1.0 - 1e-3 || y < -1.0 - 1e-3 || x > hi + 1e-3 || y > hi + 1e-3 {
                    assert_eq!(gpu[0].positions[k].to_array().map(f32::to_bits), p.to_array().map(f32::to_bits));
                    assert!(!gpu[0].moved[k], "{what}: off-map vertex {k} flagged as moved");
                    off += 1;
                }
            }
            assert!(off > 100, "{what}: too few vertices off the map ({off})");
        }
    }
    assert_eq!(falloffs_seen, [true; 4], "the seed must draw every falloff code");
}

fn a_batch_applies_dents_on_one_target_in_submission_order(context: &'static GpuContext) {
    let mut rng = SplitMix64::new(42);
    let bunny = mesh::builtin("bunny-dense").unwrap();
    let block = mesh::builtin("block").unwrap();
    let centre = Vec3::new(0.0, 3.0, 0.0);
    let probe = random_dent(&mut rng, 2, 64, centre);
    let cloud = cloud_around(&mut rng, &probe, 3000);
    let targets = vec![bunny.positions().to_vec(), block.positions().to_vec(), cloud];

    let head_on = bunny_map(&bunny, 0.3, 1.0);
    // A glancing hit at the same spot: it samples the first dent's output, so order matters.
    let point = bunny.support_point(Vec3::X);
    let velocity = Vec3::new(-1.0, 0.0, 1.0);
    let ball = sphere_at(point - velocity.normalize() * 0.5, 0.5);
    let glancing = dent_map(
        &ball,
        &Impact { point, normal: -Vec3::X, relative_velocity: velocity },
        &DentParams { resolution: Resolution::Fixed(48), ..DentParams::new(0.4) },
        None,
    )
    .unwrap();
    let block_dent = block_map(0.0, &DentParams { resolution: Resolution::Fixed(25), ..DentParams::new(0.2) }, &block);
    let dents = [
        Dent::from_map(0, &head_on, &Attenuation::Logistic),
        random_dent(&mut rng, 2, 7, centre),
        Dent::from_map(1, &block_dent, &Attenuation::Linear { scale: 1.5 }),
        Dent::from_map(0, &glancing, &Attenuation::Custom(Arc::new(|z: f32, d: f32| 1.0 / (1.0 + z / d)))),
        probe,
        random_dent(&mut rng, 2, 1, centre),
    ];
    let in_order: Vec<&Dent> = dents.iter().collect();
    let reports = parity(context, "batch", &targets, &in_order);
    assert!(reports.iter().all(|r| r.moved > 100));

    // The test can tell the order: the two bunny dents swapped give a result outside tolerance.
    let swapped: Vec<&Dent> = [3, 1, 2, 0, 4, 5].iter().map(|&k| &dents[k]).collect();
    let gpu = gpu_batch(context, &targets, &in_order);
    let cpu_swapped = cpu_batch(&targets, &swapped);
    let worst =
        gpu[0].positions.iter().zip(&cpu_swapped[0].0).map(|(g, c)| (*g - *c).abs().max_element()).fold(0.0, f32::max);
    assert!(worst > 1e-3, "swapping the bunny's dents changed nothing ({worst})");
}

/// More targets than one dispatch serves ([`MAX_RUNS`]): the batch is cut into two dispatches,
/// the second also holding targets with two dents (their second submitted after every other
/// dent), and every target still matches the CPU (tolerances as [`parity`]).
fn more_targets_than_one_dispatch_serves(context: &'static GpuContext) {
    let mut rng = SplitMix64::new(0xd15);
    let count = MAX_RUNS + 37;
    let mut dents: Vec<Dent> = (0..count).map(|t| random_dent(&mut rng, t, 6, Vec3::ZERO)).collect();
    let targets: Vec<Vec<Vec3>> = dents.iter().map(|d| cloud_around(&mut rng, d, 24)).collect();
    dents.extend((count - 5..count).map(|t| random_dent(&mut rng, t, 6, Vec3::ZERO)));
    let order: Vec<&Dent> = dents.iter().collect();
    let (gpu, cpu) = (gpu_batch(context, &targets, &order), cpu_batch(&targets, &order));
    let mut moved_targets = 0;
    for t in 0..count {
        let on_t: Vec<&&Dent> = order.iter().filter(|d| d.target == t).collect();
        let dent_tol: f32 = on_t.iter().map(|d| d.tolerance()).sum();
        let report = check_target(&format!("target {t}"), &targets[t], &gpu[t], &cpu[t], dent_tol, on_t.len());
        moved_targets += usize::from(report.moved > 0);
    }
    // Most clouds lie partly on their map (a test that moved nothing would prove nothing).
    assert!(moved_targets * 10 >= count * 9, "only {moved_targets} of {count} targets moved");
}

fn runs_group_each_targets_dents_in_submission_order() {
    let on = |vertex_offset: u32, vertex_count: u32| DisplaceParams { vertex_offset, vertex_count, ..plain_params() };
    // Targets A = 0..10, B = 10..30, C = 30..31; submission order A B A C A B.
    let params = [on(0, 10), on(10, 20), on(0, 10), on(30, 1), on(0, 10), on(10, 20)];
    assert_eq!(runs(&params).unwrap(), vec![vec![0, 2, 4], vec![1, 5], vec![3]]);
    // Overlapping ranges that are not the same target cannot be ordered.
    assert!(runs(&[on(0, 10), on(5, 10)]).is_err());
    assert!(runs(&[]).unwrap().is_empty());
}

fn clear_moved_resets_the_flags_only(context: &'static GpuContext) {
    let displace = Displace::new(context).unwrap();
    let vertices: Vec<[f32; 4]> = (0..1000).map(|k| [k as f32, -(k as f32), 0.5, 1.0]).collect();
    let positions = buffers::storage(context, "positions", &vertices);
    let mut encoder = context.device.create_command_encoder(&Default::default());
    displace.encode_clear_moved(context, &mut encoder, &positions).unwrap();
    context.queue.submit([encoder.finish()]);
    let out: Vec<[f32; 4]> = buffers::read_back(context, &positions, vertices.len()).unwrap();
    assert!(out.iter().zip(&vertices).all(|(o, v)| o[..3] == v[..3] && o[3] == 0.0));
}

fn plain_params() -> DisplaceParams {
    DisplaceParams {
        grid: GridUniform {
            origin: [0.0; 3],
            cell_size: 1.0,
            axis_x: [1.0, 0.0, 0.0],
            res: 1,
            axis_y: [0.0, 1.0, 0.0],
            _pad0: 0,
            axis_z: [0.0, 0.0, 1.0],
            _pad1: 0,
        },
        dent_distance: 1.0,
        falloff: falloff::NONE,
        falloff_scale: 0.0,
        vertex_count: 0,
        vertex_offset: 0,
        cell_offset: 0,
        table_offset: 0,
        table_len: 0,
    }
}

gpu_test_main! {
    plain: [runs_group_each_targets_dents_in_submission_order],
    gpu: [
        a_sphere_dents_the_dense_bunny_like_the_cpu,
        every_falloff_on_a_block_matches_the_cpu,
        a_glancing_map_matches_the_cpu,
        random_maps_at_several_resolutions_match_the_cpu_and_leave_off_map_vertices_alone,
        a_batch_applies_dents_on_one_target_in_submission_order,
        more_targets_than_one_dispatch_serves,
        clear_moved_resets_the_flags_only,
    ],
}
