//! Hostile input never panics a Bevy system: meshes without positions or normals, of another
//! topology, held only by the render world, not loaded yet, mirrored bodies, invalid settings,
//! contacts with NaN, bodies despawned mid-batch, a device without the kernels' limits, a body
//! refined past the device's buffers, an app without a renderer. Each gets a clear outcome (refusal with a reason, the CPU path, or no
//! dent) and the app goes on denting what it can.

use crate::common;
use libtest_mimic::Trial;

use bevy::asset::RenderAssetUsages;
use bevy::mesh::PrimitiveTopology;
use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy::render::settings::{RenderCreation, WgpuLimits, WgpuSettings};
use bevy_dentbend::dentbend::dent::{DentSettings, Refine};
use bevy_dentbend::{DentPath, DentRefused, DentRegistered, DentStats, DentWorld, Dentable, DentbendPlugin, GpuStatus};
use common::{SPEED_OK, scene};

/// Spawns `mesh` as a dentable with `dentable` in the scripted scene's app; runs a few frames;
/// the entity.
fn spawn(s: &mut common::Scene, mesh: Mesh, dentable: Dentable, transform: Transform) -> Entity {
    let handle = s.app.world_mut().resource_mut::<Assets<Mesh>>().add(mesh);
    let entity = s.app.world_mut().spawn((Mesh3d(handle), transform, dentable)).id();
    s.frames(3);
    entity
}

fn refusal(s: &common::Scene, entity: Entity) -> Option<String> {
    s.app.world().get::<DentRefused>(entity).map(|r| r.0.clone())
}

/// The scene still dents after whatever a test did to it.
fn still_dents(s: &mut common::Scene) {
    let before = s.stats().dents;
    s.hit(0.1, -0.2, SPEED_OK);
    s.until("a later dent", 60, |w| w.resource::<DentStats>().dents > before);
}

fn meshes_that_cannot_dent_are_refused_with_a_reason() {
    let mut s = scene(true, false);
    s.warm_up(true);
    let ok = Dentable::new(1.0, 0.01, 0.08);
    let tri = common::plate_mesh();

    let mut no_positions = common::with_uvs(&tri);
    no_positions.remove_attribute(Mesh::ATTRIBUTE_POSITION);
    let e = spawn(&mut s, no_positions, ok.clone(), Transform::default());
    let why = refusal(&s, e).expect("refused");
    assert!(why.contains("no Float32x3 positions"), "{why}");

    let points = Mesh::new(PrimitiveTopology::PointList, RenderAssetUsages::default())
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, vec![[0.0f32; 3]; 3]);
    let e = spawn(&mut s, points, ok.clone(), Transform::default());
    assert!(refusal(&s, e).expect("refused").contains("PointList"));

    let mut render_only = common::with_uvs(&tri);
    render_only.asset_usage = RenderAssetUsages::RENDER_WORLD;
    let handle = s.app.world_mut().resource_mut::<Assets<Mesh>>().add(render_only);
    s.frames(3); // extracted: the main world's copy is emptied
    let e = s.app.world_mut().spawn((Mesh3d(handle), Transform::default(), ok.clone())).id();
    s.frames(3);
    assert!(refusal(&s, e).expect("refused").contains("render world"));

    // A scaled body dents (scaled.rs); a mirrored one cannot (its faces would turn inside out).
    let e = spawn(&mut s, common::with_uvs(&tri), ok.clone(), Transform::from_scale(Vec3::new(-1.0, 1.0, 1.0)));
    assert!(refusal(&s, e).expect("refused").contains("mirrors"));

    let bad = Dentable::with_settings(DentSettings::new(-1.0, 0.01, 0.08));
    let e = spawn(&mut s, common::with_uvs(&tri), bad, Transform::default());
    assert!(refusal(&s, e).expect("refused").contains("settings"));

    // A handle to a mesh that is not loaded: waits, unregistered and unrefused.
    let missing: Handle<Mesh> = Handle::from(bevy::asset::uuid::Uuid::from_u128(0x5eed_dead_beef));
    let e = s.app.world_mut().spawn((Mesh3d(missing), Transform::default(), ok)).id();
    s.frames(3);
    assert!(s.app.world().get::<DentRegistered>(e).is_none() && refusal(&s, e).is_none());
    still_dents(&mut s);
}

