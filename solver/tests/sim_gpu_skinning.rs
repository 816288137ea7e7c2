//! GPU skinning in the simulation loop: a `Simulation` that skins its bending bodies with the
//! `skin` kernel (rest meshes resident, re-uploaded after a split or a dent) against the same
//! simulation skinning with the CPU twin. Both dent on the CPU, so their dynamics are identical
//! (checked bit for bit every step: the bone transforms and rest meshes agree exactly) and only
//! the skinning differs.
//!
//! Tolerance: as in `tests/parity_skin.rs`, whose bound this reuses. The kernel runs the twin's
//! f32 operations in the same order; a driver may fuse a multiply-add or reassociate a dot or
//! cross product. A position component may then move by a few ε (2⁻²³) of its terms' magnitude
//! `Σᵢ wᵢ (Σ_c |S_rc|·|p_c| + |t_r|)` (plus the rest-pose share of a weight sum short of one): we
//! allow 16 ε of it, computed per vertex in f64 from the body's influences and bone matrices.
//! The coordinates here are at most a few metres, so that is a few 1e-5 m at most, while the
//! mistakes this guards against (a rest mesh not re-uploaded after a dent of centimetres, bones
//! of the wrong body or step) move vertices by millimetres or more. A unit normal may move by a
//! few ε times κ, the cofactor terms' magnitude over `|cof(A)·n|`; we allow 32 ε·κ. On lavapipe
//! the worst error here came out at 0.08 of the tolerance (each comparison prints its worst).

mod common;

use common::skin_tolerance::{EPS, NORMAL_ULPS, blend_magnitude, cofactor_terms, position_tolerance};

use dentbend::bend::WeightParams;
use dentbend::cpu::{SkinBone, SkinInfluence};
use dentbend::glam::{DVec3, Vec3, Vec4};
use dentbend::gpu::skin::Skinned;
use dentbend::gpu::{GpuContext, buffers};
use dentbend::mesh;
use dentbend_solver::coupling::Simulation;
use dentbend_solver::coupling::{ArticulatedBody, BendableDesc, Bending, SkeletonSpec, Skinner};
use dentbend_solver::scene::{SceneSize, load_sized};
use dentbend_solver::sim::{BodyDesc, ColliderKind, DentSettings, SimError, World, WorldSettings};

/// κ of a vertex: the magnitude of the cofactor terms of `|M|` applied to `|n|` over the length
/// of the twin's unnormalized `cof(A)·n`, at least 1.
fn condition(m: &[[f64; 4]; 3], n: DVec3, bones: &[SkinBone], influence: &SkinInfluence) -> f64 {
    let terms = cofactor_terms(m, n);
    // The signed blend A (f64) for the length of cof(A)·n.
    let mut rows = [DVec3::ZERO; 3];
    let mut total = 0.0;
    for (&b, &w) in influence.bones.iter().zip(&influence.weights) {
        for (row, bone_row) in rows.iter_mut().zip(&bones[b as usize].rows) {
            *row += f64::from(w) * DVec3::new(bone_row[0].into(), bone_row[1].into(), bone_row[2].into());
        }
        total += f64::from(w);
    }
    rows[0].x += 1.0 - total;
    rows[1].y += 1.0 - total;
    rows[2].z += 1.0 - total;
    let cof = DVec3::new(rows[1].cross(rows[2]).dot(n), rows[2].cross(rows[0]).dot(n), rows[0].cross(rows[1]).dot(n));
    let length = cof.length().max(f64::MIN_POSITIVE);
    (terms.abs().element_sum() / length).max(1.0)
}

