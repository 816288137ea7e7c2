//! The `skin` kernel (shaders/skin.wgsl) against its CPU twin `cpu::skin`: seeded random bones
//! and influences on the bunny over four frames of one resident mesh, the `encode` output buffers
//! read without `run`, and the GPU path's input errors; then CPU-only properties of the twin
//! (identity bones, rigid single bones, unit normals, the inverse-transpose under non-uniform
//! scale, bad input rejected with the outputs untouched) and of `skin_bones`.
//!
//! Tolerance. The kernel runs the twin's f32 operations in the same order, so they differ only
//! where the driver fuses a multiply-add or reassociates a dot or cross product (WGSL allows
//! both), and where `1/sqrt` rounds differently. Each blended matrix entry then moves by a few
//! ε (ε = 2⁻²³) of its terms' magnitude Σ wᵢ|Sᵢ|, and each position component by a few ε of
//! `Σ_c |M_rc|·|p_c|` over the blend's terms: we allow `POSITION_ULPS = 16` ε of that sum,
//! computed in f64 from the terms' absolute values. A normal is `cof(A)·n` normalized; the
//! cofactors are differences of products of blended entries, so each component of `cof(A)·n`
//! moves by a few ε of `Σ |products|·|n_c|`, and the unit normal by that over `|cof(A)·n|`; we
//! allow `NORMAL_ULPS = 32` ε times that ratio κ (at least 1). Each parity test prints how many
//! vertices are bit-identical and the worst errors. On lavapipe the normals come out
//! bit-identical and the positions within 1.4 ε of their terms (the four-term dot products add
//! in another order), about a tenth of the tolerance.

mod common;

use common::SplitMix64;
use common::skin_tolerance::{EPS, NORMAL_ULPS, POSITION_ULPS, blend_magnitude, cofactor_terms, position_tolerance};
use dentbend::cpu::{self, SkinBone, SkinError, SkinInfluence, SkinParams, WEIGHT_SUM_TOLERANCE, skin_bones};
use dentbend::glam::{Affine3A, DVec3, Quat, Vec3};
use dentbend::gpu::skin::{MAX_BONES, Skin, SkinMesh, Skinned};
use dentbend::gpu::{GpuContext, GpuError, buffers};
use dentbend::mesh;

/// A random pose: rotation about a random axis, translation within ±`reach`, and a non-uniform
/// scale in [1/`stretch`, `stretch`] per axis (1: rigid).
fn random_pose(rng: &mut SplitMix64, reach: f32, stretch: f32) -> Affine3A {
    let axis = Vec3::new(rng.range_f32(-1.0, 1.0), rng.range_f32(-1.0, 1.0), rng.range_f32(-1.0, 1.0));
    let axis = axis.try_normalize().unwrap_or(Vec3::Y);
    let rotation = Quat::from_axis_angle(axis, rng.range_f32(-3.0, 3.0));
    let scale = Vec3::new(
        rng.range_f32(1.0 / stretch, stretch),
        rng.range_f32(1.0 / stretch, stretch),
        rng.range_f32(1.0 / stretch, stretch),
    );
    let translation =
        Vec3::new(rng.range_f32(-reach, reach), rng.range_f32(-reach, reach), rng.range_f32(-reach, reach));
    Affine3A::from_scale_rotation_translation(scale, rotation, translation)
}

/// `count` bones from random rest poses (rigid) to random current poses (scaled up to `stretch`).
fn random_bones(rng: &mut SplitMix64, count: usize, stretch: f32) -> Vec<SkinBone> {
    let rest: Vec<Affine3A> = (0..count).map(|_| random_pose(rng, 5.0, 1.0)).collect();
    let current: Vec<Affine3A> = (0..count).map(|_| random_pose(rng, 5.0, stretch)).collect();
    skin_bones(&rest, &current).unwrap()
}

/// One to four distinct bones per vertex with random weights normalized to one; unused slots
/// hold bone 0 with weight 0.
fn random_influences(rng: &mut SplitMix64, vertices: usize, bones: u32) -> Vec<SkinInfluence> {
    (0..vertices)
        .map(|_| {
            let used = 1 + rng.below(4.min(bones as u64)) as usize;
            let mut influence = SkinInfluence::default();
            for slot in 0..used {
                let mut bone = rng.below(bones as u64) as u32;
                while influence.bones[..slot].contains(&bone) {
                    bone = (bone + 1) % bones;
                }
                influence.bones[slot] = bone;
                influence.weights[slot] = rng.range_f32(0.05, 1.0);
            }
            let sum: f32 = influence.weights.iter().sum();
            influence.weights = influence.weights.map(|w| w / sum);
            influence
        })
        .collect()
}

