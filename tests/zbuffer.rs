//! Guards the Z-buffer profile kernel `cpu::zbuffer` (paper §3.2, ARCHITECTURE.md §4): spheres against
//! the analytic cap, the bunny against an f64 ray cast, thin and edge-on features, empty and
//! degenerate input.

mod common;

use common::SplitMix64;
use common::view::{View, builtin, clip_to_cell};
use dentbend::cpu::zbuffer;
use glam::{Quat, Vec3};

// ---------------------------------------------------------------------------------------------
// Set-up helpers.

// ---------------------------------------------------------------------------------------------
// f64 references.

/// Möller–Trumbore in f64: the largest depth s (along `view.z`, from `view.origin`) at which the
/// line through the centre of cell (`row`, `col`) along `view.z` meets the closed triangle; rays
/// parallel to the triangle's plane (grazing) do not count.
fn ray_cast(view: &View, positions: &[Vec3], faces: &[[u32; 3]], row: usize, col: usize) -> Option<f64> {
    let o = view.world(col as f64, row as f64, 0.0);
    let dir = view.z.as_dvec3();
    let mut best: Option<f64> = None;
    for f in faces {
        let [a, b, c] = f.map(|i| positions[i as usize].as_dvec3());
        let (e1, e2) = (b - a, c - a);
        let p = dir.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-300 {
            continue;
        }
        let inv = 1.0 / det;
        let tv = o - a;
        let u = tv.dot(p) * inv;
        let q = tv.cross(e1);
        let v = dir.dot(q) * inv;
        if u < 0.0 || v < 0.0 || u + v > 1.0 {
            continue;
        }
        let t = e2.dot(q) * inv;
        best = Some(best.map_or(t, |s: f64| s.max(t)));
    }
    best
}

/// Profile of a ray cast: `max(0, d + s)`, 0 on a miss.
fn ray_cast_profile(view: &View, positions: &[Vec3], faces: &[[u32; 3]]) -> Vec<f64> {
    let res = view.res as usize;
    let d = view.d as f64;
    (0..res * res)
        .map(|cell| ray_cast(view, positions, faces, cell / res, cell % res).map_or(0.0, |s| (d + s).max(0.0)))
        .collect()
}

/// Per cell, the range `(min, max)` of depth s over the part of the surface lying over the closed
/// cell square (grown by a hair for f32 rounding), or `None` where none does. Every sample the
/// kernel takes for a cell lies over that square.
fn cell_depth_ranges(view: &View, positions: &[Vec3], faces: &[[u32; 3]]) -> Vec<Option<(f64, f64)>> {
    let res = view.res as usize;
    let half = 0.5 + 1e-4;
    let mut ranges = vec![None; res * res];
    for f in faces {
        let tri = f.map(|i| view.grid(positions[i as usize]));
        let lo = tri[0].min(tri[1]).min(tri[2]);
        let hi = tri[0].max(tri[1]).max(tri[2]);
        let c0 = (lo.x - half).ceil().max(0.0) as usize;
        let c1 = ((hi.x + half).floor().min(res as f64 - 1.0)).max(-1.0);
        let r0 = (lo.y - half).ceil().max(0.0) as usize;
        let r1 = ((hi.y + half).floor().min(res as f64 - 1.0)).max(-1.0);
        if c1 < 0.0 || r1 < 0.0 {
            continue;
        }
        for row in r0..=r1 as usize {
            for col in c0..=c1 as usize {
                let clipped = clip_to_cell(&tri, col as f64, row as f64, half);
                for p in clipped {
                    let r: &mut Option<(f64, f64)> = &mut ranges[row * res + col];
                    *r = Some(r.map_or((p.z, p.z), |(a, b)| (a.min(p.z), b.max(p.z))));
                }
            }
        }
    }
    ranges
}

// ---------------------------------------------------------------------------------------------
// Checks shared by the tests.

/// Every value finite and in [0, d].
fn assert_in_range(profile: &[f32], d: f32) {
    for (cell, &p) in profile.iter().enumerate() {
        assert!(p.is_finite() && (0.0..=d).contains(&p), "cell {cell}: {p} outside [0, {d}]");
    }
}

