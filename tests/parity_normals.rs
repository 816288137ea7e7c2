//! Parity of the `normals` kernel (shaders/normals.wgsl) with `TriMesh::recompute_normals` and
//! `recompute_normals_near`: built-in meshes (the dense bunny, dented and not), a batch of
//! meshes of very different sizes, more targets than one dispatch takes, exact zeros for
//! isolated vertices and degenerate faces, and the moved-only mode.
//!
//! Tolerance. Each vertex sums its faces in ascending face order, the CPU's order, with the same
//! f32 operations (glam's cross product written out, then `1/sqrt(|n|²)`), so nothing but the
//! driver's rounding separates the two: WGSL (and naga's SPIR-V) leave the driver free to fuse a
//! multiply-add into one rounding and to reassociate, and `sqrt` and division may be off by a
//! few ulp. Each face normal then moves by a few ε·|e₁||e₂| (ε = 2⁻²⁴ the unit roundoff, e the
//! two edges), the sum of m ≈ 6 faces by a few more ε·Σ|e₁||e₂|, and normalizing divides by
//! |Σ n_f|. So a unit normal may move by about `8ε·κ` per component, with
//! `κ = Σ_f |e₁||e₂| / |Σ_f n_f|` ≥ 1 the sum's condition number (2–3 at a smooth vertex, large
//! where the faces nearly cancel); we allow `32ε·κ` (at least 2·10⁻⁶, i.e. ~1e-5 at κ ≈ 5).
//! Lavapipe leaves about a sixth of the bunny's normals bit-identical and the rest within 3.5ε·κ.
//! Zero normals of vertices without a proper face are exact.

mod common;

use common::SplitMix64;
use dentbend::glam::{DVec3, Vec3};
use dentbend::gpu::GpuContext;
use dentbend::gpu::normals::{MAX_TARGETS_PER_DISPATCH, Normals, NormalsTarget, adjacency};
use dentbend::{Attenuation, DentParams, Impact, TriMesh, cpu, dent_map, mesh};

/// Allowed error per component, in units of ε·κ (see the module comment).
const KAPPA_ULPS: f64 = 32.0;

fn gpu_normals(context: &GpuContext, targets: &[NormalsTarget<'_>]) -> Vec<Vec<Vec3>> {
    Normals::new(context).unwrap().run_batch(context, targets).unwrap()
}

fn all(mesh: &TriMesh) -> NormalsTarget<'_> {
    NormalsTarget { positions: mesh.positions(), faces: mesh.faces(), near: None }
}

/// κ of every vertex: Σ |e₁||e₂| over its faces divided by the length of the sum of their area
/// normals, in f64 (NaN where both vanish, infinite where only the sum does).
fn conditions(positions: &[Vec3], faces: &[[u32; 3]]) -> Vec<f64> {
    let mut scale = vec![0.0; positions.len()];
    let mut sum = vec![DVec3::ZERO; positions.len()];
    for face in faces {
        let [a, b, c] = face.map(|v| positions[v as usize].as_dvec3());
        let (e1, e2) = (b - a, c - a);
        for &v in face {
            scale[v as usize] += e1.length() * e2.length();
            sum[v as usize] += e1.cross(e2);
        }
    }
    scale.iter().zip(&sum).map(|(s, n)| s / n.length()).collect()
}