/// The CPU twin, with fresh outputs.
fn cpu_skin(bones: &[SkinBone], positions: &[Vec3], normals: &[Vec3], influences: &[SkinInfluence]) -> Skinned {
    let params = SkinParams::new(positions.len() as u32, bones.len() as u32);
    let mut out = Skinned { positions: vec![Vec3::ZERO; positions.len()], normals: vec![Vec3::ZERO; positions.len()] };
    cpu::skin(&params, bones, positions, normals, influences, &mut out.positions, &mut out.normals).unwrap();
    out
}

/// Asserts GPU ≈ CPU per component with the module's tolerances; returns the worst error in
/// units of the tolerance.
fn check(what: &str, bones: &[SkinBone], rest: (&[Vec3], &[Vec3]), influences: &[SkinInfluence], gpu: &Skinned) -> f64 {
    let cpu = cpu_skin(bones, rest.0, rest.1, influences);
    assert_eq!(gpu.positions.len(), cpu.positions.len(), "{what}: vertex count");
    assert_eq!(gpu.normals.len(), cpu.normals.len(), "{what}: normal count");
    let (mut worst_position, mut worst_normal, mut exact) = (0.0f64, 0.0f64, 0);
    for (k, influence) in influences.iter().enumerate() {
        let m = blend_magnitude(bones, influence);
        let (p, n) = (rest.0[k].as_dvec3().abs(), rest.1[k].as_dvec3().abs());
        for r in 0..3 {
            let tol = position_tolerance(&m, p, r);
            let error = (gpu.positions[k][r] as f64 - cpu.positions[k][r] as f64).abs();
            assert!(
                error <= tol,
                "{what}: vertex {k} position {r}: GPU {} vs CPU {}",
                gpu.positions[k],
                cpu.positions[k]
            );
            worst_position = worst_position.max(error / tol);
        }
        // κ: the cofactor terms' magnitudes over the length of cof(A)·n (CPU's, unnormalized).
        let terms = cofactor_terms(&m, n);
        let length = blended_normal(bones, influence, rest.1[k]).length();
        let kappa = (terms.max_element() / length).max(1.0);
        let tol = NORMAL_ULPS * EPS * kappa;
        let error = (gpu.normals[k] - cpu.normals[k]).abs().max_element() as f64;
        assert!(
            error <= tol,
            "{what}: vertex {k}: normal GPU {} vs CPU {} (κ {kappa})",
            gpu.normals[k],
            cpu.normals[k]
        );
        worst_normal = worst_normal.max(error / tol);
        exact += usize::from(gpu.positions[k] == cpu.positions[k] && gpu.normals[k] == cpu.normals[k]);
    }
    eprintln!(
        "{what}: {exact} of {} vertices bit-identical; worst error {:.2} ε of the position terms, {:.2} ε·κ \
         of the normals ({:.3} and {:.3} of the tolerances)",
        influences.len(),
        worst_position * POSITION_ULPS,
        worst_normal * NORMAL_ULPS,
        worst_position,
        worst_normal
    );
    worst_position.max(worst_normal)
}

/// `cof(A)·n` in f64 for the blended linear part `A` of one vertex (unnormalized).
fn blended_normal(bones: &[SkinBone], influence: &SkinInfluence, n: Vec3) -> DVec3 {
    let mut rows = [DVec3::ZERO; 3];
    let mut total = 0.0;
    for (&b, &w) in influence.bones.iter().zip(&influence.weights) {
        for (row, bone_row) in rows.iter_mut().zip(&bones[b as usize].rows) {
            *row += w as f64 * Vec3::from_slice(&bone_row[..3]).as_dvec3();
        }
        total += w as f64;
    }
    for (r, row) in rows.iter_mut().enumerate() {
        row[r] += 1.0 - total;
    }
    let n = n.as_dvec3();
    DVec3::new(rows[1].cross(rows[2]).dot(n), rows[2].cross(rows[0]).dot(n), rows[0].cross(rows[1]).dot(n))
}

// ---------------------------------------------------------------------------------------------
// GPU vs CPU