/// 8-neighbours of `cell` on a `res × res` grid.
fn neighbours(cell: usize, res: usize) -> impl Iterator<Item = usize> {
    let (row, col) = ((cell / res) as isize, (cell % res) as isize);
    (-1..=1isize).flat_map(move |dr| {
        (-1..=1isize).filter_map(move |dc| {
            let (r, c) = (row + dr, col + dc);
            ((dr, dc) != (0, 0) && (0..res as isize).contains(&r) && (0..res as isize).contains(&c))
                .then_some(r as usize * res + c as usize)
        })
    })
}

/// Whether the non-zero cells form one 8-connected set.
fn is_connected(profile: &[f32], res: usize) -> bool {
    let lit: Vec<usize> = (0..profile.len()).filter(|&c| profile[c] > 0.0).collect();
    let Some(&start) = lit.first() else { return true };
    let mut seen = vec![false; profile.len()];
    let (mut stack, mut count) = (vec![start], 0);
    seen[start] = true;
    while let Some(c) = stack.pop() {
        count += 1;
        for n in neighbours(c, res) {
            if profile[n] > 0.0 && !seen[n] {
                seen[n] = true;
                stack.push(n);
            }
        }
    }
    count == lit.len()
}

// ---------------------------------------------------------------------------------------------
// Tests.

/// A finely tessellated sphere seen from several oblique directions matches the analytic cap
/// `P(r) = max(0, d − (R − √(R² − r²)))`, r = lateral distance of the cell centre from the centre
/// line, within bounds that follow from the tessellation and the kernel's sampling:
///
/// - below by the cap of the inscribed sphere: every face plane is at least R_in = R − sagitta
///   from the centre (sagitta ≈ R(1 − cos(edge angle/2)), here measured on the mesh: ≈ 1.1e-3·R), so
///   the mesh covers the ball of radius R_in and a centre ray meets it no deeper than that ball;
/// - above by the cap of the sphere itself (the mesh is inscribed) evaluated ¹⁄√2 cell closer to the
///   centre line, the farthest an edge or vertex sample lies from the centre of the cell it marks
///   (this is the one cell of silhouette dilation, and the slope × ½ cell rise of edge samples).
///
/// Heights are measured from the mesh's own tip, as the pipeline places the origin; f32 adds
/// ~1e-6·R.
#[test]
fn sphere_matches_analytic_cap() {
    let radius = 1.0f32;
    let centre = Vec3::new(0.3, -0.2, 0.7);
    // Icosphere of radius 1, 4 subdivisions (5120 triangles), moved off the origin.
    let (positions, faces) = builtin("sphere");
    let positions: Vec<Vec3> = positions.into_iter().map(|p| centre + radius * p).collect();
    let r_in = faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|i| (positions[i as usize] - centre).as_dvec3());
            (b - a).cross(c - a).normalize().dot(a).abs()
        })
        .fold(f64::INFINITY, f64::min);
    let (r, tol) = (radius as f64, 1e-5);
    assert!(r - r_in < 2e-3, "sagitta {}", r - r_in);

    let mut rng = SplitMix64::new(7);
    let mut dirs = vec![Vec3::new(1.0, 2.0, 3.0), Vec3::new(-0.2, 0.1, -1.0), Vec3::new(0.6, -0.8, 0.05)];
    for _ in 0..2 {
        dirs.push(Vec3::new(rng.range_f32(-1.0, 1.0), rng.range_f32(-1.0, 1.0), rng.range_f32(-1.0, 1.0)));
    }
    for dir in dirs {
        for d in [0.05f32, 0.3, 0.75] {
            let view = View::looking(dir, &positions, centre, 1.2 * radius, 160, d);
            let profile = view.profile(&positions, &faces);
            assert_in_range(&profile, d);
            let tip = positions.iter().map(|p| (*p - centre).dot(view.z)).fold(f32::NEG_INFINITY, f32::max) as f64;
            let top = profile.iter().copied().fold(0.0, f32::max);
            assert!((top - d).abs() < 1e-5, "dir {dir}, d {d}: max {top}");

            let (h, dd, res) = (view.h as f64, d as f64, view.res as usize);
            let reach = 0.7072 * h;
            let axis = view.grid(centre);
            let (mut worst_lo, mut worst_hi) = (0.0f64, 0.0f64);
            for (cell, &p) in profile.iter().enumerate() {
                let (row, col) = ((cell / res) as f64, (cell % res) as f64);
                let lateral = h * (row - axis.y).hypot(col - axis.x);
                let cap = |rad: f64, at: f64| {
                    if at < rad { (dd + (rad * rad - at * at).sqrt() - tip).max(0.0) } else { 0.0 }
                };
                let lower = cap(r_in, lateral);
                let upper = cap(r, (lateral - reach).max(0.0));
                let p = p as f64;
                assert!(
                    p >= lower - tol && p <= upper + tol,
                    "dir {dir}, d {d}, cell ({row}, {col}): {p} outside [{lower}, {upper}]"
                );
                let analytic = (dd - (r - (r * r - lateral * lateral).max(0.0).sqrt())).max(0.0);
                worst_lo = worst_lo.min(p - analytic);
                worst_hi = worst_hi.max(p - analytic);
            }
            eprintln!("sphere dir {dir} d {d}: profile − P(r) in [{worst_lo:.2e}, {worst_hi:.2e}], h = {h:.2e}");
        }
    }
}

