//! Parity of the GPU Z-buffer (`shaders/zbuffer.wgsl`, `gpu::zbuffer::Zbuffer`) with its CPU twin
//! `cpu::zbuffer`: the bunny from several directions at 64² and 200², a tessellated sphere, thin
//! and edge-on triangles, random triangle soups at 1², 7² and 64², bad input, and batches of
//! dents with different projectiles and resolutions in one dispatch.
//!
//! Tolerance (see [`compare`]): the WGSL performs the CPU's f32 operations in the same order, but
//! a GPU may contract `a·b + c` into one FMA and divide to 2.5 ulp (WGSL's accuracy for `/`), so
//! every height may differ by a few ulps of the values it is computed from, and a cell centre
//! within ~1e-5 cell of a projected triangle edge may fall inside a different triangle than on
//! the CPU (the barycentric test's tolerance is 1e-5). Such a cell takes a height of the surface
//! over it (a neighbouring triangle's centre sample, or an edge sample when the edge is a
//! silhouette), so it is allowed the range of the surface over its square, from an f64 clip.
//!
//! On Mesa's llvmpipe (lavapipe, the CI adapter) every cell must be bit-identical instead: it
//! rounds each WGSL operation separately and divides exactly, as the CPU does (every cell of every
//! case here compares equal there), so a change in the shader's operation order shows up.

mod common;

use common::SplitMix64;
use common::view::{View, builtin, clip_to_cell};
use dentbend::cpu::{ZbufferParams, zbuffer};
use dentbend::gpu::GpuContext;
use dentbend::gpu::zbuffer::{Zbuffer, ZbufferDent};
use glam::{DVec2, Quat, Vec3};

// ---------------------------------------------------------------------------------------------
// Set-up helpers (as in tests/zbuffer.rs).

/// One dent of a test: a view and a projectile.
struct Case {
    name: String,
    view: View,
    positions: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
    /// Triangles read (the CPU twin caps it at `faces.len()`).
    face_count: usize,
}

impl Case {
    fn new(name: impl Into<String>, view: View, positions: Vec<Vec3>, faces: Vec<[u32; 3]>) -> Self {
        let face_count = faces.len();
        Self { name: name.into(), view, positions, faces, face_count }
    }

    fn params(&self) -> ZbufferParams {
        self.view.params(self.face_count)
    }

    fn cpu(&self) -> Vec<f32> {
        let mut out = vec![f32::NAN; (self.view.res as usize).pow(2)];
        zbuffer(&self.params(), &self.positions, &self.faces, &mut out);
        out
    }

    fn dent(&self) -> ZbufferDent<'_> {
        ZbufferDent { params: self.params(), positions: &self.positions, faces: &self.faces }
    }
}

/// The compiled kernel.
fn kernel(context: &GpuContext) -> Zbuffer {
    Zbuffer::new(context).expect("zbuffer kernel compiles")
}

/// The bunny seen along `dir`, d = 0.6 of its depth along the view, at `res`².
fn bunny_case(dir: Vec3, res: u32) -> Case {
    let (positions, faces) = builtin("bunny");
    let (lo, hi) = positions.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), &p| (a.min(p), b.max(p)));
    let z = dir.normalize();
    let depth = positions.iter().map(|p| p.dot(z)).fold(f32::NEG_INFINITY, f32::max)
        - positions.iter().map(|p| p.dot(z)).fold(f32::INFINITY, f32::min);
    let half = 0.5 * (hi - lo).length() + 0.05;
    let view = View::looking(dir, &positions, 0.5 * (lo + hi), half, res, 0.6 * depth);
    Case::new(format!("bunny {dir} {res}²"), view, positions, faces)
}

/// The unit icosphere (5120 triangles) moved off the origin, seen along `dir` at `res`².
fn sphere_case(dir: Vec3, res: u32, d: f32) -> Case {
    let (positions, faces) = builtin("sphere");
    let centre = Vec3::new(0.3, -0.2, 0.7);
    let positions: Vec<Vec3> = positions.into_iter().map(|p| centre + p).collect();
    let view = View::looking(dir, &positions, centre, 1.2, res, d);
    Case::new(format!("sphere {dir} {res}² d {d}"), view, positions, faces)
}

