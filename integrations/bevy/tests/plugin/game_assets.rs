//! Bevy's own meshes as game assets: a UV sphere (a seam column computed at 2π, a row of
//! vertices at each pole) and a `Cuboid` (24 vertices split at its hard edges) dent with the game
//! settings (refinement, volume rim, guard) on the CPU path, and the `Cuboid` on the GPU path
//! alike. Registration keeps their shading:
//! the authored normals stay bit for bit until a dent moves the surface around them, and after
//! one only the normals near it change. Reports tell the depth the dent really made.

use crate::common;
use libtest_mimic::Trial;

use bevy::prelude::*;
use bevy_dentbend::dentbend::dent::{DentSettings, VolumeMode};
use bevy_dentbend::{DentAdvice, DentApplied, DentPath, DentStats, DentWorld, Dentable};
use common::SPEED_OK;

/// Every `DentApplied` written so far.
#[derive(Resource, Default)]
struct Seen(Vec<DentApplied>);

fn collect(mut seen: ResMut<Seen>, mut applied: MessageReader<DentApplied>) {
    seen.0.extend(applied.read().copied());
}

/// The game dent: the scene's material (1 m/s threshold, 1 cm per m/s, at most 8 cm) with the
/// volume rim and the default refinement and guard.
fn game_dentable() -> Dentable {
    let mut settings = DentSettings::new(1.0, 0.01, 0.08);
    settings.params.volume = VolumeMode::Preserve;
    Dentable::with_settings(settings)
}

/// The asset's normals.
fn normals_of(mesh: &Mesh) -> Vec<Vec3> {
    match mesh.attribute(Mesh::ATTRIBUTE_NORMAL) {
        Some(bevy::mesh::VertexAttributeValues::Float32x3(n)) => n.iter().map(|n| Vec3::from_array(*n)).collect(),
        _ => panic!("the asset has no Float32x3 normals"),
    }
}

/// The scripted scene with `asset` (its top at the plate's top, y = 0 in the world) as the
/// dentable body on the CPU path; registered.
fn scene_with_asset(asset: Mesh) -> common::Scene {
    scene_with_asset_on(asset, false)
}

/// [`scene_with_asset`] on the GPU path (`gpu`) or the CPU path.
fn scene_with_asset_on(asset: Mesh, gpu: bool) -> common::Scene {
    let mut s = common::scene_dentable(gpu, game_dentable());
    let handle = s.app.world_mut().resource_mut::<Assets<Mesh>>().add(asset);
    s.app.world_mut().entity_mut(s.target).insert((Mesh3d(handle), Name::new("asset under test")));
    s.app.init_resource::<Seen>().add_systems(Update, collect);
    s.warm_up(gpu);
    s
}

/// The body's registered asset (the plug-in's private copy).
fn registered_asset(s: &common::Scene) -> Mesh {
    let handle = &s.app.world().get::<Mesh3d>(s.target).expect("a mesh").0;
    s.app.world().resource::<Assets<Mesh>>().get(handle).expect("the asset").clone()
}

