//! `rapier_wall`: the paper's Figure 3 in Rapier. A 50 kg ball (radius 0.2 m) flies at 12 m/s
//! (3.6 kJ) into a fixed prescored wall 3 × 2 × 0.2 m (300 kg/m³) standing on the ground; the
//! wall's toughness is 1 kJ, so the hit dents it and then breaks it along a 40-cell pattern (finer near the hit) of
//! radius 0.5 m placed where it hit. The pieces become Rapier bodies, the ball carries on through the
//! hole with what the break left of its energy and pushes them out; the rest keeps the hole.
//! 60 Hz.

use dentbend::dent::DentSettings;
use dentbend::fracture::{FractureSettings, PatternParams};
use dentbend::mesh::{self, TriMesh};
use glam::Vec3;
use rapier3d::prelude::{ColliderBuilder, ColliderHandle, RigidBodyBuilder, RigidBodyHandle};

use crate::{Adapter, AdapterError, PhysicsWorld, StepReport, convex_collider, trimesh_collider};

/// Wall width (x), height (y) and thickness (z), m; it stands on the ground, centred on x = 0.
pub const WALL_SIZE: Vec3 = Vec3::new(3.0, 2.0, 0.2);
/// Ball radius, m.
pub const BALL_RADIUS: f32 = 0.2;
/// Ball mass, kg.
pub const BALL_MASS: f32 = 50.0;
/// Ball speed towards the wall, m/s.
pub const BALL_SPEED: f32 = 12.0;
/// The wall's toughness, J: the ball's 3.6 kJ pass it.
pub const TOUGHNESS: f32 = 1000.0;
/// The wall's density, kg/m³ (its pieces' mass).
pub const WALL_DENSITY: f32 = 300.0;
/// The pattern: cells, seed, radius (m). Its cells near the hit are smaller than the ball, which
/// pushes them ahead through the hole.
pub const PATTERN: PatternParams = PatternParams { cells: 40, seed: 3, radius: 0.5 };
/// The wall's dent settings: threshold 2 m/s, 2 mm per m/s above it, at most 3 cm.
pub const WALL_DENT: (f32, f32, f32) = (2.0, 0.002, 0.03);

/// The scene.
pub struct Wall {
    /// The Rapier world.
    pub world: PhysicsWorld,
    /// The adapter; the wall is its one dentable collider.
    pub adapter: Adapter,
    /// The wall's collider.
    pub wall: ColliderHandle,
    /// The ball.
    pub ball: RigidBodyHandle,
}

/// Totals of a run.
#[derive(Debug, Clone, Default)]
pub struct WallTotals {
    /// Steps run.
    pub steps: usize,
    /// Dents made (the wall's, before it broke, and any a piece made falling on it).
    pub dents: usize,
    /// Fractures.
    pub fractures: usize,
    /// Pieces the fractures made.
    pub pieces: usize,
    /// Pieces that became Rapier bodies.
    pub piece_bodies: usize,
    /// The step the wall broke on.
    pub fracture_step: Option<usize>,
    /// Rapier's step, s.
    pub physics_seconds: f64,
    /// Dent decisions, maps, fracture and collider work, s.
    pub damage_seconds: f64,
}

impl Wall {
    /// The scene before the ball arrives.
    ///
    /// # Errors
    /// A collider or setting that cannot be built (none for the defaults).
    pub fn new() -> Result<Self, AdapterError> {
        let mut world = PhysicsWorld::new(Vec3::new(0.0, -9.81, 0.0), 1.0 / 60.0);
        let mut adapter = Adapter::new();
        let ground = world.bodies.insert(RigidBodyBuilder::fixed().translation(Vec3::new(0.0, -0.5, 0.0)));
        world.colliders.insert_with_parent(ColliderBuilder::cuboid(20.0, 0.5, 20.0), ground, &mut world.bodies);

        let wall_mesh = wall_mesh()?;
        let body = world.bodies.insert(RigidBodyBuilder::fixed().translation(Vec3::new(0.0, 0.5 * WALL_SIZE.y, 0.0)));
        let collider = trimesh_collider(&wall_mesh)?;
        let wall = world.colliders.insert_with_parent(collider, body, &mut world.bodies);
        let (threshold, gain, cap) = WALL_DENT;
        let settings = DentSettings::new(threshold, gain, cap);
        adapter.dentables.insert(&world.colliders, &world.bodies, wall, wall_mesh, settings)?;
        let mut fracture = FractureSettings::new(PATTERN, Some(TOUGHNESS), None)
            .map_err(|error| AdapterError::Fracture { collider: wall, error })?;
        fracture.density = WALL_DENSITY;
        adapter.dentables.set_fracture(wall, Some(fracture))?;

        let ball_mesh = mesh::icosphere(BALL_RADIUS, 3)?;
        let start = Vec3::new(0.2, 0.5 * WALL_SIZE.y + 0.1, 1.5);
        let ball = RigidBodyBuilder::dynamic().translation(start).linvel(-BALL_SPEED * Vec3::Z);
        let ball = world.bodies.insert(ball);
        let volume = 4.0 / 3.0 * std::f32::consts::PI * BALL_RADIUS.powi(3);
        let collider = convex_collider(&ball_mesh)?.density(BALL_MASS / volume);
        let collider = world.colliders.insert_with_parent(collider, ball, &mut world.bodies);
        adapter.dentables.insert_projectile(&world.colliders, collider, ball_mesh)?;
        Ok(Self { world, adapter, wall, ball })
    }

    /// One step.
    ///
    /// # Errors
    /// As [`Adapter::step`].
    pub fn step(&mut self) -> Result<StepReport, AdapterError> {
        self.adapter.step(&mut self.world)
    }

    /// `steps` steps, totalled.
    ///
    /// # Errors
    /// As [`Adapter::step`].
    pub fn run(&mut self, steps: usize) -> Result<WallTotals, AdapterError> {
        let mut totals = WallTotals::default();
        let mut piece_bodies = Vec::new();
        for k in 0..steps {
            let report = self.step()?;
            totals.steps += 1;
            totals.dents += report.dents.len();
            totals.physics_seconds += report.physics_seconds;
            totals.damage_seconds += report.dent_seconds + report.collider_seconds;
            for broken in &report.fractures {
                totals.fractures += 1;
                totals.pieces += broken.pieces.len() + broken.left_out;
                totals.fracture_step.get_or_insert(k + 1);
                piece_bodies.extend(broken.pieces.iter().map(|p| p.body));
            }
        }
        totals.piece_bodies = piece_bodies.iter().filter(|&&b| self.world.bodies.contains(b)).count();
        Ok(totals)
    }

    /// The wall's mesh now (its rest after the break), collider frame.
    pub fn wall_mesh(&self) -> Option<&TriMesh> {
        self.adapter.dentables.mesh(self.wall)
    }
}

/// The wall's mesh: 60 × 40 × 2 cells, centred on its body.
fn wall_mesh() -> Result<TriMesh, AdapterError> {
    Ok(mesh::subdivided_box(WALL_SIZE, [60, 40, 2])?)
}