/// `count` random triangles of a few cells (and some spanning the grid, some slivers) around
/// and across a `res`² grid turned by a random rotation.
fn soup_case(seed: u64, res: u32, count: usize) -> Case {
    let mut rng = SplitMix64::new(seed);
    let d = rng.range_f32(0.5, 4.0);
    let q = Quat::from_euler(
        glam::EulerRot::XYZ,
        rng.range_f32(-3.0, 3.0),
        rng.range_f32(-3.0, 3.0),
        rng.range_f32(-3.0, 3.0),
    );
    let mut view = View::world_aligned(res, d).rotated(q);
    view.h = rng.range_f32(0.05, 2.0);
    let r = res as f32;
    let (mut positions, mut faces) = (Vec::new(), Vec::new());
    for k in 0..count {
        let size = match k % 4 {
            0 => r,
            1 => 0.3,
            _ => 3.0,
        };
        let (cx, cy) = (rng.range_f32(-0.2 * r, 1.2 * r), rng.range_f32(-0.2 * r, 1.2 * r));
        let base = positions.len() as u32;
        for _ in 0..3 {
            let (col, row) = (cx + rng.range_f32(-size, size), cy + rng.range_f32(-size, size));
            positions.push(view.point(col, row, rng.range_f32(-1.5 * d, 0.3 * d)));
        }
        faces.push([base, base + 1, base + 2]);
    }
    Case::new(format!("soup seed {seed} {res}²"), view, positions, faces)
}

// ---------------------------------------------------------------------------------------------
// The comparison.

/// Relative tolerance of heights off edges, times the largest |value| a height is computed from
/// (d and the depth range of the projectile): the world → grid transform and the barycentric
/// interpolation round ~10 times, each error up to one ulp (2⁻²⁴ ≈ 6e-8) of such values, more
/// with FMA contraction and WGSL's 2.5-ulp division; 2e-6 leaves ~3× headroom.
const REL_TOL: f64 = 2e-6;

/// Distance (cells) of a cell centre from a projected triangle edge within which GPU and CPU may
/// disagree on which triangles contain it: their barycentrics differ by a few ulps of the grid
/// coordinates (~res · 6e-8 cell), and the test's tolerance band is 1e-5 of the triangle's
/// altitude; 1e-3 cell covers both for the triangles here.
const EDGE_BAND: f64 = 1e-3;

/// Per cell: whether its centre lies within [`EDGE_BAND`] of a projected edge or vertex of a
/// triangle that reaches above z = 0, and the range `(min, max)` of the height `d + s` over the
/// part of the surface lying over the cell square (grown by a hair), if any.
fn edge_cells(case: &Case) -> (Vec<bool>, Vec<Option<(f64, f64)>>) {
    let view = &case.view;
    let (res, d) = (view.res as usize, view.d as f64);
    let mut near = vec![false; res * res];
    let mut ranges: Vec<Option<(f64, f64)>> = vec![None; res * res];
    let half = 0.5 + 1e-4;
    for face in &case.faces[..case.face_count.min(case.faces.len())] {
        let Some(tri) =
            face.iter().map(|&v| case.positions.get(v as usize).map(|&p| view.grid(p))).collect::<Option<Vec<_>>>()
        else {
            continue;
        };
        if tri.iter().all(|p| p.z + d <= 0.0) || tri.iter().any(|p| !p.is_finite()) {
            continue;
        }
        let lo = tri[0].min(tri[1]).min(tri[2]);
        let hi = tri[0].max(tri[1]).max(tri[2]);
        let c0 = (lo.x - half).ceil().max(0.0);
        let c1 = (hi.x + half).floor().min(res as f64 - 1.0);
        let r0 = (lo.y - half).ceil().max(0.0);
        let r1 = (hi.y + half).floor().min(res as f64 - 1.0);
        if c1 < c0 || r1 < r0 {
            continue;
        }
        for row in r0 as usize..=r1 as usize {
            for col in c0 as usize..=c1 as usize {
                let p = DVec2::new(col as f64, row as f64);
                let cell = row * res + col;
                if (0..3).any(|k| segment_distance(p, tri[k].truncate(), tri[(k + 1) % 3].truncate()) < EDGE_BAND) {
                    near[cell] = true;
                }
                for q in clip_to_cell(&tri, col as f64, row as f64, half) {
                    let r = &mut ranges[cell];
                    *r = Some(r.map_or((q.z + d, q.z + d), |(a, b)| (a.min(q.z + d), b.max(q.z + d))));
                }
            }
        }
    }
    (near, ranges)
}

/// Distance from `p` to segment `a`–`b`.
fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 { ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
    (a + t * ab - p).length()
}