/// Asserts `gpu` ≈ `cpu` for `body` skinned in `world` with the module's tolerances; returns the
/// worst error in units of its tolerance.
fn agree(what: &str, body: &ArticulatedBody, world: &World, gpu: &Skinned, cpu: &Skinned) -> f64 {
    let bones: Vec<SkinBone> = body.bone_transforms(world).unwrap().into_iter().map(SkinBone::from_affine).collect();
    let rest = body.rest_mesh();
    let n = rest.vertex_count();
    assert_eq!((gpu.positions.len(), gpu.normals.len()), (n, n), "{what}: GPU output length");
    assert_eq!((cpu.positions.len(), cpu.normals.len()), (n, n), "{what}: CPU output length");
    let mut worst = 0.0f64;
    for (v, influence) in body.influences().iter().enumerate() {
        let m = blend_magnitude(&bones, influence);
        let p = rest.positions()[v].as_dvec3().abs();
        for r in 0..3 {
            let tolerance = position_tolerance(&m, p, r);
            let error = f64::from((gpu.positions[v][r] - cpu.positions[v][r]).abs());
            assert!(
                error <= tolerance,
                "{what}: vertex {v} position: GPU {} vs CPU {} (tolerance {tolerance:.2e} m)",
                gpu.positions[v],
                cpu.positions[v]
            );
            worst = worst.max(error / tolerance);
        }
        let normal = rest.normals()[v].as_dvec3();
        let tolerance = NORMAL_ULPS * EPS * condition(&m, normal.abs(), &bones, influence);
        let error = f64::from((gpu.normals[v] - cpu.normals[v]).abs().max_element());
        assert!(error <= tolerance, "{what}: vertex {v} normal: GPU {} vs CPU {}", gpu.normals[v], cpu.normals[v]);
        worst = worst.max(error / tolerance);
    }
    worst
}

/// One step of both simulations; asserts that their dynamics agree exactly (bone transforms,
/// rest meshes, skeletons) and that their skinned bodies agree within the tolerances. Returns
/// the worst error in units of the tolerance.
fn step_both(frame: usize, gpu: &mut Simulation, cpu: &mut Simulation) -> f64 {
    gpu.step().unwrap_or_else(|e| panic!("GPU-skinned simulation, frame {frame}: {e}"));
    cpu.step().unwrap_or_else(|e| panic!("CPU-skinned simulation, frame {frame}: {e}"));
    let gpu_out = gpu.skinned().unwrap().to_vec();
    let cpu_out = cpu.skinned().unwrap().to_vec();
    let (bending, world) = (cpu.bending(), cpu.world());
    assert_eq!(gpu_out.len(), bending.bodies().len(), "frame {frame}: skinned bodies");
    let mut worst = 0.0f64;
    for (k, body) in bending.bodies().iter().enumerate() {
        let twin = &gpu.bending().bodies()[k];
        assert_eq!(twin.skeleton().len(), body.skeleton().len(), "frame {frame}: bones differ");
        assert!(twin.rest_mesh() == body.rest_mesh(), "frame {frame}: rest meshes differ (the premise)");
        let same = twin.bone_transforms(gpu.world()).unwrap() == body.bone_transforms(world).unwrap();
        assert!(same, "frame {frame}: bone transforms differ: the dynamics are not identical (the premise)");
        let what = format!("frame {frame}, body {}", body.name());
        worst = worst.max(agree(&what, body, world, &gpu_out[k], &cpu_out[k]));
    }
    worst
}

/// The key a GPU skinner uploads on: rest revision and bone count of each bending body.
fn keys(sim: &Simulation) -> Vec<(u64, usize)> {
    sim.bending().bodies().iter().map(|b| (b.rest_revision(), b.skeleton().len())).collect()
}

/// Groups uploaded by `sim`'s GPU skinner so far.
fn uploads(sim: &Simulation) -> usize {
    sim.skinner().gpu().map_or(0, |g| g.uploads())
}

/// Steps `frames` frames of `gpu` (skinned on the GPU) and `cpu` (on the CPU twin), comparing
/// them every step, and checks that the GPU skinner, holding every body in one group, uploads it
/// at the first step's skin and then again exactly at the steps where a body's rest revision or
/// bone count changed. Returns the number of uploads after the first.
fn run_both(name: &str, frames: usize, mut gpu: Simulation, mut cpu: Simulation) -> (Simulation, usize) {
    assert_eq!(uploads(&gpu), 0, "{name}: uploaded before the first step");
    let mut before: Option<Vec<(u64, usize)>> = None;
    let mut reuploads = 0;
    let mut worst = 0.0f64;
    for frame in 1..=frames {
        worst = worst.max(step_both(frame, &mut gpu, &mut cpu));
        assert_eq!(gpu.skinner().gpu().map(|g| g.groups()), Some(1), "{name}, frame {frame}: groups");
        let after = keys(&gpu);
        let changed = before.as_ref().is_some_and(|b| *b != after);
        reuploads += usize::from(changed);
        assert_eq!(uploads(&gpu), 1 + reuploads, "{name}, frame {frame}: uploads (a body changed: {changed})");
        before = Some(after);
    }
    println!("{name}: {frames} frames, {reuploads} re-uploads, worst error {worst:.3} of the tolerance");
    (cpu, reuploads)
}