fn the_bunny_skinned_on_the_gpu_matches_the_cpu_frame_after_frame(context: &'static GpuContext) {
    let bunny = mesh::builtin("bunny").unwrap();
    let (positions, normals) = (bunny.positions(), bunny.normals());
    let mut rng = SplitMix64::new(0x5c1e);
    let bone_count = 12;
    let influences = random_influences(&mut rng, positions.len(), bone_count);
    let skin = Skin::new(context).unwrap();
    let resident = skin.upload(context, positions, normals, &influences, bone_count).unwrap();
    assert_eq!((resident.vertex_count(), resident.bone_count()), (positions.len(), bone_count as usize));
    // Rigid frames, then stretched ones: only the bones change between frames.
    for (frame, stretch) in [1.0, 1.0, 1.6, 2.5].into_iter().enumerate() {
        let bones = random_bones(&mut rng, bone_count as usize, stretch);
        let gpu = skin.run(context, &resident, &bones).unwrap();
        let worst = check(&format!("frame {frame}"), &bones, (positions, normals), &influences, &gpu);
        assert!(worst <= 1.0);
    }
}

fn encode_leaves_the_skinned_mesh_in_gpu_buffers(context: &'static GpuContext) {
    let sphere = mesh::builtin("sphere").unwrap();
    let (positions, normals) = (sphere.positions(), sphere.normals());
    let mut rng = SplitMix64::new(7);
    let influences = random_influences(&mut rng, positions.len(), 4);
    let bones = random_bones(&mut rng, 4, 1.3);
    let skin = Skin::new(context).unwrap();
    let resident = skin.upload(context, positions, normals, &influences, 4).unwrap();
    let mut encoder = context.device.create_command_encoder(&Default::default());
    skin.encode(context, &mut encoder, &resident, &bones).unwrap();
    context.queue.submit([encoder.finish()]);
    let read = |buffer| -> Vec<Vec3> {
        let values: Vec<[f32; 4]> = buffers::read_back(context, buffer, positions.len()).unwrap();
        assert!(values.iter().all(|v| v[3] == 0.0), "w must be 0");
        values.iter().map(|v| Vec3::from_slice(&v[..3])).collect()
    };
    let gpu = Skinned { positions: read(resident.positions()), normals: read(resident.normals()) };
    assert!(check("encode", &bones, (positions, normals), &influences, &gpu) <= 1.0);
    for buffer in [resident.positions(), resident.normals()] {
        assert!(buffer.usage().contains(wgpu::BufferUsages::VERTEX), "the outputs bind as vertex buffers");
    }
}

fn the_gpu_path_rejects_bad_input(context: &'static GpuContext) {
    let skin = Skin::new(context).unwrap();
    let p = [Vec3::ZERO, Vec3::X];
    let n = [Vec3::Z; 2];
    let good = [SkinInfluence::rigid(0); 2];
    let upload = |positions: &[Vec3], normals: &[Vec3], influences: &[SkinInfluence], bones| {
        skin.upload(context, positions, normals, influences, bones).map(|_: SkinMesh| ())
    };
    assert!(matches!(upload(&p, &n[..1], &good, 1), Err(SkinError::Length { .. })));
    assert!(matches!(upload(&p, &n, &good[..1], 1), Err(SkinError::Length { .. })));
    assert!(matches!(upload(&[Vec3::NAN, Vec3::X], &n, &good, 1), Err(SkinError::NonFiniteRest { vertex: 0 })));
    let mut bad = good;
    bad[1].weights[0] = f32::NAN;
    assert!(matches!(upload(&p, &n, &bad, 1), Err(SkinError::NonFiniteWeight { vertex: 1, slot: 0 })));
    assert!(matches!(upload(&p, &n, &[SkinInfluence::rigid(1); 2], 1), Err(SkinError::BoneIndex { bone: 1, .. })));
    let too_many = MAX_BONES as u32 + 1;
    assert!(
        matches!(upload(&p, &n, &good, too_many), Err(SkinError::Gpu(e)) if matches!(e.downcast_ref(), Some(GpuError::OverLimit { .. })))
    );

    let resident = skin.upload(context, &p, &n, &good, 2).unwrap();
    let run = |bones: &[SkinBone]| skin.run(context, &resident, bones);
    assert!(matches!(run(&[SkinBone::IDENTITY]), Err(SkinError::Length { len: 1, expected: 2, .. })));
    let mut nan = [SkinBone::IDENTITY; 2];
    nan[1].rows[2][3] = f32::INFINITY;
    assert!(matches!(run(&nan), Err(SkinError::NonFiniteBone { bone: 1 })));
    // Still usable after the errors; an empty mesh skins to nothing.
    assert_eq!(run(&[SkinBone::IDENTITY; 2]).unwrap().positions, p);
    let empty = skin.upload(context, &[], &[], &[], 0).unwrap();
    assert_eq!(skin.run(context, &empty, &[]).unwrap(), Skinned::default());
}