/// What [`compare`] saw.
#[derive(Debug, Default)]
struct Stats {
    cells: usize,
    exact: usize,
    /// Cells off edges that differ, and their largest difference.
    off_edge: usize,
    worst_off_edge: f64,
    /// Cells near an edge that differ by more than the tolerance (within the surface range).
    flipped: usize,
}

/// Asserts that `gpu` matches the CPU twin's `cpu` profile of `case`: every value in [0, d];
/// off edges within `REL_TOL · scale`; cells near a projected edge (see [`EDGE_BAND`]) anywhere
/// between the CPU's value and the surface heights over the cell, and few of them; with `exact`,
/// every cell bit-identical.
fn compare(case: &Case, gpu: &[f32], cpu: &[f32], exact: bool) -> Stats {
    let view = &case.view;
    let (res, d) = (view.res as usize, view.d as f64);
    assert_eq!(gpu.len(), res * res, "{}: profile length", case.name);
    let depth = case
        .positions
        .iter()
        .map(|&p| view.grid(p).z.abs())
        .filter(|s| s.is_finite() && *s < 1e3 * d)
        .fold(0.0, f64::max);
    let tol = REL_TOL * (d + depth);
    let (near, ranges) = edge_cells(case);
    let mut stats = Stats { cells: res * res, ..Default::default() };
    for cell in 0..res * res {
        let (g, c) = (gpu[cell] as f64, cpu[cell] as f64);
        let (row, col) = (cell / res, cell % res);
        assert!(g.is_finite() && (0.0..=d).contains(&g), "{}: cell ({row}, {col}) = {g} outside [0, {d}]", case.name);
        assert!(
            !exact || gpu[cell].to_bits() == cpu[cell].to_bits(),
            "{}: cell ({row}, {col}): GPU {g} ≠ CPU {c}, on an adapter that rounds as the CPU does",
            case.name
        );
        if g == c {
            stats.exact += 1;
            continue;
        }
        let diff = (g - c).abs();
        if diff <= tol {
            stats.off_edge += 1;
            stats.worst_off_edge = stats.worst_off_edge.max(diff);
            continue;
        }
        let (lo, hi) = ranges[cell].map_or((c, c), |(lo, hi)| (lo.min(c), hi.max(c)));
        assert!(
            near[cell] && g >= lo.max(0.0) - tol && g <= hi.min(d) + tol,
            "{}: cell ({row}, {col}): GPU {g}, CPU {c} (|Δ| {diff:.2e} > {tol:.2e}; near an edge: {}, surface over \
             the cell {lo}..{hi})",
            case.name,
            near[cell]
        );
        stats.flipped += 1;
    }
    // Flips are rare: a 1e-3-cell band around the edges holds a few cells in a thousand.
    assert!(stats.flipped <= 2 + stats.cells / 500, "{}: {} cells flipped", case.name, stats.flipped);
    eprintln!(
        "{}: {} cells, {} exact, {} within {tol:.1e} (worst {:.1e}), {} flipped near an edge",
        case.name, stats.cells, stats.exact, stats.off_edge, stats.worst_off_edge, stats.flipped
    );
    stats
}

/// Runs `cases` as one GPU batch and compares every dent with its CPU twin.
fn check_batch(zbuffer: &Zbuffer, context: &GpuContext, cases: &[Case]) -> Vec<Vec<f32>> {
    let dents: Vec<ZbufferDent> = cases.iter().map(Case::dent).collect();
    let gpu = zbuffer.run_batch(context, &dents).expect("GPU batch runs");
    assert_eq!(gpu.len(), cases.len());
    let exact = context.info.name.contains("llvmpipe");
    for (case, profile) in cases.iter().zip(&gpu) {
        compare(case, profile, &case.cpu(), exact);
    }
    gpu
}

// ---------------------------------------------------------------------------------------------
// Tests.

/// The bunny (non-convex: ears, folds) from axis-aligned and oblique directions at 64² and 200².
fn bunny_from_several_directions(context: &'static GpuContext) {
    let zbuffer = kernel(context);
    let dirs =
        [Vec3::Z, -Vec3::Y, Vec3::X, Vec3::new(1.0, 1.0, 1.0), Vec3::new(-1.0, -0.5, 2.0), Vec3::new(0.3, -1.0, -0.7)];
    for res in [64, 200] {
        for dir in dirs {
            check_batch(&zbuffer, context, &[bunny_case(dir, res)]);
        }
    }
}