/// Figure 14's plank (demo size): the ball splits the plank's bone and dents it. Skinned every
/// step on the GPU and on the CPU twin, the two agree at every frame, before and after the split
/// and the dent, and the GPU skinner uploads the plank again when they change it.
fn the_plank_skins_alike_on_the_gpu_and_the_cpu_through_its_split_and_dent(context: &'static GpuContext) {
    let scene = load_sized("plank", SceneSize::Demo).unwrap();
    let gpu = Simulation::new(scene.world.clone(), None).unwrap().with_bending(scene.bending.clone());
    let gpu = gpu.skin_on(Some(context)).skin_every_step(true);
    let cpu = Simulation::new(scene.world, None).unwrap().with_bending(scene.bending).skin_every_step(true);
    assert!(gpu.skins_on_gpu() && !cpu.skins_on_gpu());
    // The ball lands at frame 6; 12 frames cover the split, the dent and the bend's start.
    let (cpu, reuploads) = run_both("plank", 12, gpu, cpu);
    let plank = cpu.bending().find("plank").unwrap();
    assert_eq!(plank.skeleton().len(), 2, "the plank's bone was not split");
    assert!(cpu.dents().iter().any(|d| d.target == "plank"), "the plank was not dented: {:?}", cpu.dents());
    // One upload per step that split or dented the plank (a split and a dent in one step: one).
    let mut changes: Vec<u64> = cpu.bending().joints().iter().map(|j| j.frame).collect();
    changes.extend(cpu.dents().iter().filter(|d| d.target == "plank").map(|d| d.step));
    changes.sort_unstable();
    changes.dedup();
    assert_eq!(reuploads, changes.len(), "uploads again for changes at frames {changes:?}");
}

/// Ball radius (m) and speed (m/s) of the dent-only scene.
const RADIUS: f32 = 0.15;
const SPEED: f32 = 5.0;

/// Three 2 × 0.4 × 0.4 m two-bone bars side by side (z = -1, 0, 1 m) without dynamic
/// articulation, dentable (threshold 1 m/s, 1 cm per m/s above it: about 4 cm at 5 m/s), and a
/// ball flying down onto the middle one, `bar1`, off its middle, without gravity: a dent changes
/// that bar's rest mesh, never the bones; its neighbours on the GPU share its group.
fn dent_only_scene() -> (World, Bending) {
    let settings = WorldSettings { gravity: Vec3::ZERO, sleep_time: 0.0, ..Default::default() };
    let mut world = World::new(settings).unwrap();
    let mut bending = Bending::new();
    for (k, z) in [-1.0, 0.0, 1.0].into_iter().enumerate() {
        let mut desc = BendableDesc::new(format!("bar{k}"), mesh::plank(2.0, 0.4, 0.4, 40).unwrap());
        desc.position = Vec3::new(0.0, 0.0, z);
        desc.skeleton = SkeletonSpec::Auto { bones: 2 };
        desc.weights = WeightParams { resolution: 32, ..WeightParams::default() };
        desc.dent = Some(DentSettings::new(1.0, 0.01, 0.06));
        bending.add(&mut world, desc).unwrap();
    }
    let ball = BodyDesc::new("ball", mesh::icosphere(RADIUS, 3).unwrap())
        .at(Vec3::new(0.3, 0.2 + RADIUS + 0.1, 0.0))
        .velocity(Vec3::new(0.0, -SPEED, 0.0))
        .collider(ColliderKind::Ball);
    world.add(ball).unwrap();
    (world, bending)
}