// ---------------------------------------------------------------------------------------------
// CPU properties

fn identity_bones_give_back_the_rest_mesh_exactly() {
    let bunny = mesh::builtin("bunny").unwrap();
    let mut rng = SplitMix64::new(1);
    let influences = random_influences(&mut rng, bunny.vertex_count(), 6);
    let out = cpu_skin(&[SkinBone::IDENTITY; 6], bunny.positions(), bunny.normals(), &influences);
    assert_eq!(out.positions, bunny.positions(), "positions must come back bit for bit");
    // The normals are renormalized, exactly as `normalize_or_zero` does to the rest normals.
    let renormalized: Vec<Vec3> = bunny.normals().iter().map(|n| n.normalize_or_zero()).collect();
    assert_eq!(out.normals, renormalized);
}

fn a_single_bone_moves_its_vertices_rigidly() {
    let bunny = mesh::builtin("bunny").unwrap();
    let mut rng = SplitMix64::new(2);
    let rest: Vec<Affine3A> = (0..5).map(|_| random_pose(&mut rng, 5.0, 1.0)).collect();
    let current: Vec<Affine3A> = (0..5).map(|_| random_pose(&mut rng, 5.0, 1.0)).collect();
    let bones = skin_bones(&rest, &current).unwrap();
    // Each vertex on one bone with weight 1; the other slots name other bones with weight 0.
    let influences: Vec<SkinInfluence> = (0..bunny.vertex_count())
        .map(|_| SkinInfluence { bones: [rng.below(5) as u32, 1, 2, 3], weights: [1.0, 0.0, 0.0, 0.0] })
        .collect();
    let out = cpu_skin(&bones, bunny.positions(), bunny.normals(), &influences);
    for (k, influence) in influences.iter().enumerate() {
        let b = influence.bones[0] as usize;
        let transform = current[b] * rest[b].inverse();
        let p = transform.transform_point3(bunny.positions()[k]);
        let n = transform.transform_vector3(bunny.normals()[k]);
        let scale = p.abs().max_element().max(1.0);
        assert!((out.positions[k] - p).abs().max_element() <= 1e-5 * scale, "vertex {k}: {} vs {p}", out.positions[k]);
        assert!((out.normals[k] - n).abs().max_element() <= 1e-5, "vertex {k}: normal {} vs {n}", out.normals[k]);
    }
}

fn blended_normals_are_unit_length() {
    let bunny = mesh::builtin("bunny").unwrap();
    let mut rng = SplitMix64::new(3);
    let influences = random_influences(&mut rng, bunny.vertex_count(), 8);
    let bones = random_bones(&mut rng, 8, 2.0);
    let out = cpu_skin(&bones, bunny.positions(), bunny.normals(), &influences);
    for (k, n) in out.normals.iter().enumerate() {
        assert!((n.length() - 1.0).abs() <= 1e-6, "vertex {k}: |n| = {}", n.length());
    }
}

/// A flat grid of `side²` vertices through `origin` spanned by `u` and `v`, every normal u × v.
fn plane(origin: Vec3, u: Vec3, v: Vec3, side: usize) -> (Vec<Vec3>, Vec<Vec3>) {
    let positions: Vec<Vec3> =
        (0..side * side).map(|k| origin + (k % side) as f32 * u + (k / side) as f32 * v).collect();
    (positions, vec![u.cross(v).normalize(); side * side])
}