/// Hits `asset` at the top, head-on; checks the dent is made as reported and that the normals
/// of every vertex below `far_below` (mesh y) stay the asset's, bit for bit, before and after.
fn dents_and_keeps_far_normals(asset: Mesh, far_below: f32) -> DentStats {
    let original = normals_of(&asset);
    let positions: Vec<Vec3> = match asset.attribute(Mesh::ATTRIBUTE_POSITION) {
        Some(bevy::mesh::VertexAttributeValues::Float32x3(p)) => p.iter().map(|p| Vec3::from_array(*p)).collect(),
        _ => panic!("no positions"),
    };
    let mut s = scene_with_asset(asset);
    assert_eq!(s.app.world().resource::<DentWorld>().path(s.target), Some(DentPath::Cpu));
    let registered = normals_of(&registered_asset(&s));
    let changed = (0..original.len()).find(|&v| registered[v] != original[v]);
    assert_eq!(changed, None, "registration changed the shading of a vertex");

    s.hit(0.0, 0.0, SPEED_OK);
    s.until("the dent", 60, |w| w.resource::<DentStats>().dents == 1);
    s.frames(2);
    let seen = &s.app.world().resource::<Seen>().0;
    assert_eq!(seen.len(), 1, "{seen:?}");
    let applied = seen[0];
    // 1 cm per m/s above 1 m/s at 5 m/s: 4 cm decided.
    assert!((applied.dent_distance - 0.04).abs() < 1e-4, "{applied:?}");
    let depth = applied.depth_made.expect("a CPU-path dent reports its depth");
    // The guard may limit it, but the dent must be made (a half at least: nothing crosses here).
    assert!(depth >= 0.5 * applied.dent_distance && depth <= 1.01 * applied.dent_distance, "{applied:?}");
    let after = normals_of(&registered_asset(&s));
    let far: Vec<usize> = (0..positions.len()).filter(|&v| positions[v].y < far_below).collect();
    assert!(!far.is_empty());
    for v in far {
        assert_eq!(after[v], original[v], "vertex {v} far below the dent changed its normal");
    }
    let stats = s.stats();
    assert_eq!((stats.cpu_dents, stats.empty_dents), (1, 0), "{stats:?}");
    stats
}

/// A 1 m UV sphere whose top is at y = 0.1 (the plate's top face in its own coordinates).
fn uv_sphere() -> Mesh {
    Sphere::new(0.5).mesh().uv(32, 18).translated_by(Vec3::new(0.0, -0.4, 0.0))
}

fn a_bevy_uv_sphere_dents_and_keeps_its_shading() {
    dents_and_keeps_far_normals(uv_sphere(), -0.3);
}

fn a_bevy_cuboid_is_refined_under_the_dent_and_keeps_its_hard_edges() {
    // 1 × 0.2 × 1 m: one quad per side; its top at y = 0.1.
    let stats = dents_and_keeps_far_normals(Cuboid::new(1.0, 0.2, 1.0).mesh().build(), 0.0);
    assert!(stats.refined_triangles > 0, "{stats:?}");
}

/// The game dent on the GPU path, on Bevy's `Cuboid` (one quad a side, split at its hard edges):
/// refined and made on Bevy's device like on the CPU path (the same triangles, vertices within
/// the kernels' tolerance, the same depth reported), with no CPU-path dent; the refined mesh
/// grows through its asset (every vertex with a UV) and Bevy's vertex slab draws it.
fn the_game_dent_on_the_gpu_path_matches_the_cpu_path() {
    let cuboid = || Cuboid::new(1.0, 0.2, 1.0).mesh().build();
    let run = |gpu: bool| {
        let mut s = scene_with_asset_on(cuboid(), gpu);
        s.hit(0.1, -0.05, SPEED_OK);
        s.settle(1);
        s.frames(3);
        s
    };
    let (mut g, c) = (run(true), run(false));
    let (gpu, cpu) = (g.target_now(), c.target_now());
    assert_eq!(gpu.faces(), cpu.faces(), "the same refinement on both paths");
    assert!(gpu.vertex_count() > 24, "the cuboid was not refined");
    // Tolerance as gpu_path.rs: one dent of at most 4 cm, the map's 2e-5·d error plus a
    // few ulps of the coordinate, margin 3.
    let tol = 3.0 * (2e-5 * 0.04 + 8.0 * f32::EPSILON * 1.5);
    let worst = gpu.positions().iter().zip(cpu.positions()).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
    assert!(worst <= tol, "GPU and CPU vertices differ by {worst} (allowed {tol})");
    let (gs, cs) = (g.stats(), c.stats());
    assert_eq!((gs.gpu_dents, gs.cpu_dents, gs.empty_dents), (1, 0, 0), "{gs:?}");
    assert_eq!(gs.refined_triangles, cs.refined_triangles);
    let (ga, ca) = (g.app.world().resource::<Seen>().0.clone(), c.app.world().resource::<Seen>().0.clone());
    assert_eq!((ga.len(), ca.len()), (1, 1), "one DentApplied on each path");
    let (gd, cd) = (ga[0].depth_made.expect("the GPU path reports the depth"), ca[0].depth_made.unwrap());
    assert!((gd - cd).abs() <= tol, "depth made {gd} on the GPU path, {cd} on the CPU path");
    assert_eq!(ga[0].limited_to, ca[0].limited_to);
    let asset = registered_asset(&g);
    assert_eq!(g.target_asset_positions(), gpu.positions(), "the grown asset lacks the dent");
    let Some(bevy::mesh::VertexAttributeValues::Float32x2(uvs)) = asset.attribute(Mesh::ATTRIBUTE_UV_0) else {
        panic!("the grown asset lost its UVs")
    };
    assert_eq!(uvs.len(), gpu.vertex_count(), "a UV for every vertex");
    let layout = bevy_dentbend::slab_layout(&asset).expect("a layout");
    let handle = g.app.world().get::<Mesh3d>(g.target).expect("a mesh").0.clone();
    g.probe.request(handle.id(), layout.stride);
    g.frames(2);
    let bytes = g.probe.take().expect("the slab was read");
    assert_eq!(bytes.len() as u64, gpu.vertex_count() as u64 * layout.stride, "the slab slot did not grow");
    let at = |v: usize, k: usize| {
        let i = v * layout.stride as usize + layout.fields.position as usize + k * 4;
        f32::from_le_bytes(bytes[i..i + 4].try_into().unwrap())
    };
    for (v, p) in gpu.positions().iter().enumerate() {
        assert_eq!(Vec3::new(at(v, 0), at(v, 1), at(v, 2)), *p, "vertex {v}: position in the slab");
    }
}