/// The bunny from nine directions (axis-aligned and oblique) against an f64 Möller–Trumbore ray
/// cast through every cell centre, with d = 0.6 of its depth along the view so the ears are in.
///
/// - Where the ray cast hits, the kernel equals it up to `2e-5 + 1e-3·spread` (world units), where
///   `spread` is the depth range of the surface over the cell's square: the sample may sit up to
///   1e-3 cell off the true centre (f32 grid coordinates carry ~1.5e-5 cell of error, and near a
///   fold of the surface, where two layers meet at an edge through the centre, the barycentric
///   test can pick the other layer: seen up to ~2e-4 cell), which moves it along the surface's
///   slope (≤ spread per cell); plus ~40 ulp of heights up to ~6. Sampling anywhere else in the
///   cell, as a conservative rasterizer does, errs by ~0.2–0.5·spread and fails this. The one
///   exception is the tip's own cell, which holds d exactly (the tip vertex need not sit on a cell
///   centre).
/// - Every cell the kernel marks but the ray cast misses touches a ray-cast hit: one cell of
///   silhouette dilation, from the edge samples that keep thin features.
/// - No value exceeds the highest point of the surface over the cell's own square, since every
///   sample lies in its cell.
#[test]
fn bunny_matches_ray_cast() {
    let (positions, faces) = builtin("bunny");
    let (lo, hi) = positions.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), &p| (a.min(p), b.max(p)));
    let centre = 0.5 * (lo + hi);
    let dirs = [
        Vec3::Z,
        -Vec3::Z,
        Vec3::X,
        Vec3::Y,
        -Vec3::Y,
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(-1.0, -0.5, 2.0),
        Vec3::new(0.3, -1.0, -0.7),
        Vec3::new(-2.0, 0.4, -1.0),
    ];
    for dir in dirs {
        let z = dir.normalize();
        let depth = positions.iter().map(|p| p.dot(z)).fold(f32::NEG_INFINITY, f32::max)
            - positions.iter().map(|p| p.dot(z)).fold(f32::INFINITY, f32::min);
        let d = 0.6 * depth;
        let half = 0.5 * (hi - lo).length() + 0.05;
        let view = View::looking(dir, &positions, centre, half, 128, d);
        let res = view.res as usize;
        let tol = 1e-4; // f32 rounding of heights up to ~6 world units, for the upper bound
        let tip_cells: Vec<usize> = positions
            .iter()
            .map(|&p| view.grid(p))
            .filter(|g| g.z >= -1e-6 * depth as f64)
            .map(|g| (g.y.round() as usize).min(res - 1) * res + (g.x.round() as usize).min(res - 1))
            .collect();

        let profile = view.profile(&positions, &faces);
        assert_in_range(&profile, d);
        let top = profile.iter().copied().fold(0.0, f32::max);
        assert!((top - d).abs() < 1e-5 * depth, "dir {dir}: max {top} vs d {d}");

        let reference = ray_cast_profile(&view, &positions, &faces);
        let ranges = cell_depth_ranges(&view, &positions, &faces);
        let (mut both, mut dilated, mut worst) = (0, 0, 0.0f64);
        for cell in 0..res * res {
            let (p, rc) = (profile[cell] as f64, reference[cell]);
            let upper = ranges[cell].map_or(0.0, |(_, s)| (d as f64 + s).max(0.0));
            assert!(p <= upper + tol, "dir {dir}, cell {cell}: {p} above the surface over the cell {upper}");
            if rc > 0.0 && !tip_cells.contains(&cell) {
                both += 1;
                let spread = ranges[cell].map_or(0.0, |(lo, hi)| hi - lo);
                let close = 2e-5 + 1e-3 * spread;
                assert!(
                    (p - rc).abs() <= close,
                    "dir {dir}, cell {cell}: {p} but the ray cast gives {rc} (surface spread {spread})"
                );
                worst = worst.max((p - rc).abs());
            }
            if p > 0.0 && rc == 0.0 {
                dilated += 1;
                assert!(
                    neighbours(cell, res).any(|n| reference[n] > 0.0),
                    "dir {dir}, cell {cell}: marked ({p}) but no ray-cast hit next to it"
                );
            }
        }
        assert!(both > res * res / 10, "dir {dir}: profile covers only {both} cells");
        eprintln!(
            "bunny dir {dir}, d {d:.2}, h {:.3}: {both} cells hit, max |kernel − ray cast| {worst:.1e}; \
             {dilated} cells dilated at the silhouette",
            view.h
        );
    }
}