fn a_non_uniform_scale_carries_normals_by_the_inverse_transpose() {
    // Guards the normal transform: the skinned normal stays perpendicular to the skinned grid's
    // edges, which the plain linear part A·n (checked to fail here) does not.
    let side = 8;
    let (positions, normals) =
        plane(Vec3::new(0.5, -1.0, 2.0), Vec3::new(0.3, 0.1, 0.2), Vec3::new(-0.1, 0.4, 0.05), side);
    let stretch = Affine3A::from_scale_rotation_translation(
        Vec3::new(3.0, 0.4, 1.2),
        Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7),
        Vec3::new(1.0, 2.0, -1.0),
    );
    let other =
        Affine3A::from_scale_rotation_translation(Vec3::new(0.5, 2.0, 1.0), Quat::from_rotation_y(1.1), Vec3::Y);
    let bones = [SkinBone::from_affine(stretch), SkinBone::from_affine(other)];
    let cases = [
        ("one bone", SkinInfluence::rigid(0)),
        ("two bones blended", SkinInfluence { bones: [0, 1, 0, 0], weights: [0.3, 0.7, 0.0, 0.0] }),
    ];
    for (what, influence) in cases {
        let out = cpu_skin(&bones, &positions, &normals, &vec![influence; positions.len()]);
        let linear = 0.3 * stretch.matrix3 + 0.7 * other.matrix3;
        let linear = if influence.weights[0] == 1.0 { stretch.matrix3 } else { linear };
        let naive = (linear * dentbend::glam::Vec3A::from(normals[0])).normalize();
        let mut naive_worst: f32 = 0.0;
        for k in 0..positions.len() {
            for next in [k + 1, k + side] {
                if next >= positions.len() || (next == k + 1 && next % side == 0) {
                    continue;
                }
                let edge = (out.positions[next] - out.positions[k]).normalize();
                let cosine = out.normals[k].dot(edge);
                assert!(cosine.abs() <= 1e-5, "{what}: vertex {k}: normal · edge = {cosine}");
                naive_worst = naive_worst.max(Vec3::from(naive).dot(edge).abs());
            }
        }
        assert!(naive_worst > 0.1, "{what}: A·n should have failed this test ({naive_worst})");
    }
}

fn bad_input_is_rejected_and_leaves_the_outputs_untouched() {
    let bunny = mesh::builtin("bunny").unwrap();
    let (positions, normals) = (bunny.positions(), bunny.normals());
    let n = positions.len();
    let mut rng = SplitMix64::new(4);
    let good = random_influences(&mut rng, n, 4);
    let bones = random_bones(&mut rng, 4, 1.5);
    let params = SkinParams::new(n as u32, 4);
    let sentinel = Vec3::splat(-7.0);

    let attempt = |params: &SkinParams,
                   bones: &[SkinBone],
                   rest: (&[Vec3], &[Vec3]),
                   influences: &[SkinInfluence],
                   out_len: (usize, usize)|
     -> SkinError {
        let (mut p, mut q) = (vec![sentinel; out_len.0], vec![sentinel; out_len.1]);
        let error = cpu::skin(params, bones, rest.0, rest.1, influences, &mut p, &mut q).unwrap_err();
        assert!(p.iter().chain(&q).all(|&v| v == sentinel), "{error}: the outputs were written");
        error
    };
    let with = |vertex: usize, f: &dyn Fn(&mut SkinInfluence)| {
        let mut influences = good.clone();
        f(&mut influences[vertex]);
        attempt(&params, &bones, (positions, normals), &influences, (n, n))
    };

    let e = with(10, &|i| i.weights[2] = f32::NAN);
    assert!(matches!(e, SkinError::NonFiniteWeight { vertex: 10, slot: 2 }), "{e}");
    let e = with(11, &|i| i.weights[0] = f32::INFINITY);
    assert!(matches!(e, SkinError::NonFiniteWeight { vertex: 11, slot: 0 }), "{e}");
    let e = with(12, &|i| *i = SkinInfluence { bones: [0, 1, 0, 0], weights: [1.25, -0.25, 0.0, 0.0] });
    assert!(matches!(e, SkinError::NegativeWeight { vertex: 12, slot: 1, .. }), "{e}");
    let e = with(13, &|i| i.weights = [0.5, 0.4, 0.0, 0.0]);
    assert!(matches!(e, SkinError::WeightSum { vertex: 13, .. }), "{e}");
    let e = with(14, &|i| i.weights = [1.0 + 2.0 * WEIGHT_SUM_TOLERANCE, 0.0, 0.0, 0.0]);
    assert!(matches!(e, SkinError::WeightSum { vertex: 14, .. }), "{e}");
    let e = with(15, &|i| i.bones[3] = 4);
    assert!(matches!(e, SkinError::BoneIndex { vertex: 15, bone: 4, bone_count: 4 }), "{e}");
    let e = with(16, &|i| i.bones[1] = u32::MAX);
    assert!(matches!(e, SkinError::BoneIndex { vertex: 16, .. }), "{e}");
    // The first bad vertex is the one reported.
    let mut two_bad = good.clone();
    two_bad[n - 1].weights[0] = f32::NAN;
    two_bad[20].weights[0] = -1.0;
    let e = attempt(&params, &bones, (positions, normals), &two_bad, (n, n));
    assert!(matches!(e, SkinError::NegativeWeight { vertex: 20, .. }), "{e}");

    // Mismatched lengths, each input in turn.
    let rest = (positions, normals);
    for (what, e) in [
        ("rest positions", attempt(&params, &bones, (&positions[1..], normals), &good, (n, n))),
        ("rest normals", attempt(&params, &bones, (positions, &normals[..n - 1]), &good, (n, n))),
        ("influences", attempt(&params, &bones, rest, &good[1..], (n, n))),
        ("skinned positions", attempt(&params, &bones, rest, &good, (n + 1, n))),
        ("skinned normals", attempt(&params, &bones, rest, &good, (n, 0))),
        ("bone matrices", attempt(&params, &bones[..3], rest, &good, (n, n))),
        ("rest positions", attempt(&SkinParams::new(n as u32 + 1, 4), &bones, rest, &good, (n, n))),
    ] {
        assert!(matches!(e, SkinError::Length { what: w, .. } if w == what), "{what}: {e}");
    }
    let mut nan_bone = bones.clone();
    nan_bone[2].rows[1][1] = f32::NAN;
    let e = attempt(&params, &nan_bone, rest, &good, (n, n));
    assert!(matches!(e, SkinError::NonFiniteBone { bone: 2 }), "{e}");
    let mut nan_rest = normals.to_vec();
    nan_rest[5].y = f32::NEG_INFINITY;
    let e = attempt(&params, &bones, (positions, &nan_rest), &good, (n, n));
    assert!(matches!(e, SkinError::NonFiniteRest { vertex: 5 }), "{e}");

    // Just inside the weight-sum tolerance is accepted.
    let mut loose = good.clone();
    loose[3].weights = [1.0 + 0.5 * WEIGHT_SUM_TOLERANCE, 0.0, 0.0, 0.0];
    cpu_skin(&bones, positions, normals, &loose);
    // An empty mesh skins to nothing.
    assert_eq!(cpu_skin(&[], &[], &[], &[]), Skinned::default());
}