/// A mesh without normals gets smooth ones and dents.
fn a_mesh_without_normals_gets_normals() {
    let mut s = scene(true, false);
    s.warm_up(true);
    let mut mesh = common::with_uvs(&common::plate_mesh());
    mesh.remove_attribute(Mesh::ATTRIBUTE_NORMAL);
    let e = spawn(&mut s, mesh, Dentable::new(1.0, 0.01, 0.08), Transform::from_xyz(0.0, -3.0, 0.0));
    assert!(s.app.world().get::<DentRegistered>(e).is_some(), "{:?}", refusal(&s, e));
    let handle = s.app.world().get::<Mesh3d>(e).unwrap().0.clone();
    assert!(s.app.world().resource::<Assets<Mesh>>().get(&handle).unwrap().attribute(Mesh::ATTRIBUTE_NORMAL).is_some());
}

/// A contact with NaN, or naming bodies the plug-in does not know, is rejected and counted;
/// nothing changes.
fn bad_contacts_are_rejected() {
    let mut s = scene(true, false);
    s.warm_up(true);
    s.hit(f32::NAN, 0.0, SPEED_OK);
    s.frames(3);
    let stats = s.stats();
    assert_eq!((stats.dents, stats.rejected_contacts), (0, 1));
    assert_eq!(s.target_now().positions(), s.target_mesh.positions());
    still_dents(&mut s);
}

/// A body despawned right after its dent was decided: the render world (which runs beside the
/// main world) makes the dent if it got it before the body was forgotten, else drops it and
/// counts it; either way no dent is lost silently, nothing panics, and the other bodies keep
/// denting.
fn a_body_despawned_mid_batch() {
    let mut s = scene(true, false);
    s.warm_up(true);
    // A second dentable to hit after the first is gone.
    let other =
        spawn(&mut s, common::with_uvs(&common::plate_mesh()), Dentable::new(1.0, 0.01, 0.08), Transform::default());
    s.until("the second plate on the GPU", 60, |w| w.resource::<DentWorld>().path(other) == Some(DentPath::Gpu));
    s.hit(0.0, 0.0, SPEED_OK);
    // Run the main world's update only up to the decision, then despawn: run PostUpdate by hand.
    s.app.world_mut().run_schedule(PostUpdate);
    s.app.world_mut().despawn(s.target);
    s.frames(6);
    let stats = s.stats();
    assert_eq!(
        stats.gpu_dents + stats.rejected_contacts,
        1,
        "the dent was neither made nor counted as dropped: {stats:?}"
    );
    s.target = other;
    still_dents(&mut s);
}

/// The only GPU body despawned right after its dent was decided: the render world has no
/// resident target left, so the dent is made before the body is forgotten or dropped and
/// counted, never kept waiting; a body added afterwards dents.
fn the_last_body_despawned_mid_batch() {
    let mut s = scene(true, false);
    s.warm_up(true);
    s.hit(0.0, 0.0, SPEED_OK);
    s.app.world_mut().run_schedule(PostUpdate);
    s.app.world_mut().despawn(s.target);
    s.frames(6);
    let stats = s.stats();
    assert_eq!(stats.gpu_dents + stats.rejected_contacts, 1, "the dent was neither made nor counted: {stats:?}");
    let other =
        spawn(&mut s, common::with_uvs(&common::plate_mesh()), Dentable::new(1.0, 0.01, 0.08), Transform::default());
    s.until("a new plate on the GPU", 60, |w| w.resource::<DentWorld>().path(other) == Some(DentPath::Gpu));
    s.target = other;
    still_dents(&mut s);
}