/// Asserts the GPU normals of one mesh against the CPU's; returns the largest error in units of
/// the tolerance.
fn check(what: &str, positions: &[Vec3], faces: &[[u32; 3]], gpu: &[Vec3], cpu: &[Vec3]) -> f64 {
    assert_eq!(gpu.len(), cpu.len(), "{what}: normal count");
    let kappa = conditions(positions, faces);
    let mut worst: f64 = 0.0;
    for (k, (g, c)) in gpu.iter().zip(cpu).enumerate() {
        if *c == Vec3::ZERO {
            // κ = 0/0: no face, or only faces with a repeated corner (an exactly zero edge), whose
            // products are zero on any GPU. κ = ∞: faces that cancel exactly on the CPU, whose
            // direction no rounding order pins down; a GPU may return any unit vector there.
            if kappa[k].is_nan() {
                assert_eq!(*g, Vec3::ZERO, "{what}: vertex {k} must have a zero normal");
            }
            continue;
        }
        let tol = (KAPPA_ULPS * f32::EPSILON as f64 / 2.0 * kappa[k].max(1.0)).max(2e-6);
        let error = (*g - *c).abs().max_element() as f64;
        assert!(error <= tol, "{what}: vertex {k}: GPU {g} vs CPU {c} (κ {}, tolerance {tol:e})", kappa[k]);
        worst = worst.max(error / tol);
    }
    let exact = gpu.iter().zip(cpu).filter(|(g, c)| g == c).count();
    eprintln!("{what}: {exact} of {} bit-identical, worst {worst:.3} of tolerance", cpu.len());
    worst
}

fn the_dense_bunny_matches_the_cpu_before_and_after_a_dent(context: &'static GpuContext) {
    let mut bunny = mesh::builtin("bunny-dense").unwrap();
    let gpu = gpu_normals(context, &[all(&bunny)]);
    check("bunny-dense", bunny.positions(), bunny.faces(), &gpu[0], bunny.normals());

    let point = bunny.support_point(Vec3::X);
    let ball = common::sphere_at(point + Vec3::X, 1.0);
    let map = dent_map(&ball, &Impact::head_on(point, -Vec3::X), &DentParams::new(0.4), None).unwrap();
    let report = map.apply(&mut bunny, &Attenuation::Logistic).unwrap();
    assert!(report.moved_vertices > 100);
    let gpu = gpu_normals(context, &[all(&bunny)]);
    check("dented bunny-dense", bunny.positions(), bunny.faces(), &gpu[0], bunny.normals());
}

fn a_batch_of_meshes_of_every_size_matches_the_cpu(context: &'static GpuContext) {
    let triangle = TriMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]).unwrap();
    let meshes: Vec<TriMesh> = ["cylinder", "bunny", "sphere", "plank", "block", "bunny-dense"]
        .iter()
        .map(|name| mesh::builtin(name).unwrap())
        .chain([triangle])
        .collect();
    let targets: Vec<NormalsTarget> = meshes.iter().map(all).collect();
    let gpu = gpu_normals(context, &targets);
    for (k, mesh) in meshes.iter().enumerate() {
        check(&format!("mesh {k}"), mesh.positions(), mesh.faces(), &gpu[k], mesh.normals());
    }
    assert_eq!(gpu[6], vec![Vec3::Z; 3]);
}

fn isolated_vertices_and_degenerate_faces_give_exact_zeros(context: &'static GpuContext) {
    let positions = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(5.0, 5.0, 5.0), // isolated
        Vec3::new(2.0, 0.0, 0.0), // only in the collinear face 1-4-5
        Vec3::new(3.0, 0.0, 0.0),
        Vec3::new(7.0, 7.0, 7.0), // only in a face with a repeated vertex
        Vec3::new(8.0, 7.0, 7.0),
    ];
    let faces = vec![[0, 1, 2], [1, 4, 5], [6, 6, 7], [2, 1, 0], [0, 2, 1]];
    let degenerate = TriMesh::new(positions, faces).unwrap();
    let cpu = degenerate.normals();
    // Vertices 0–2: faces +z, −z, −z sum to −z; the others get zero (exactly, on any GPU).
    assert_eq!(cpu[3..], [Vec3::ZERO; 5]);
    let gpu = gpu_normals(context, &[all(&degenerate)]);
    check("degenerate", degenerate.positions(), degenerate.faces(), &gpu[0], cpu);
    assert_eq!(gpu[0][3..], [Vec3::ZERO; 5]);
}

