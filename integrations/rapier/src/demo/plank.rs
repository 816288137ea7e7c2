//! `rapier_plank`: the paper's Figure 14 in Rapier. A 60 kg ball (radius 0.2 m) falls at about
//! 6 m/s on a one-bone plank 4 × 0.1 × 0.3 m (700 kg/m³) lying across two supports 3.8 m
//! apart; the hit splits the bone where it lands (dynamic articulation above 2 m/s) and joins
//! the halves with a plastic joint (strength 40 N·m·s), which bends into a V and stays bent;
//! the ends stay straight. The plank is dentable: the ball also leaves a dent where it lands,
//! which bends with it. 60 Hz.

use dentbend::bend::{WeightParams, auto_skeleton};
use dentbend::dent::DentSettings;
use dentbend::mesh::{self, TriMesh};
use glam::Vec3;
use rapier3d::math::Pose;
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder, RigidBodyHandle};

use crate::{Adapter, AdapterError, BendSettings, Bendable, PhysicsWorld, StepReport};

/// Plank length (x), thickness (y) and width (z), m.
pub const PLANK_SIZE: Vec3 = Vec3::new(4.0, 0.1, 0.3);
/// Where the ball lands on the plank's top, world x and z, m (off the middle, so the joint's
/// place shows it follows the hit).
pub const HIT_X: f32 = 0.3;
/// Ball radius, m.
pub const BALL_RADIUS: f32 = 0.2;
/// Ball mass, kg.
pub const BALL_MASS: f32 = 60.0;
/// Ball speed when it reaches the plank, m/s (about).
pub const BALL_SPEED: f32 = 6.0;
/// Support centres' x, m.
pub const SUPPORT_X: f32 = 1.9;
/// The plank's dent settings: threshold 2 m/s, 5 mm per m/s above it, at most 3 cm (the
/// ball's hit at about 6 m/s leaves about 2 cm in the 10 cm plank).
pub const PLANK_DENT: (f32, f32, f32) = (2.0, 0.005, 0.03);
/// The plastic joints' strength, N·m·s.
pub const STRENGTH: f32 = 40.0;

/// The scene.
pub struct Plank {
    /// The Rapier world.
    pub world: PhysicsWorld,
    /// The adapter; `adapter.bendables[0]` is the plank.
    pub adapter: Adapter,
    /// The ball.
    pub ball: RigidBodyHandle,
}

/// Totals of a run.
#[derive(Debug, Clone, Default)]
pub struct PlankTotals {
    /// Steps run.
    pub steps: usize,
    /// Joints created by dynamic articulation.
    pub joints_created: usize,
    /// Steps on which a plastic joint yielded.
    pub plastic_bends: usize,
    /// Largest net plastic bend of any joint during the run, degrees.
    pub max_bend_deg: f32,
    /// The step the first joint was made on.
    pub split_step: Option<usize>,
    /// Dents made in the plank.
    pub dents: usize,
    /// Deepest dent distance, m.
    pub max_dent_depth: f32,
    /// Dent decisions, maps and the mapping back to the rest frame, s.
    pub dent_seconds: f64,
    /// Collider refits (hulls of dented pieces), s.
    pub collider_seconds: f64,
    /// Rapier's step, s.
    pub physics_seconds: f64,
    /// Splits and joint rules, s.
    pub bend_seconds: f64,
}