/// A finely tessellated sphere from oblique directions, with shallow and deep dent distances.
fn tessellated_sphere(context: &'static GpuContext) {
    let zbuffer = kernel(context);
    for (dir, d) in
        [(Vec3::new(1.0, 2.0, 3.0), 0.05), (Vec3::new(-0.2, 0.1, -1.0), 0.3), (Vec3::new(0.6, -0.8, 0.05), 0.75)]
    {
        check_batch(&zbuffer, context, &[sphere_case(dir, 160, d)]);
    }
}

/// A needle (0.01 cell wide) and an edge-on triangle (its plane contains `axis_z`), each alone and
/// under a rotated view: only edge and tip samples mark them.
fn thin_and_edge_on_triangles(context: &'static GpuContext) {
    let zbuffer = kernel(context);
    let d = 10.0f32;
    let (a, b) = ((5.2f32, 10.3f32), (50.7f32, 40.1f32));
    let dir = Vec3::new(b.0 - a.0, b.1 - a.1, 0.0).normalize();
    let across = 0.01 * Vec3::new(-dir.y, dir.x, 0.0);
    let mut cases = Vec::new();
    for (k, q) in [Quat::IDENTITY, Quat::from_euler(glam::EulerRot::XYZ, 0.7, -1.1, 0.4)].into_iter().enumerate() {
        let view = View::world_aligned(64, d).rotated(q);
        let tip = Vec3::new(b.0, b.1, -1.0) + across;
        let needle = vec![view.point(a.0, a.1, -6.0), view.point(b.0, b.1, -1.0), view.point(tip.x, tip.y, tip.z)];
        let edge_on = vec![view.point(a.0, a.1, 0.0), view.point(b.0, b.1, -8.0), view.point(a.0, a.1, -20.0)];
        // Vertical and horizontal slivers, a point and a segment (collinear corners).
        let slivers = vec![
            view.point(20.0, 3.0, -1.0),
            view.point(20.004, 60.0, -3.0),
            view.point(20.0, 60.0, -2.0),
            view.point(2.0, 33.5, -0.5),
            view.point(61.0, 33.5, -4.0),
            view.point(30.0, 33.5, -2.0),
            view.point(40.3, 20.6, -0.25),
        ];
        let sliver_faces = vec![[0, 1, 2], [3, 4, 5], [6, 6, 6], [3, 5, 4]];
        cases.push(Case::new(format!("needle {k}"), view, needle, vec![[0, 1, 2]]));
        cases.push(Case::new(format!("edge-on {k}"), view, edge_on, vec![[0, 1, 2]]));
        cases.push(Case::new(format!("slivers {k}"), view, slivers, sliver_faces));
    }
    let gpu = check_batch(&zbuffer, context, &cases);
    for (case, profile) in cases.iter().zip(&gpu) {
        assert!(profile.iter().filter(|&&p| p > 0.0).count() >= 40, "{}: trail too short", case.name);
    }
}

/// Random triangle soups (triangles of a few cells, slivers, and ones spanning the grid, partly
/// off it and partly below z = 0) at 1², 7² and 64².
fn random_triangle_soups(context: &'static GpuContext) {
    let zbuffer = kernel(context);
    for (seed, res, count) in [(1, 1, 20), (2, 7, 40), (3, 7, 3), (4, 64, 300), (5, 64, 2000)] {
        check_batch(&zbuffer, context, &[soup_case(seed, res, count)]);
    }
}