fn more_targets_than_one_dispatch_takes(context: &'static GpuContext) {
    let mut rng = SplitMix64::new(7);
    // Random tetrahedra and fans; a few vertices of each may end up unused.
    let meshes: Vec<TriMesh> = (0..MAX_TARGETS_PER_DISPATCH + 37)
        .map(|_| {
            let n = 4 + rng.below(12) as u32;
            let positions =
                (0..n).map(|_| Vec3::new(rng.range_f32(-1.0, 1.0), rng.range_f32(-1.0, 1.0), rng.next_f32())).collect();
            let faces = (0..2 * n).map(|_| [0, 1, 2].map(|_| rng.below(n as u64) as u32)).collect();
            TriMesh::new(positions, faces).unwrap()
        })
        .collect();
    let targets: Vec<NormalsTarget> = meshes.iter().map(all).collect();
    let gpu = gpu_normals(context, &targets);
    let worst = meshes
        .iter()
        .enumerate()
        .map(|(k, m)| check(&format!("random mesh {k}"), m.positions(), m.faces(), &gpu[k], m.normals()))
        .fold(0.0, f64::max);
    eprintln!("random meshes: worst {worst:.3} of tolerance");
}

fn moved_only_refreshes_the_vertices_that_share_a_face_with_a_moved_one(context: &'static GpuContext) {
    let bunny = mesh::builtin("bunny-dense").unwrap();
    let point = bunny.support_point(Vec3::X);
    let ball = common::sphere_at(point + Vec3::X, 1.0);
    let map = dent_map(&ball, &Impact::head_on(point, -Vec3::X), &DentParams::new(0.4), None).unwrap();
    let (params, table) = map.displace_params(&Attenuation::Logistic, bunny.vertex_count());
    let mut positions = bunny.positions().to_vec();
    let mut moved = vec![false; positions.len()];
    cpu::displace(&params, &map.cells, &table, &mut positions, &mut moved);
    let dented = TriMesh::new(positions, bunny.faces().to_vec()).unwrap();

    // `recompute_normals_near`'s set: every corner of a face with a moved corner.
    let mut affected = vec![false; moved.len()];
    for face in dented.faces().iter().filter(|f| f.iter().any(|&v| moved[v as usize])) {
        face.iter().for_each(|&v| affected[v as usize] = true);
    }
    let stale = vec![Vec3::splat(9.0); moved.len()];
    let target = NormalsTarget { positions: dented.positions(), faces: dented.faces(), near: Some((&moved, &stale)) };
    let gpu = gpu_normals(context, &[target]).remove(0);
    let expected: Vec<Vec3> =
        dented.normals().iter().zip(&affected).map(|(&n, &a)| if a { n } else { Vec3::splat(9.0) }).collect();
    let refreshed = affected.iter().filter(|&&a| a).count();
    assert!(refreshed > moved.iter().filter(|&&m| m).count() && refreshed < moved.len() / 2);
    check("moved only", dented.positions(), dented.faces(), &gpu, &expected);
    // Vertices away from the dent keep the stale normal bit for bit.
    assert!(gpu.iter().zip(&affected).all(|(n, &a)| a || *n == Vec3::splat(9.0)));
}

fn adjacency_lists_each_vertex_faces_in_ascending_order() {
    // Faces 0: (0 1 2), 1: (2 1 3), 2: (3 3 0); vertex 4 is isolated.
    let block = adjacency(5, &[[0, 1, 2], [2, 1, 3], [3, 3, 0]]);
    #[rustfmt::skip]
    let expected = vec![
        6, 8, 10, 12, 15, 15, // offsets, from the start of the block
        0, 2,                 // vertex 0
        0, 1,                 // vertex 1
        0, 1,                 // vertex 2
        1, 2, 2,              // vertex 3: once per corner
    ];
    assert_eq!(block, expected);
    // No vertex: the block is its end offset alone.
    assert_eq!(adjacency(0, &[]), vec![1]);
}

gpu_test_main! {
    plain: [adjacency_lists_each_vertex_faces_in_ascending_order],
    gpu: [
        the_dense_bunny_matches_the_cpu_before_and_after_a_dent,
        a_batch_of_meshes_of_every_size_matches_the_cpu,
        isolated_vertices_and_degenerate_faces_give_exact_zeros,
        more_targets_than_one_dispatch_takes,
        moved_only_refreshes_the_vertices_that_share_a_face_with_a_moved_one,
    ],
}
