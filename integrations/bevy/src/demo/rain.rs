//! Balls rain on a dentable block, the bunny and a low-poly crate, and on a bendable plank.

use bevy::app::ScheduleRunnerPlugin;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy::window::ExitCondition;
use dentbend::TriMesh;
use dentbend::dent::{Resolution, VolumeMode};
use dentbend::fracture::{FractureSettings, PatternParams};
use dentbend::glam::Vec3 as DVec3;
use dentbend::mesh;

use super::Physics;
use crate::{DentProjectile, Dentable, DentbendPlugin, bevy_mesh};

/// The rain.
#[derive(Resource, Debug, Clone)]
pub struct RainSettings {
    /// Balls spawned per frame (a fraction spreads them over frames).
    pub balls_per_frame: f32,
    /// Ball radius, m.
    pub ball_radius: f32,
    /// Downward speed at spawn, m/s (they fall 3 m more).
    pub speed: f32,
    /// Whether the block and the bunny dent (off: the same rain, no dent, for a baseline).
    pub dents: bool,
    /// Seed of the spawn positions.
    pub seed: u64,
    /// A bendable plank on two posts over the block.
    pub plank: bool,
    /// Z-buffer side of the block's and the bunny's dents, cells (`None`: from the meshes).
    pub resolution: Option<u32>,
    /// A breakable wall behind the block, broken by a wrecking ball at frame
    /// 20 (its dents and fracture take the CPU path).
    pub wall: bool,
    /// The plank dents where balls land on it (bendable dents, on the CPU path), and a ball
    /// landing fast splits the bone it lands on.
    pub dent_plank: bool,
}

impl Default for RainSettings {
    fn default() -> Self {
        Self {
            balls_per_frame: 0.5,
            ball_radius: 0.12,
            speed: 6.0,
            dents: true,
            seed: 7,
            plank: true,
            resolution: None,
            wall: false,
            dent_plank: false,
        }
    }
}

/// Marks the scene's dentable bodies and its bendable plank.
#[derive(Component, Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// The 4 × 1 × 4 m block the rain falls on.
    Block,
    /// The bunny sitting on it.
    Bunny,
    /// The bendable plank.
    Plank,
    /// A low-poly crate on the block: 12 triangles, its vertices split at its hard edges (as a
    /// game asset's), dented with the game settings (refinement, volume rim, guard) on the CPU
    /// path.
    Crate,
    /// The breakable wall behind the block.
    Wall,
}

/// A ball and the frame it was spawned.
#[derive(Component)]
struct Ball(u32);

/// The scene: light, camera (rendering into the [`Capture`](super::Capture) image when the app has
/// one, else into the window), block, bunny, and the rain spawner.
pub struct RainPlugin;

impl Plugin for RainPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<RainSettings>()
            .init_resource::<Physics>()
            .add_systems(Startup, setup)
            .add_systems(Update, (spawn_balls, despawn_balls, launch_wrecking_ball));
    }
}

/// A windowless app: Bevy's renderer without a window, run by a loop runner, the default
/// [`Physics`] stepping 1/60 s a frame, and dentbend (`gpu`: the GPU path when the device
/// allows). Add [`RainPlugin`] for the rain, and a [`CapturePlugin`](super::CapturePlugin) for
/// pictures.
pub fn headless_app(gpu: bool) -> App {
    headless_app_with(gpu, RenderPlugin::default(), Physics::default())
}

/// [`headless_app`] with Bevy's `render` plug-in configured (device limits, backends) and the
/// physics engine `physics`.
pub fn headless_app_with(gpu: bool, render: RenderPlugin, physics: Physics) -> App {
    let mut app = App::new();
    let window = WindowPlugin { primary_window: None, exit_condition: ExitCondition::DontExit, ..default() };
    let mut plugins = DefaultPlugins.set(window).set(render);
    if bevy::log::tracing::dispatcher::has_been_set() {
        // A second app in one process (tests): the first one's log subscriber stays.
        plugins = plugins.disable::<bevy::log::LogPlugin>();
    }
    #[cfg(feature = "window")]
    let plugins = plugins.disable::<bevy::winit::WinitPlugin>();
    app.add_plugins(plugins).add_plugins(ScheduleRunnerPlugin::run_loop(std::time::Duration::ZERO));
    physics.add_to(&mut app);
    app.add_plugins(DentbendPlugin { gpu, ..default() });
    app
}