/// A dent alone (no split) changes a bending body's rest mesh: the GPU skinner uploads its group
/// again and the three bars still agree with the CPU twin; without the new upload the GPU would
/// skin the undented rest mesh, centimetres off where the dent is.
fn a_dent_alone_uploads_the_rest_mesh_again_and_the_skins_agree(context: &'static GpuContext) {
    let (world, bending) = dent_only_scene();
    let rest_before = bending.bodies()[1].rest_mesh().clone();
    let gpu = Simulation::new(world.clone(), None).unwrap().with_bending(bending.clone());
    let gpu = gpu.skin_on(Some(context)).skin_every_step(true);
    let cpu = Simulation::new(world, None).unwrap().with_bending(bending).skin_every_step(true);
    let (cpu, reuploads) = run_both("dent only", 6, gpu, cpu);
    let bar = cpu.bending().find("bar1").unwrap();
    assert!(cpu.bending().bodies().iter().all(|b| b.skeleton().len() == 2), "bones changed");
    assert!(cpu.dents().iter().all(|d| d.target == "bar1"), "not bar1 alone dented: {:?}", cpu.dents());
    let depth = bar.rest_mesh().positions().iter().zip(rest_before.positions()).map(|(a, b)| a.distance(*b));
    let depth = depth.fold(0.0f32, f32::max);
    // Far above the position tolerance (a few 1e-6 m at these coordinates): a stale rest mesh
    // on the GPU could not pass the comparison.
    assert!(depth > 0.01, "the dent moved the rest mesh by only {depth} m");
    let mut dent_frames: Vec<u64> = cpu.dents().iter().map(|d| d.step).collect();
    dent_frames.dedup();
    assert!(!dent_frames.is_empty(), "bar1 was not dented");
    assert!(dent_frames.iter().all(|&f| f > 1), "dented at the first step, before any upload: {dent_frames:?}");
    assert_eq!(reuploads, dent_frames.len(), "one upload per step that dented the bar: {dent_frames:?}");
}

/// Skinning every step is timed (finite, positive) and serialized with the step; off by default,
/// when it is 0, nothing is uploaded until asked, and asking skins on demand (once per step).
/// The GPU's meshes equal the CPU twin's within the tolerance, names and colours alike, and the
/// CPU path's meshes are `Bending::skinned_meshes` exactly.
fn skinning_is_timed_when_every_step_and_on_demand_otherwise(context: &'static GpuContext) {
    let (world, bending) = dent_only_scene();
    let mut every = Simulation::new(world.clone(), None).unwrap().with_bending(bending.clone()).skin_every_step(true);
    every = every.skin_on(Some(context));
    let mut lazy = Simulation::new(world, None).unwrap().with_bending(bending).skin_on(Some(context));
    for frame in 1..=3 {
        let (timing, _) = every.step().unwrap();
        assert!(timing.skinning_ms.is_finite() && timing.skinning_ms > 0.0, "frame {frame}: {timing:?}");
        let json = serde_json::to_value(timing).unwrap();
        assert_eq!(json["skinning_ms"].as_f64(), Some(timing.skinning_ms), "frame {frame}: {json}");
        let (timing, _) = lazy.step().unwrap();
        assert_eq!(timing.skinning_ms, 0.0, "frame {frame}: skinned without being asked");
    }
    assert!(every.skinner().gpu().is_some_and(|g| g.resident(2).is_some()), "no resident mesh");
    assert!(lazy.skinner().gpu().is_none(), "uploaded without being asked");

    let meshes = lazy.skinned_meshes().unwrap();
    assert_eq!(uploads(&lazy), 1);
    let again = lazy.skinned_meshes().unwrap();
    assert_eq!(meshes, again, "the same step skinned twice differently");
    assert_eq!(uploads(&lazy), 1, "asked twice in one step: uploaded again");

    let reference = every.bending().skinned_meshes(every.world()).unwrap();
    assert_eq!(meshes.len(), reference.len());
    let gpu = every.skinned().unwrap().to_vec();
    let mut cpu_sim = Simulation::new(every.world().clone(), None).unwrap().with_bending(every.bending().clone());
    let cpu_meshes = cpu_sim.skinned_meshes().unwrap();
    assert_eq!(cpu_meshes, reference, "the CPU path is not Bending::skinned_meshes");
    let cpu = cpu_sim.skinned().unwrap().to_vec();
    for (k, ((name, mesh, colour), (ref_name, ref_mesh, ref_colour))) in meshes.iter().zip(&reference).enumerate() {
        assert_eq!((name, colour, mesh.faces()), (ref_name, ref_colour, ref_mesh.faces()));
        let body = &every.bending().bodies()[k];
        agree("on demand", body, every.world(), &gpu[k], &cpu[k]);
        let from_mesh = Skinned { positions: mesh.positions().to_vec(), normals: gpu[k].normals.clone() };
        agree("mesh", body, every.world(), &from_mesh, &cpu[k]);
    }
}