impl Plank {
    /// The scene before the ball lands. `weights_resolution`: level-set cells along the plank
    /// (64 is plenty for a box).
    ///
    /// # Errors
    /// A rig or collider that cannot be built (none for the defaults).
    pub fn new(weights_resolution: u32) -> Result<Self, AdapterError> {
        let mut world = PhysicsWorld::new(Vec3::new(0.0, -9.81, 0.0), 1.0 / 60.0);
        for x in [-SUPPORT_X, SUPPORT_X] {
            let body = world.bodies.insert(RigidBodyBuilder::fixed().translation(Vec3::new(x, -0.3, 0.0)));
            world.colliders.insert_with_parent(ColliderBuilder::cuboid(0.2, 0.3, 0.3), body, &mut world.bodies);
        }
        let ground = world.bodies.insert(RigidBodyBuilder::fixed().translation(Vec3::new(0.0, -0.7, 0.0)));
        world.colliders.insert_with_parent(ColliderBuilder::cuboid(4.0, 0.1, 1.5), ground, &mut world.bodies);

        let plank: TriMesh = mesh::plank(PLANK_SIZE.x, PLANK_SIZE.z, PLANK_SIZE.y, 64)?;
        let skeleton = auto_skeleton(&plank, 1).map_err(|e| AdapterError::Rig(e.to_string()))?;
        let mut settings = BendSettings::plastic(700.0, STRENGTH);
        settings.split_speed = Some(2.0);
        settings.weights = WeightParams { resolution: weights_resolution, ..WeightParams::default() };
        let pose = Pose::from_translation(Vec3::new(0.0, 0.5 * PLANK_SIZE.y + 0.002, 0.0));
        let mut adapter = Adapter::new();
        let mut bendable = Bendable::new(&mut world, plank, pose, skeleton, settings)?;
        let (threshold, gain, cap) = PLANK_DENT;
        bendable.set_dentable(DentSettings::new(threshold, gain, cap))?;
        adapter.bendables.push(bendable);

        // The ball starts 0.3 m above the plank's top and reaches it at about BALL_SPEED.
        let gap = 0.3;
        let start_speed = (BALL_SPEED * BALL_SPEED - 2.0 * 9.81 * gap).sqrt();
        let centre = Vec3::new(HIT_X, PLANK_SIZE.y + 0.002 + gap + BALL_RADIUS, 0.0);
        let ball = world.bodies.insert(RigidBodyBuilder::dynamic().translation(centre).linvel(Vec3::new(
            0.0,
            -start_speed,
            0.0,
        )));
        let density = BALL_MASS / (4.0 / 3.0 * std::f32::consts::PI * BALL_RADIUS.powi(3));
        let collider = world.colliders.insert_with_parent(
            ColliderBuilder::ball(BALL_RADIUS).density(density).friction(0.5),
            ball,
            &mut world.bodies,
        );
        adapter.dentables.insert_projectile(&world.colliders, collider, mesh::icosphere(BALL_RADIUS, 3)?)?;
        Ok(Self { world, adapter, ball })
    }

    /// The plank.
    pub fn plank(&self) -> &Bendable {
        &self.adapter.bendables[0]
    }

    /// Steps once.
    ///
    /// # Errors
    /// As [`Adapter::step`].
    pub fn step(&mut self) -> Result<StepReport, AdapterError> {
        self.adapter.step(&mut self.world)
    }

    /// Runs `steps` steps.
    ///
    /// # Errors
    /// As [`step`](Self::step).
    pub fn run(&mut self, steps: usize) -> Result<PlankTotals, AdapterError> {
        let mut t = PlankTotals::default();
        for i in 0..steps {
            let r = self.step()?;
            t.steps += 1;
            t.joints_created += r.joints_created;
            if r.joints_created > 0 && t.split_step.is_none() {
                t.split_step = Some(i);
            }
            t.plastic_bends += r.plastic_bends;
            t.dents += r.dents.len();
            t.max_dent_depth = r.dents.iter().map(|d| d.dent_distance).fold(t.max_dent_depth, f32::max);
            t.dent_seconds += r.dent_seconds;
            t.collider_seconds += r.collider_seconds;
            t.physics_seconds += r.physics_seconds;
            t.bend_seconds += r.bend_seconds;
            let bend = self.plank().joints().iter().map(|j| j.bend_angle()).fold(0.0, f32::max);
            t.max_bend_deg = t.max_bend_deg.max(bend.to_degrees());
        }
        Ok(t)
    }
}
