//! Shared by the plug-in's tests: their trials (apps with a renderer skipped without a GPU
//! adapter, unless `DENTBEND_REQUIRE_GPU=1`), and a scripted scene:
//! a dentable plate under a camera, a hidden ball, and dents made through the contact hook.

#![allow(dead_code)]

pub mod slab;

use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy_dentbend::demo::{Capture, CapturePlugin, Captured, Frame, Physics, headless_app, headless_app_with};
use bevy_dentbend::dentbend::dent::BodyState;
use bevy_dentbend::dentbend::glam::{Affine3A, Mat3};
use bevy_dentbend::dentbend::{TriMesh, mesh};
use bevy_dentbend::{
    DentBody, DentContact, DentGpu, DentPath, DentProjectile, DentStats, DentWorld, Dentable, GpuStatus,
};
use libtest_mimic::{Failed, Trial};

/// The trials of `module`'s tests that build a Bevy app with a renderer: without a GPU
/// adapter they are ignored, with the reason (failed under `DENTBEND_REQUIRE_GPU=1`).
pub fn gpu_trials(module: &str, tests: Vec<(&'static str, fn())>) -> Vec<Trial> {
    let adapter = bevy_dentbend::dentbend::gpu::GpuContext::new().err().map(|e| e.to_string());
    let required = std::env::var("DENTBEND_REQUIRE_GPU").as_deref() == Ok("1");
    tests
        .into_iter()
        .map(|(name, body)| {
            let name = trial_name(module, name);
            match (&adapter, required) {
                (None, _) => Trial::test(name, move || {
                    body();
                    Ok(())
                }),
                (Some(why), true) => {
                    let why = why.clone();
                    Trial::test(name, move || {
                        Err(Failed::from(format!("no GPU adapter ({why}) and DENTBEND_REQUIRE_GPU=1")))
                    })
                }
                (Some(why), false) => {
                    Trial::test(name, || Ok(())).with_ignored_flag(true).with_kind(format!("no GPU: {why}"))
                }
            }
        })
        .collect()
}

/// The trials of `module`'s tests that build apps without a renderer (no GPU needed).
pub fn headless_trials(module: &str, tests: Vec<(&'static str, fn())>) -> Vec<Trial> {
    tests
        .into_iter()
        .map(|(name, body)| {
            Trial::test(trial_name(module, name), move || {
                body();
                Ok(())
            })
        })
        .collect()
}

/// `file::test`, from the test's module path and name.
fn trial_name(module: &str, name: &str) -> String {
    format!("{}::{name}", module.rsplit("::").next().unwrap_or(module))
}

/// Frame size of the scripted scene, pixels.
pub const SIZE: UVec2 = UVec2::new(320, 240);
/// Half extents of the plate, m (its top face at y = 0).
pub const PLATE: Vec3 = Vec3::new(1.0, 0.1, 1.0);
/// Radius of the hidden ball, m.
pub const BALL: f32 = 0.25;
/// A ball speed that dents the plate, m/s (threshold 1 m/s).
pub const SPEED_OK: f32 = 5.0;

/// The scripted scene.
pub struct Scene {
    pub app: App,
    /// The dentable body.
    pub target: Entity,
    pub ball: Entity,
    pub camera: Entity,
    /// Reads what Bevy's vertex slab holds.
    pub probe: slab::SlabProbe,
    /// The dentable body (the plate, or the plank) as spawned.
    pub target_mesh: TriMesh,
}

/// The plate: 2 × 0.2 × 2 m, 48 × 2 × 48 cells, with UVs (so its vertices carry an attribute the
/// dents must not touch).
pub fn plate_mesh() -> TriMesh {
    mesh::subdivided_box(2.0 * PLATE, [48, 2, 48]).expect("a valid box")
}

/// A Bevy mesh of `tri` with UVs from x and z.
pub fn with_uvs(tri: &TriMesh) -> Mesh {
    let uvs: Vec<[f32; 2]> = tri.positions().iter().map(|p| [p.x * 0.5 + 0.5, p.z * 0.5 + 0.5]).collect();
    bevy_dentbend::bevy_mesh(tri).with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, uvs)
}

/// The scene on the GPU path (`gpu`) or the CPU path, with frames kept in memory when `capture`.
pub fn scene(gpu: bool, capture: bool) -> Scene {
    scene_with(gpu, capture, None)
}

/// The scene with the plate's [`Dentable`] replaced before it registers.
pub fn scene_dentable(gpu: bool, dentable: Dentable) -> Scene {
    let mut s = scene(gpu, false);
    s.app.world_mut().entity_mut(s.target).insert(dentable);
    s
}

/// [`scene`] with Bevy's render plug-in configured.
pub fn scene_with(gpu: bool, capture: bool, render: Option<RenderPlugin>) -> Scene {
    let mut app = match render {
        Some(render) => headless_app_with(gpu, render, Physics::default()),
        None => headless_app(gpu),
    };
    if capture {
        app.add_plugins(CapturePlugin { size: SIZE, out: None, keep: true });
    }
    let target_mesh = plate_mesh();
    let world = app.world_mut();
    let plate_asset = world.resource_mut::<Assets<Mesh>>().add(with_uvs(&target_mesh));
    let ball_asset = world.resource_mut::<Assets<Mesh>>().add(bevy_dentbend::bevy_mesh(&ball_mesh()));
    let grey = world.resource_mut::<Assets<StandardMaterial>>().add(StandardMaterial {
        base_color: Color::srgb(0.6, 0.6, 0.65),
        perceptual_roughness: 0.5,
        ..default()
    });
    let target = world
        .spawn((
            Mesh3d(plate_asset),
            MeshMaterial3d(grey.clone()),
            Transform::from_xyz(0.0, -PLATE.y, 0.0),
            // 1 m/s threshold, 1 cm per m/s above it, at most 8 cm.
            Dentable::new(1.0, 0.01, 0.08),
        ))
        .id();
    let ball = world
        .spawn((Mesh3d(ball_asset), MeshMaterial3d(grey), Transform::default(), Visibility::Hidden, DentProjectile))
        .id();
    world.spawn((
        DirectionalLight { illuminance: 8000.0, shadow_maps_enabled: false, ..default() },
        Transform::from_xyz(4.0, 1.5, 0.5).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    let mut camera = world.spawn((
        Camera3d::default(),
        Tonemapping::Reinhard,
        Transform::from_xyz(0.0, 2.2, 2.2).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    if capture {
        let target = camera.world().resource::<Capture>().target();
        camera.insert(target);
    }
    let camera = camera.id();
    let probe = slab::SlabProbe::install(&mut app);
    app.finish();
    app.cleanup();
    let mut scene = Scene { app, target, ball, camera, probe, target_mesh };
    scene.stop_capturing();
    scene
}

/// The hidden ball's mesh (its own coordinates).
pub fn ball_mesh() -> TriMesh {
    mesh::icosphere(BALL, 3).expect("a valid sphere")
}

impl Scene {
    /// The plate and the ball (no camera, no material) in `app`, which needs no renderer.
    pub fn around(mut app: App) -> Scene {
        let target_mesh = plate_mesh();
        let world = app.world_mut();
        let plate_asset = world.resource_mut::<Assets<Mesh>>().add(with_uvs(&target_mesh));
        let ball_asset = world.resource_mut::<Assets<Mesh>>().add(bevy_dentbend::bevy_mesh(&ball_mesh()));
        let target = world
            .spawn((Mesh3d(plate_asset), Transform::from_xyz(0.0, -PLATE.y, 0.0), Dentable::new(1.0, 0.01, 0.08)))
            .id();
        let ball = world.spawn((Mesh3d(ball_asset), Transform::default(), DentProjectile)).id();
        Scene { app, target, ball, camera: Entity::PLACEHOLDER, probe: slab::SlabProbe::default(), target_mesh }
    }

    /// Runs `n` frames.
    pub fn frames(&mut self, n: u32) {
        for _ in 0..n {
            self.app.update();
        }
    }

    /// Runs frames until `done` holds (at most `limit`); panics naming `what` otherwise.
    pub fn until(&mut self, what: &str, limit: u32, done: impl Fn(&World) -> bool) {
        for _ in 0..limit {
            if done(self.app.world()) {
                return;
            }
            self.app.update();
        }
        assert!(done(self.app.world()), "{what}: not after {limit} frames");
    }

    /// Runs frames until `dents` dents are made and their collider read-backs have all arrived
    /// (the read-back total unchanged over 4 frames, longer than a read-back takes).
    pub fn settle(&mut self, dents: u64) {
        self.until("the dents made", 120, |w| w.resource::<DentStats>().dents == dents);
        let (mut last, mut same) = (u64::MAX, 0);
        for _ in 0..120 {
            let bytes = self.stats().collider_readback_bytes;
            same = if bytes == last { same + 1 } else { 0 };
            if same >= 4 {
                return;
            }
            last = bytes;
            self.app.update();
        }
        panic!("the read-backs never settled");
    }

    /// Runs frames until the plate is registered on the expected path (the GPU one when `gpu`).
    pub fn warm_up(&mut self, gpu: bool) {
        let target = self.target;
        let path = if gpu { DentPath::Gpu } else { DentPath::Cpu };
        self.until("the plate registered", 200, |w| w.resource::<DentWorld>().path(target) == Some(path));
        if gpu {
            let status = self.app.world().resource::<DentGpu>().status();
            assert!(matches!(status, GpuStatus::Ready(_)), "GPU path expected, status {status:?}");
        }
        // A few frames for the mesh upload and the pipelines.
        self.frames(4);
    }

    fn stop_capturing(&mut self) {
        if let Some(mut capture) = self.app.world_mut().get_resource_mut::<Capture>() {
            capture.enabled = false;
        }
    }

    /// Renders frames until one more frame has been captured; that frame.
    pub fn capture(&mut self) -> Frame {
        let before = self.app.world().resource::<Captured>().done();
        self.app.world_mut().resource_mut::<Capture>().enabled = true;
        self.app.update();
        self.stop_capturing();
        self.until("a frame captured", 200, |w| w.resource::<Captured>().done() > before);
        self.app.world().resource::<Captured>().frames().pop().expect("a kept frame")
    }

    /// Captures frames until two in a row are identical (pipelines compiled, meshes uploaded,
    /// nothing changing); that frame.
    pub fn capture_settled(&mut self) -> Frame {
        let mut last = self.capture();
        for _ in 0..60 {
            let next = self.capture();
            if next.rgba == last.rgba {
                return next;
            }
            last = next;
        }
        panic!("the frame never settled");
    }

    /// Writes a contact of the hidden ball falling at `speed` m/s on the plate's top face at
    /// (x, z), through the contact hook.
    pub fn hit(&mut self, x: f32, z: f32, speed: f32) {
        let point = Vec3::new(x, 0.0, z);
        let centre = point + Vec3::Y * BALL;
        let inertia = Mat3::from_diagonal(Vec3::splat(1.0 / (0.4 * 10.0 * BALL * BALL)));
        let ball_state = BodyState::moving(centre, -speed * Vec3::Y, Vec3::ZERO, 10.0, inertia);
        let contact = DentContact {
            a: DentBody {
                entity: self.target,
                pose: Affine3A::from_translation(Vec3::new(0.0, -PLATE.y, 0.0)),
                state: BodyState::FIXED,
            },
            b: DentBody { entity: self.ball, pose: Affine3A::from_translation(centre), state: ball_state },
            point,
            normal: Vec3::Y,
            started: true,
        };
        self.app.world_mut().write_message(contact);
    }

    /// The plug-in's totals.
    pub fn stats(&self) -> DentStats {
        self.app.world().resource::<DentStats>().clone()
    }

    /// The plate's mesh as the main world knows it.
    pub fn target_now(&self) -> TriMesh {
        self.app.world().resource::<DentWorld>().mesh(self.target).expect("the plate is dentable").clone()
    }

    /// The positions of the plate's Bevy mesh asset (its private copy).
    pub fn target_asset_positions(&self) -> Vec<Vec3> {
        let handle = &self.app.world().get::<Mesh3d>(self.target).expect("a mesh").0;
        let mesh = self.app.world().resource::<Assets<Mesh>>().get(handle).expect("the asset");
        match mesh.attribute(Mesh::ATTRIBUTE_POSITION) {
            Some(bevy::mesh::VertexAttributeValues::Float32x3(p)) => p.iter().map(|p| Vec3::from_array(*p)).collect(),
            _ => panic!("the plate's asset lost its positions"),
        }
    }

    /// Where world point `p` appears in the frame, pixels.
    pub fn project(&mut self, p: Vec3) -> Vec2 {
        let mut query = self.app.world_mut().query::<(&Camera, &GlobalTransform)>();
        let (camera, transform) = query.get(self.app.world(), self.camera).expect("the camera");
        camera.world_to_viewport(transform, p).expect("a visible point")
    }
}

/// A windowless app without a renderer stepping `physics` (an engine's plug-ins) and `dentbend` at 1/60 s a frame
/// (manual time, so every frame is one fixed step), finished and ready to spawn into.
pub fn physics_app<M>(physics: impl bevy::app::Plugins<M>, dentbend: bevy_dentbend::DentbendPlugin) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, AssetPlugin::default(), TransformPlugin))
        .init_asset::<Mesh>()
        .add_plugins(physics)
        .add_plugins(dentbend)
        .insert_resource(bevy::time::TimeUpdateStrategy::ManualDuration(std::time::Duration::from_secs_f64(
            1.0 / 60.0,
        )));
    app.finish();
    app.cleanup();
    app
}

/// Spawns a dynamic ball projectile of `radius` m and `density` kg/m³ at `at`, moving at
/// `velocity` m/s; its entity.
pub fn launch_ball(app: &mut App, at: Vec3, radius: f32, density: f32, velocity: Vec3) -> Entity {
    use bevy_rapier3d::prelude::{Collider, ColliderMassProperties, RigidBody, Velocity};
    let mesh = app.world_mut().resource_mut::<Assets<Mesh>>().add(Sphere::new(radius).mesh().ico(3).expect("a sphere"));
    app.world_mut()
        .spawn((
            Mesh3d(mesh),
            Transform::from_translation(at),
            RigidBody::Dynamic,
            Collider::ball(radius),
            ColliderMassProperties::Density(density),
            Velocity::linear(velocity),
            DentProjectile,
        ))
        .id()
}