/// A skinner handed a world without the bending bodies' sub-bodies, or asked for meshes of
/// other bodies than it skinned, returns an error on both backends instead of panicking, and
/// keeps no results from before a failed skin.
fn a_skinner_refuses_a_foreign_world_and_stale_results(context: Option<&'static GpuContext>) {
    let (world, bending) = dent_only_scene();
    let backend = if context.is_some() { "GPU" } else { "CPU" };
    let mut skinner = Skinner::new(context);
    let empty = World::new(WorldSettings::default()).unwrap();
    skinner.skin(&bending, &world).unwrap();
    let error = skinner.skin(&bending, &empty).unwrap_err();
    assert!(matches!(error, SimError::Invalid { .. }), "{backend}: {error}");
    // No results left from before the failed skin.
    let error = skinner.meshes(&bending).unwrap_err();
    assert!(error.to_string().contains("skin again"), "{backend}: {error}");
    skinner.skin(&bending, &world).unwrap();
    assert_eq!(skinner.meshes(&bending).unwrap().len(), 3, "{backend}");
    let error = skinner.meshes(&Bending::new()).unwrap_err();
    assert!(error.to_string().contains("skin again"), "{backend}: {error}");
}

/// Figure 13's tetrahedra (demo size, 96 one-bone struts) on the GPU in groups of at most 1,000
/// vertices: several groups, each of several struts; every strut's skin, read back or read from
/// its range of its group's resident buffer, agrees with the CPU twin's.
fn many_bodies_in_several_groups_skin_as_on_the_cpu(context: &'static GpuContext) {
    let scene = load_sized("tetrahedra", SceneSize::Demo).unwrap();
    let mut sim = Simulation::new(scene.world, None).unwrap().with_bending(scene.bending);
    for _ in 0..3 {
        sim.step().unwrap();
    }
    let (bending, world) = (sim.bending(), sim.world());
    let count = bending.bodies().len();
    let mut gpu = Skinner::new(Some(context)).with_group_vertices(1000);
    gpu.skin(bending, world).unwrap();
    let mut cpu = Skinner::new(None);
    cpu.skin(bending, world).unwrap();
    let groups = gpu.gpu().unwrap().groups();
    println!("{count} bodies in {groups} groups");
    assert!(groups > 1 && groups < count, "{count} bodies in {groups} groups");
    let skinned = gpu.skinned().unwrap().to_vec();
    let reference = cpu.skinned().unwrap();
    assert_eq!(skinned.len(), count);
    for (k, body) in bending.bodies().iter().enumerate() {
        let what = format!("body {k} ({})", body.name());
        agree(&what, body, world, &skinned[k], &reference[k]);
        let (mesh, range) = gpu.gpu().unwrap().resident(k).unwrap();
        assert_eq!(range.len(), body.rest_mesh().vertex_count(), "{what}: range");
        let resident: Vec<Vec4> =
            buffers::read_back_range(context, mesh.positions(), range.start, range.len()).unwrap();
        let resident: Vec<Vec3> = resident.iter().map(|v| v.truncate()).collect();
        assert_eq!(resident, skinned[k].positions, "{what}: resident buffer and read-back differ");
    }
}

gpu_test_main! {
    gpu: [
        the_plank_skins_alike_on_the_gpu_and_the_cpu_through_its_split_and_dent,
        a_dent_alone_uploads_the_rest_mesh_again_and_the_skins_agree,
        skinning_is_timed_when_every_step_and_on_demand_otherwise,
        many_bodies_in_several_groups_skin_as_on_the_cpu,
    ],
    both: [a_skinner_refuses_a_foreign_world_and_stale_results],
}