/// A `Cuboid` with the paper's dent (kernels only, `Dentable::paper`) is named in one warning
/// with its fix; the same cuboid with the game settings, and the scene's finely meshed plate,
/// are not.
fn a_body_too_coarse_for_its_dents_is_named_with_the_fix() {
    let cuboid = || Cuboid::new(1.0, 0.2, 1.0).mesh().build();
    let mut s = common::scene_dentable(false, Dentable::paper(1.0, 0.01, 0.08));
    s.app.init_resource::<Seen>();
    s.warm_up(false);
    assert!(s.app.world().get::<DentAdvice>(s.target).is_none(), "the 48-cell plate is fine enough");
    let mut spawn = |dentable: Dentable, name: &str| {
        let handle = s.app.world_mut().resource_mut::<Assets<Mesh>>().add(cuboid());
        let entity =
            s.app.world_mut().spawn((Mesh3d(handle), Transform::default(), dentable, Name::new(name.to_owned()))).id();
        s.frames(3);
        entity
    };
    let coarse = spawn(Dentable::paper(1.0, 0.01, 0.08), "paper crate");
    let game = spawn(game_dentable(), "game crate");
    let advice = s.app.world().get::<DentAdvice>(coarse).expect("the coarse body is named").0.clone();
    assert!(advice.contains("paper crate") && advice.contains("too coarse"), "{advice}");
    assert!(advice.contains("Dentable::new"), "the advice names no fix: {advice}");
    assert!(s.app.world().get::<DentAdvice>(game).is_none(), "refinement serves the game crate");
}

pub fn tests() -> Vec<Trial> {
    common::gpu_trials(
        module_path!(),
        vec![
            ("a_bevy_uv_sphere_dents_and_keeps_its_shading", a_bevy_uv_sphere_dents_and_keeps_its_shading),
            (
                "a_bevy_cuboid_is_refined_under_the_dent_and_keeps_its_hard_edges",
                a_bevy_cuboid_is_refined_under_the_dent_and_keeps_its_hard_edges,
            ),
            ("the_game_dent_on_the_gpu_path_matches_the_cpu_path", the_game_dent_on_the_gpu_path_matches_the_cpu_path),
            (
                "a_body_too_coarse_for_its_dents_is_named_with_the_fix",
                a_body_too_coarse_for_its_dents_is_named_with_the_fix,
            ),
        ],
    )
}