fn skin_bones_are_current_poses_times_inverse_rest_poses() {
    let mut rng = SplitMix64::new(5);
    let rest: Vec<Affine3A> = (0..6).map(|_| random_pose(&mut rng, 3.0, 1.5)).collect();
    let current: Vec<Affine3A> = (0..6).map(|_| random_pose(&mut rng, 3.0, 1.5)).collect();
    let bones = skin_bones(&rest, &current).unwrap();
    for (k, bone) in bones.iter().enumerate() {
        // The bone carries the rest pose onto the current one.
        let moved = bone.to_affine() * rest[k];
        let (a, b) = (moved.to_cols_array(), current[k].to_cols_array());
        assert!(a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= 1e-5), "bone {k}: {a:?} vs {b:?}");
        assert_eq!(SkinBone::from_affine(bone.to_affine()), *bone);
    }
    assert_eq!(skin_bones(&[], &[]).unwrap(), Vec::<SkinBone>::new());
    assert!(matches!(skin_bones(&rest, &current[1..]), Err(SkinError::Length { len: 5, expected: 6, .. })));
    let flat = Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0));
    assert!(matches!(skin_bones(&[rest[0], flat], &current[..2]), Err(SkinError::SingularRestPose { bone: 1 })));
    let mut nan = current[..2].to_vec();
    nan[0].translation.x = f32::NAN;
    assert!(matches!(skin_bones(&rest[..2], &nan), Err(SkinError::NonFiniteBone { bone: 0 })));
}

gpu_test_main! {
    plain: [
        identity_bones_give_back_the_rest_mesh_exactly,
        a_single_bone_moves_its_vertices_rigidly,
        blended_normals_are_unit_length,
        a_non_uniform_scale_carries_normals_by_the_inverse_transpose,
        bad_input_is_rejected_and_leaves_the_outputs_untouched,
        skin_bones_are_current_poses_times_inverse_rest_poses,
    ],
    gpu: [
        the_bunny_skinned_on_the_gpu_matches_the_cpu_frame_after_frame,
        encode_leaves_the_skinned_mesh_in_gpu_buffers,
        the_gpu_path_rejects_bad_input,
    ],
}