/// A needle (0.01 cell wide) and an edge-on triangle (its plane contains `axis_z`, so a ray cast
/// misses it everywhere) each leave a connected trail along their whole length, every column they
/// cross marked, with their height there (for the edge-on one, that of its front edge).
#[test]
fn thin_features_leave_a_trail() {
    let d = 10.0f32;
    let (a, b) = ((5.2f32, 10.3f32), (50.7f32, 40.1f32));
    let dir = Vec3::new(b.0 - a.0, b.1 - a.1, 0.0).normalize();
    let across = 0.01 * Vec3::new(-dir.y, dir.x, 0.0);
    for q in [Quat::IDENTITY, Quat::from_euler(glam::EulerRot::XYZ, 0.7, -1.1, 0.4)] {
        let view = View::world_aligned(64, d).rotated(q);
        let res = view.res as usize;
        let needle = [view.point(a.0, a.1, -6.0), view.point(b.0, b.1, -1.0), {
            let p = Vec3::new(b.0, b.1, -1.0) + across;
            view.point(p.x, p.y, p.z)
        }];
        let edge_on = [view.point(a.0, a.1, 0.0), view.point(b.0, b.1, -8.0), view.point(a.0, a.1, -20.0)];
        // (name, triangle, the part whose height the trail carries: for the edge-on triangle its
        // front edge, as a degenerate triangle).
        for (name, tri, front) in
            [("needle", needle, needle), ("edge-on", edge_on, [edge_on[0], edge_on[1], edge_on[1]])]
        {
            let faces = [[0, 1, 2]];
            let profile = view.profile(&tri, &faces);
            assert_in_range(&profile, d);
            if name == "edge-on" {
                assert!(ray_cast_profile(&view, &tri, &faces).iter().all(|&p| p == 0.0));
                assert!(profile.iter().any(|&p| p > d - 1e-4), "the tip's cell holds d");
            }
            assert!(is_connected(&profile, res), "{name}: trail broken");
            let ranges = cell_depth_ranges(&view, &front, &[[0, 1, 2]]);
            for (cell, &p) in profile.iter().enumerate() {
                if p > 0.0 {
                    let (s_lo, s_hi) = ranges[cell].unwrap_or_else(|| panic!("{name}: cell {cell} off the trail"));
                    let (lo, hi) = (d as f64 + s_lo, d as f64 + s_hi);
                    assert!(
                        (lo - 1e-4..=hi + 1e-4).contains(&(p as f64)),
                        "{name}, cell {cell}: {p} not in [{lo}, {hi}]"
                    );
                }
            }
            for col in 6..=50 {
                assert!((0..res).any(|row| profile[row * res + col] > 0.0), "{name}: column {col} empty");
            }
            for (x, y) in [a, b] {
                let cell = (y + 0.5).floor() as usize * res + (x + 0.5).floor() as usize;
                assert!(profile[cell] > 0.0, "{name}: end cell unmarked");
            }
        }
    }
}