/// Enormous, non-finite, degenerate and out-of-range input (as in tests/zbuffer.rs), a
/// `face_count` past the triangles given, a flat triangle far larger than the grid at 1024² and a
/// sloped one across a 500² grid (25 and 9 tiles of `centres`, more cells than lavapipe lets one
/// invocation loop over), and invalid grids (zero cell size, zero d), which give all-zero
/// profiles.
fn bad_and_degenerate_input(context: &'static GpuContext) {
    let zbuffer = kernel(context);
    let d = 1.0;
    let positions = vec![
        Vec3::new(1e30, 0.0, 0.0),
        Vec3::new(-1e30, 1e30, -0.5),
        Vec3::new(0.0, -1e30, 0.0),
        Vec3::new(f32::MAX, -f32::MAX, 0.0),
        Vec3::new(-f32::MAX, f32::MAX, -f32::MAX),
        Vec3::new(2.0, 3.0, -0.5),
        Vec3::new(2.0, 3.0, -0.5),
        Vec3::new(-5.0, 3.0, -0.2),
        Vec3::new(7.0, 3.0, 0.0),
        Vec3::new(f32::NAN, 1.0, 0.0),
        Vec3::new(1.0, f32::INFINITY, 0.0),
    ];
    let faces =
        vec![[0, 1, 2], [3, 4, 5], [0, 3, 4], [5, 6, 5], [5, 7, 8], [1, 2, 5], [0, 1, 99], [9, 5, 8], [10, 7, 8]];
    let mut bad = Case::new("bad", View::world_aligned(64, d), positions.clone(), faces.clone());
    bad.face_count = faces.len() + 3;
    let big = vec![Vec3::new(-1e7, -1e7, -0.25), Vec3::new(3e7, -1e7, -0.25), Vec3::new(-1e7, 3e7, -0.25)];
    let mut flat = View::world_aligned(1024, d);
    flat.h = 0.5;
    let mut no_cell = Case::new("zero cell size", View::world_aligned(16, d), positions.clone(), faces.clone());
    no_cell.view.h = 0.0;
    let no_d = Case::new("zero d", View::world_aligned(16, 0.0), big.clone(), vec![[0, 1, 2]]);
    let view = View::world_aligned(500, 50.0).rotated(Quat::from_rotation_z(0.3));
    let sloped = vec![view.point(-30.0, -10.0, -7.0), view.point(560.0, 20.0, -50.0), view.point(200.0, 540.0, 0.0)];
    let cases = [
        bad,
        Case::new("big", flat, big, vec![[0, 1, 2]]),
        no_cell,
        no_d,
        Case::new("big sloped", view, sloped, vec![[0, 1, 2]]),
    ];
    let gpu = check_batch(&zbuffer, context, &cases);
    assert!(gpu[1].iter().all(|&p| (p - 0.75).abs() < 1e-6), "the big triangle covers the grid at its height");
    assert!(gpu[2].iter().chain(&gpu[3]).all(|&p| p == 0.0), "invalid grids give zeros");
}

/// Seven dents of different projectiles and resolutions (1² to 200²) in one dispatch: each
/// matches its CPU twin, and equals the same dent run alone bit for bit (dents do not interact).
fn a_batch_of_different_dents(context: &'static GpuContext) {
    let zbuffer = kernel(context);
    let cases = [
        bunny_case(Vec3::new(-1.0, -0.5, 2.0), 200),
        soup_case(11, 1, 10),
        sphere_case(Vec3::new(0.2, 1.0, -0.4), 64, 0.4),
        soup_case(12, 7, 30),
        bunny_case(Vec3::X, 37),
        soup_case(13, 64, 500),
        sphere_case(Vec3::new(-1.0, 0.3, 0.2), 128, 0.1),
    ];
    let batched = check_batch(&zbuffer, context, &cases);
    for (case, profile) in cases.iter().zip(&batched) {
        let alone = zbuffer.run_batch(context, &[case.dent()]).unwrap();
        assert!(alone[0].iter().zip(profile).all(|(a, b)| a.to_bits() == b.to_bits()), "{}: batch differs", case.name);
    }
    // Batching the same dent twice, with the bunny's triangles, changes nothing either.
    let twice = zbuffer.run_batch(context, &[cases[4].dent(), cases[4].dent()]).unwrap();
    assert_eq!(twice[0], batched[4]);
    assert_eq!(twice[1], batched[4]);
}

/// An empty batch gives nothing; a dent with no triangles a zero profile.
fn empty_input(context: &'static GpuContext) {
    let zbuffer = kernel(context);
    assert!(zbuffer.run_batch(context, &[]).unwrap().is_empty());
    let case = Case::new("no triangles", View::world_aligned(8, 1.0), vec![Vec3::ZERO], vec![]);
    let gpu = check_batch(&zbuffer, context, &[case]);
    assert!(gpu[0].iter().all(|&p| p == 0.0));
}

/// A grid too large for one binding is an error before anything is allocated.
fn oversized_batches_are_errors(context: &'static GpuContext) {
    let zbuffer = kernel(context);
    let case = Case::new("huge grid", View::world_aligned(100_000, 1.0), vec![Vec3::ZERO; 3], vec![[0, 1, 2]]);
    let error = zbuffer.run_batch(context, &[case.dent()]).unwrap_err();
    assert!(matches!(error, dentbend::gpu::GpuError::OverLimit { .. }), "{error}");
}

gpu_test_main! {
    gpu: [
        bunny_from_several_directions,
        tessellated_sphere,
        thin_and_edge_on_triangles,
        random_triangle_soups,
        bad_and_degenerate_input,
        a_batch_of_different_dents,
        empty_input,
        oversized_batches_are_errors,
    ],
}