fn setup(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    settings: Res<RainSettings>,
    physics: Res<Physics>,
    target: Option<Res<crate::demo::Capture>>,
) {
    let physics = *physics;
    commands.insert_resource(GlobalAmbientLight { brightness: 400.0, ..default() });
    commands.spawn((
        DirectionalLight { illuminance: 9000.0, shadow_maps_enabled: false, ..default() },
        // Low and from the side, so dents on the top face shade.
        Transform::from_xyz(6.0, 2.0, 1.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    let mut camera = commands.spawn((
        Camera3d::default(),
        Tonemapping::Reinhard,
        Transform::from_xyz(0.0, 3.2, 5.2).looking_at(Vec3::new(0.0, 0.2, 0.0), Vec3::Y),
    ));
    if let Some(capture) = target {
        camera.insert(capture.target());
    }

    let block = mesh::subdivided_box(DVec3::new(4.0, 1.0, 4.0), [64, 8, 64]).expect("a valid box");
    spawn_target(
        &mut commands,
        &mut meshes,
        &mut materials,
        (&settings, physics),
        Target::Block,
        &block,
        Vec3::new(0.0, -0.5, 0.0),
    );
    let bunny = unit_bunny();
    spawn_target(
        &mut commands,
        &mut meshes,
        &mut materials,
        (&settings, physics),
        Target::Bunny,
        &bunny,
        Vec3::new(1.1, 0.0, -0.6),
    );
    let mut game_crate = mesh::builtin("crate").expect("the built-in crate");
    game_crate.transform(dentbend::glam::Affine3A::from_scale(DVec3::splat(0.35))).expect("a smaller crate");
    spawn_target(
        &mut commands,
        &mut meshes,
        &mut materials,
        (&settings, physics),
        Target::Crate,
        &game_crate,
        // 0.7 m wide, on the block's back left quarter (clear of the tests' dropped balls).
        Vec3::new(-1.0, 0.35, -1.0),
    );
    if settings.plank {
        spawn_plank(&mut commands, &mut meshes, &mut materials, physics, settings.dents && settings.dent_plank);
    }
    if settings.wall && settings.dents {
        spawn_wall(&mut commands, &mut meshes, &mut materials, physics);
    }
}

/// The frame the wrecking ball is launched at the wall.
const WRECKING_FRAME: u32 = 20;
/// Where the wall stands: centre, m (2 × 1.2 × 0.15 m, behind the block, its front face looking
/// along +z).
const WALL_CENTRE: Vec3 = Vec3::new(0.3, 0.6, -2.4);

/// A fixed prescored wall (300 kg/m³, toughness 1 kJ, 40 cells within 0.4 m of the hit).
fn spawn_wall(
    commands: &mut Commands,
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<StandardMaterial>,
    physics: Physics,
) {
    let tri = mesh::subdivided_box(DVec3::new(2.0, 1.2, 0.15), [40, 24, 2]).expect("a valid box");
    let pattern = PatternParams { cells: 40, seed: 3, radius: 0.4 };
    let mut fracture = FractureSettings::new(pattern, Some(1000.0), None).expect("valid fracture settings");
    fracture.density = 300.0;
    let color = Color::srgb(0.75, 0.72, 0.68);
    let mut wall = commands.spawn((
        Target::Wall,
        Mesh3d(meshes.add(bevy_mesh(&tri))),
        MeshMaterial3d(materials.add(StandardMaterial { base_color: color, perceptual_roughness: 0.8, ..default() })),
        Transform::from_translation(WALL_CENTRE),
        Dentable::new(2.0, 0.002, 0.03).breaking(fracture),
    ));
    physics.fixed_trimesh(&mut wall, &tri);
}

/// At [`WRECKING_FRAME`], a 50 kg ball (radius 0.2 m) flies at 12 m/s (3.6 kJ) into the wall,
/// and a 5 kg one drops on the plank.
fn launch_wrecking_ball(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    settings: Res<RainSettings>,
    physics: Res<Physics>,
    mut frame: Local<u32>,
) {
    *frame += 1;
    if *frame != WRECKING_FRAME {
        return;
    }
    if settings.plank && settings.dent_plank && settings.dents {
        // A 5 kg ball dropped at 8 m/s on the plank's right bone, 0.8 m from its joint: it
        // splits the bone there and dents it.
        let radius = 0.12;
        let mut ball = commands.spawn((
            Mesh3d(meshes.add(Sphere::new(radius).mesh().ico(3).expect("a sphere"))),
            Transform::from_xyz(0.8, POST + 0.5, 1.2),
            DentProjectile,
        ));
        physics.ball(&mut ball, radius, 5.0, Vec3::new(0.0, -8.0, 0.0), 0.0);
    }
    if !(settings.wall && settings.dents) {
        return;
    }
    let radius = 0.2;
    let mut ball = commands.spawn((
        Mesh3d(meshes.add(Sphere::new(radius).mesh().ico(3).expect("a sphere"))),
        Transform::from_translation(WALL_CENTRE + Vec3::new(0.1, 0.1, 1.0)),
        DentProjectile,
    ));
    physics.ball(&mut ball, radius, 50.0, Vec3::new(0.0, 0.0, -12.0), 0.0);
}

/// Height of the plank's posts above the block, m.
const POST: f32 = 0.4;

/// A 3.4 × 0.1 × 0.3 m plank of two bones (plastic joint of 40 N·m·s, 700 kg/m³) on two posts
/// near the block's front edge: balls that land on it bend it at the joint.
fn spawn_plank(
    commands: &mut Commands,
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<StandardMaterial>,
    physics: Physics,
    dents: bool,
) {
    use crate::{BendSettings, Bendable};
    use dentbend::bend::auto_skeleton;
    use dentbend::dent::DentSettings;
    let wood = materials.add(StandardMaterial { base_color: Color::srgb(0.6, 0.42, 0.25), ..default() });
    let post = meshes.add(Cuboid::new(0.2, POST, 0.3));
    for x in [-1.5, 1.5] {
        let mut post = commands.spawn((
            Mesh3d(post.clone()),
            MeshMaterial3d(wood.clone()),
            Transform::from_xyz(x, 0.5 * POST, 1.2),
        ));
        physics.fixed_box(&mut post, Vec3::new(0.1, 0.5 * POST, 0.15));
    }
    let plank = mesh::plank(3.4, 0.3, 0.1, 68).expect("a valid plank");
    let skeleton = auto_skeleton(&plank, 2).expect("a two-bone plank");
    let mut settings = BendSettings::plastic(700.0, 40.0);
    if dents {
        // A ball landing at 3 m/s or more splits the bone it lands on (joints 0.4 m apart at least).
        (settings.split_speed, settings.min_joint_spacing) = (Some(3.0), 0.4);
    }
    let mut bendable = Bendable::new(skeleton, settings);
    if dents {
        // Dented where balls land on it: 2 m/s threshold, 5 mm per m/s above it, at most 2 cm.
        bendable = bendable.dentable(DentSettings::new(2.0, 0.005, 0.02));
    }
    commands.spawn((
        Target::Plank,
        Mesh3d(meshes.add(bevy_mesh(&plank))),
        MeshMaterial3d(wood),
        Transform::from_xyz(0.0, POST + 0.052, 1.2),
        bendable,
    ));
}

/// The built-in bunny, 1 m tall, standing on y = 0 with its foot centred on the origin.
fn unit_bunny() -> TriMesh {
    let bunny = mesh::builtin("bunny").expect("the built-in bunny");
    let (lo, hi) = bunny.bounds();
    let scale = 1.0 / (hi.y - lo.y);
    let foot = DVec3::new(0.5 * (lo.x + hi.x), lo.y, 0.5 * (lo.z + hi.z));
    let positions = bunny.positions().iter().map(|p| (*p - foot) * scale).collect();
    TriMesh::new(positions, bunny.faces().to_vec()).expect("a scaled bunny")
}

fn spawn_target(
    commands: &mut Commands,
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<StandardMaterial>,
    (settings, physics): (&RainSettings, Physics),
    kind: Target,
    tri: &TriMesh,
    at: Vec3,
) {
    let color = match kind {
        Target::Block => Color::srgb(0.55, 0.6, 0.7),
        Target::Bunny | Target::Plank => Color::srgb(0.85, 0.7, 0.5),
        Target::Crate | Target::Wall => Color::srgb(0.6, 0.45, 0.3),
    };
    let mut entity = commands.spawn((
        kind,
        Mesh3d(meshes.add(bevy_mesh(tri))),
        MeshMaterial3d(materials.add(StandardMaterial { base_color: color, perceptual_roughness: 0.6, ..default() })),
        Transform::from_translation(at),
    ));
    physics.fixed_trimesh(&mut entity, tri);
    if settings.dents {
        // 2 m/s threshold, 8 mm per m/s above it, at most 6 cm; the game dent (refinement,
        // guard), the crate (a solid) keeping its volume.
        let mut dentable = Dentable::new(2.0, 0.008, 0.06);
        if kind == Target::Crate {
            dentable = dentable.with_volume(VolumeMode::Preserve);
        }
        if let Some(side) = settings.resolution {
            dentable.settings.params.resolution = Resolution::Fixed(side);
        }
        entity.insert(dentable);
    }
}

/// A deterministic stream of numbers in [0, 1) (SplitMix64).
fn unit(state: &mut u64) -> f32 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
}

/// The spawner's state: random stream, balls owed, frame, the balls' mesh and material.
struct Spawner {
    rng: u64,
    owed: f32,
    frame: u32,
    mesh: Handle<Mesh>,
    material: Handle<StandardMaterial>,
}

fn spawn_balls(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    settings: Res<RainSettings>,
    physics: Res<Physics>,
    mut state: Local<Option<Spawner>>,
) {
    let Spawner { rng, owed, frame, mesh, material } = state.get_or_insert_with(|| {
        let ball = mesh::icosphere(settings.ball_radius, 2).expect("a valid sphere");
        let material = StandardMaterial { base_color: Color::srgb(0.8, 0.2, 0.15), ..default() };
        Spawner {
            rng: settings.seed,
            owed: 0.0,
            frame: 0,
            mesh: meshes.add(bevy_mesh(&ball)),
            material: materials.add(material),
        }
    });
    *frame += 1;
    *owed += settings.balls_per_frame;
    while *owed >= 1.0 {
        *owed -= 1.0;
        let x = -1.8 + 3.6 * unit(rng);
        let z = -1.8 + 3.6 * unit(rng);
        let mut ball = commands.spawn((
            Ball(*frame),
            DentProjectile,
            Mesh3d(mesh.clone()),
            MeshMaterial3d(material.clone()),
            Transform::from_xyz(x, 3.0, z),
        ));
        // Steel: 7,800 kg/m³.
        let mass = 7800.0 * 4.0 / 3.0 * std::f32::consts::PI * settings.ball_radius.powi(3);
        physics.ball(&mut ball, settings.ball_radius, mass, Vec3::new(0.0, -settings.speed, 0.0), 0.3);
    }
}

/// Balls leave after three seconds or when they fall off the block.
fn despawn_balls(mut commands: Commands, balls: Query<(Entity, &Ball, &Transform)>, mut frame: Local<u32>) {
    *frame += 1;
    for (entity, ball, transform) in &balls {
        if *frame > ball.0 + 180 || transform.translation.y < -3.0 {
            commands.entity(entity).despawn();
        }
    }
}