/// Nothing lands on the grid: a sphere beside it, or a triangle wholly deeper than −d.
#[test]
fn empty_profiles() {
    let d = 0.5;
    let (positions, faces) = builtin("sphere");
    let mut view = View::looking(Vec3::new(0.2, 0.3, 1.0), &positions, Vec3::ZERO, 1.5, 64, d);
    view.origin += 10.0 * view.x;
    assert!(view.profile(&positions, &faces).iter().all(|&p| p == 0.0));

    let view = View::world_aligned(32, 2.0);
    let deep = [Vec3::new(-10.0, -8.0, -2.5), Vec3::new(9.0, -7.0, -6.0), Vec3::new(0.0, 12.0, -2.0)];
    assert!(view.profile(&deep, &[[0, 1, 2]]).iter().all(|&p| p == 0.0));
}

/// A flat triangle far larger than the grid covers every cell at its height, at res 2048 too;
/// enormous, degenerate and out-of-range input neither panics nor leaves [0, d].
#[test]
fn huge_degenerate_and_bad_input() {
    let d = 1.0;
    for res in [16, 2048] {
        let view = View::world_aligned(res, d);
        let big = [Vec3::new(-1e7, -1e7, -0.25), Vec3::new(3e7, -1e7, -0.25), Vec3::new(-1e7, 3e7, -0.25)];
        let profile = view.profile(&big, &[[0, 1, 2]]);
        assert!(profile.iter().all(|&p| (p - 0.75).abs() < 1e-6), "res {res}");
    }

    let view = View::world_aligned(64, d);
    let positions = [
        Vec3::new(1e30, 0.0, 0.0),
        Vec3::new(-1e30, 1e30, -0.5),
        Vec3::new(0.0, -1e30, 0.0),
        Vec3::new(f32::MAX, -f32::MAX, 0.0),
        Vec3::new(-f32::MAX, f32::MAX, -f32::MAX),
        Vec3::new(2.0, 3.0, -0.5),
        Vec3::new(2.0, 3.0, -0.5),
        Vec3::new(-5.0, 3.0, -0.2),
        Vec3::new(7.0, 3.0, 0.0),
    ];
    let faces = [[0, 1, 2], [3, 4, 5], [0, 3, 4], [5, 6, 5], [5, 7, 8], [1, 2, 5], [0, 1, 99]];
    let mut profile = vec![f32::NAN; 64 * 64];
    let mut params = view.params(faces.len() + 3);
    zbuffer(&params, &positions, &faces, &mut profile);
    assert_in_range(&profile, d);
    // The point triangle lands in its own cell; the collinear one is a row of cells.
    let cell = |x: f32, y: f32| (y + 32.0) as usize * 64 + (x + 32.0) as usize;
    assert!(profile[cell(2.0, 3.0)] >= 0.5);
    assert!((-5..=7).all(|x| profile[cell(x as f32, 3.0)] > 0.0));

    let mut short = vec![f32::NAN; 100];
    zbuffer(&params, &positions, &faces, &mut short);
    assert_in_range(&short, d);
    params.grid.cell_size = 0.0;
    zbuffer(&params, &positions, &faces, &mut profile);
    assert!(profile.iter().all(|&p| p == 0.0));
}