/// A device without the kernels' limits (Bevy asked for WebGL2 limits: no storage buffers in
/// compute) puts every body on the CPU path, which still dents and updates the asset.
fn a_device_without_the_limits_takes_the_cpu_path() {
    let settings = WgpuSettings { constrained_limits: Some(WgpuLimits::downlevel_webgl2_defaults()), ..default() };
    let mut s = common::scene_with(
        true,
        false,
        Some(RenderPlugin { render_creation: RenderCreation::Automatic(Box::new(settings)), ..default() }),
    );
    s.warm_up(false);
    let status = s.app.world().resource::<bevy_dentbend::DentGpu>().status();
    assert!(
        matches!(&status, GpuStatus::Unavailable(why) if why.contains("max_storage_buffers_per_shader_stage")),
        "{status:?}"
    );
    s.hit(0.0, 0.0, SPEED_OK);
    s.until("a CPU dent", 30, |w| w.resource::<DentStats>().dents == 1);
    assert_ne!(s.target_asset_positions(), s.target_mesh.positions());
}

/// A body whose mesh, refined under a dent, would outgrow what Bevy's device can hold (storage
/// bindings of 512 KiB; the plate refined to 2 mm edges under the dent, tens of thousands of
/// vertices at 16 bytes each) leaves the GPU path with a log line: that dent is dropped and
/// counted, the body takes the CPU path, and a later hit dents it there (its asset updated).
fn a_body_outgrowing_the_device_takes_the_cpu_path() {
    let limits = WgpuLimits { max_storage_buffer_binding_size: 512 << 10, ..default() };
    let settings = WgpuSettings { constrained_limits: Some(limits), ..default() };
    let render = RenderPlugin { render_creation: RenderCreation::Automatic(Box::new(settings)), ..default() };
    let mut s = common::scene_with(true, false, Some(render));
    let mut dentable = Dentable::new(1.0, 0.01, 0.08);
    dentable.settings.params.refine = Refine::MaxEdge(0.002);
    s.app.world_mut().entity_mut(s.target).insert(dentable);
    s.warm_up(true);
    s.hit(0.0, 0.0, SPEED_OK);
    let target = s.target;
    s.until("the plate on the CPU path", 60, |w| w.resource::<DentWorld>().path(target) == Some(DentPath::Cpu));
    let stats = s.stats();
    assert_eq!((stats.dents, stats.rejected_contacts), (0, 1), "{stats:?}");
    s.hit(0.3, 0.3, SPEED_OK);
    s.until("a CPU dent", 60, |w| w.resource::<DentStats>().cpu_dents == 1);
    assert_ne!(s.target_asset_positions().len(), s.target_mesh.vertex_count(), "the CPU dent refined the asset");
}

/// Without a renderer at all (a server): the CPU path, mesh assets updated.
fn an_app_without_a_renderer_dents_on_the_cpu() {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, AssetPlugin::default(), TransformPlugin))
        .init_asset::<Mesh>()
        .add_plugins(DentbendPlugin::default());
    app.finish();
    app.cleanup();
    let mut s = common::Scene::around(app);
    s.warm_up(false);
    assert!(matches!(s.app.world().resource::<bevy_dentbend::DentGpu>().status(), GpuStatus::Unavailable(_)));
    s.hit(0.0, 0.0, SPEED_OK);
    s.until("a CPU dent", 30, |w| w.resource::<DentStats>().dents == 1);
    assert_ne!(s.target_asset_positions(), s.target_mesh.positions());
}

pub fn tests() -> Vec<Trial> {
    common::gpu_trials(
        module_path!(),
        vec![
            ("meshes_that_cannot_dent_are_refused_with_a_reason", meshes_that_cannot_dent_are_refused_with_a_reason),
            ("a_mesh_without_normals_gets_normals", a_mesh_without_normals_gets_normals),
            ("bad_contacts_are_rejected", bad_contacts_are_rejected),
            ("a_body_despawned_mid_batch", a_body_despawned_mid_batch),
            ("the_last_body_despawned_mid_batch", the_last_body_despawned_mid_batch),
            ("a_device_without_the_limits_takes_the_cpu_path", a_device_without_the_limits_takes_the_cpu_path),
            ("a_body_outgrowing_the_device_takes_the_cpu_path", a_body_outgrowing_the_device_takes_the_cpu_path),
            ("an_app_without_a_renderer_dents_on_the_cpu", an_app_without_a_renderer_dents_on_the_cpu),
        ],
    )
}
