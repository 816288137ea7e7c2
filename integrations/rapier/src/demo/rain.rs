//! `rapier_rain`: balls rain in waves on the bunny and a block, both fixed tri-mesh colliders;
//! everything dents (the balls are convex hulls of icospheres that the bunny and the block dent
//! back, unless the settings make them rigid). 60 Hz.

use std::collections::{BTreeMap, HashMap};

use dentbend::damage::{AppliedDent, CpuBackend, DentBackend};
use dentbend::dent::DentSettings;
use dentbend::mesh::{self, TriMesh, content_hash};
use dentbend::record::DamageFile;
use glam::{Affine3A, Vec3};
use rapier3d::prelude::{ActiveEvents, ColliderBuilder, ColliderHandle, RigidBodyBuilder, RigidBodyHandle};

use super::Lcg;
use crate::{Adapter, AdapterError, PhysicsWorld, StepReport, convex_collider, trimesh_collider};

/// Ball radius, m.
pub const BALL_RADIUS: f32 = 0.12;
/// Ball mass, kg.
pub const BALL_MASS: f32 = 2.0;
/// Where the bunny stands (the middle of its base), world, m.
pub const BUNNY_AT: Vec3 = Vec3::new(-1.2, 0.0, 0.0);
/// Where the block's centre is, world, m.
pub const BLOCK_AT: Vec3 = Vec3::new(1.3, 0.25, 0.0);
/// Block size, m.
pub const BLOCK_SIZE: Vec3 = Vec3::new(1.6, 0.5, 1.6);

/// The bunny's and the block's dent settings: threshold 2 m/s, 8 mm per m/s above it, at most
/// 4 cm; σ 4 cm.
pub fn target_dent() -> DentSettings {
    let mut s = DentSettings::new(2.0, 0.008, 0.04);
    s.params.sigma = Some(0.04);
    s
}

/// The balls' dent settings: threshold 3 m/s, 2 mm per m/s above it, at most 1 cm; σ 2 cm.
pub fn ball_dent() -> DentSettings {
    let mut s = DentSettings::new(3.0, 0.002, 0.01);
    s.params.sigma = Some(0.02);
    s
}

/// The run's size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RainSettings {
    /// Steps of 1/60 s.
    pub steps: usize,
    /// Balls in all.
    pub balls: usize,
    /// Waves they come in, one every `wave_interval` steps from step 0.
    pub waves: usize,
    /// Steps between waves.
    pub wave_interval: usize,
    /// Jitter seed.
    pub seed: u64,
    /// Whether the balls are rigid projectiles (they dent the targets and are not dented).
    pub rigid_balls: bool,
}

impl Default for RainSettings {
    fn default() -> Self {
        Self { steps: 300, balls: 32, waves: 4, wave_interval: 45, seed: 7, rigid_balls: false }
    }
}

/// Totals of a run.
#[derive(Debug, Clone, Default)]
pub struct RainTotals {
    /// Steps run.
    pub steps: usize,
    /// Every dent, with the step it was made on.
    pub dents: Vec<(usize, AppliedDent<ColliderHandle>)>,
    /// Seconds in Rapier's step, dents, collider refits.
    pub physics_seconds: f64,
    /// Dent decisions and maps, s.
    pub dent_seconds: f64,
    /// Collider refits, s.
    pub collider_seconds: f64,
}

/// The scene, stepped by [`Rain::step`].
pub struct Rain {
    /// The Rapier world.
    pub world: PhysicsWorld,
    /// The adapter (all CPU).
    pub adapter: Adapter,
    /// The bunny's collider (fixed, tri-mesh).
    pub bunny: ColliderHandle,
    /// The block's collider (fixed, tri-mesh).
    pub block: ColliderHandle,
    /// The balls launched so far.
    pub balls: Vec<(RigidBodyHandle, ColliderHandle)>,
    /// Every dentable collider's mesh before the run (collider frame).
    pub initial: HashMap<ColliderHandle, TriMesh>,
    settings: RainSettings,
    rng: Lcg,
    ball_mesh: TriMesh,
    step: usize,
    /// Whether the bodies' damage is recorded (balls as they are launched).
    recording: bool,
}

impl Rain {
    /// The scene before the first wave.
    ///
    /// # Errors
    /// A mesh or collider that cannot be built (none for the defaults).
    pub fn new(settings: RainSettings) -> Result<Self, AdapterError> {
        Self::with_backend(settings, Box::new(CpuBackend))
    }

    /// The scene with its dents on `backend`.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn with_backend(
        settings: RainSettings,
        backend: Box<dyn DentBackend<ColliderHandle>>,
    ) -> Result<Self, AdapterError> {
        let mut world = PhysicsWorld::new(Vec3::new(0.0, -9.81, 0.0), 1.0 / 60.0);
        let mut adapter = Adapter::with_backend(backend);
        let mut initial = HashMap::new();
        let ground = world.bodies.insert(RigidBodyBuilder::fixed().translation(Vec3::new(0.0, -0.1, 0.0)));
        world.colliders.insert_with_parent(ColliderBuilder::cuboid(10.0, 0.1, 10.0), ground, &mut world.bodies);

        let mut bunny_mesh = mesh::builtin("bunny")?;
        bunny_mesh.transform(Affine3A::from_scale(Vec3::splat(0.15)))?;
        let bunny = add_fixed(&mut world, &bunny_mesh, BUNNY_AT)?;
        let block_mesh = mesh::subdivided_box(BLOCK_SIZE, [32, 10, 32])?;
        let block = add_fixed(&mut world, &block_mesh, BLOCK_AT)?;
        for (handle, mesh) in [(bunny, bunny_mesh), (block, block_mesh)] {
            adapter.dentables.insert(&world.colliders, &world.bodies, handle, mesh.clone(), target_dent())?;
            initial.insert(handle, mesh);
        }
        let ball_mesh = mesh::icosphere(BALL_RADIUS, 2)?;
        let rng = Lcg::new(settings.seed);
        let balls = Vec::new();
        Ok(Self { world, adapter, bunny, block, balls, initial, settings, rng, ball_mesh, step: 0, recording: false })
    }

    /// Records every body's damage from now on ([`Dentables::damage_file`](crate::Dentables::damage_file)):
    /// the bunny as `bunny`, the block as `block`, dentable balls as `ball-0`, `ball-1`, … in
    /// launch order.
    ///
    /// # Errors
    /// None for the scene's own colliders.
    pub fn record_damage(&mut self) -> Result<(), AdapterError> {
        self.recording = true;
        self.adapter.dentables.record_damage(self.bunny, "bunny")?;
        self.adapter.dentables.record_damage(self.block, "block")?;
        for k in 0..self.balls.len() {
            if self.adapter.dentables.is_dentable(self.balls[k].1) {
                self.adapter.dentables.record_damage(self.balls[k].1, format!("ball-{k}"))?;
            }
        }
        Ok(())
    }

    /// Gives the scene the damage `file` recorded (from a run of the same settings), with no
    /// simulation: the bunny and the block take theirs, and each recorded ball is placed
    /// beside the scene and takes its own; colliders follow.
    ///
    /// # Errors
    /// A body the scene does not have, damage that does not replay on it.
    pub fn restore(&mut self, file: &DamageFile) -> Result<(), AdapterError> {
        for body in &file.bodies {
            let handle = match body.name.as_str() {
                "bunny" => self.bunny,
                "block" => self.block,
                name => {
                    let k: usize = name.strip_prefix("ball-").and_then(|k| k.parse().ok()).ok_or_else(|| {
                        AdapterError::InvalidParameter {
                            name: "body",
                            value: name.to_owned(),
                            reason: "the rain scene has bodies bunny, block and ball-<n>",
                        }
                    })?;
                    while self.balls.len() <= k {
                        let at = Vec3::new(4.0 + 0.3 * self.balls.len() as f32, BALL_RADIUS, 3.0);
                        self.add_ball(at, Vec3::ZERO)?;
                    }
                    self.balls[k].1
                }
            };
            self.adapter.dentables.restore(&mut self.world.colliders, handle, body)?;
        }
        Ok(())
    }

    /// Content hash of every dentable body's mesh, by the names of
    /// [`record_damage`](Self::record_damage).
    pub fn mesh_hashes(&self) -> BTreeMap<String, u64> {
        let mut out = BTreeMap::new();
        let mut named = vec![("bunny".to_owned(), self.bunny), ("block".to_owned(), self.block)];
        named.extend(self.balls.iter().enumerate().map(|(k, b)| (format!("ball-{k}"), b.1)));
        for (name, handle) in named {
            if let Some(mesh) = self.adapter.dentables.mesh(handle) {
                out.insert(name, content_hash(mesh));
            }
        }
        out
    }

    /// The balls' mesh (collider frame, m).
    pub fn ball_mesh(&self) -> &TriMesh {
        &self.ball_mesh
    }

    /// The run's settings.
    pub fn settings(&self) -> RainSettings {
        self.settings
    }

    /// Steps once (launching a wave first when one is due).
    ///
    /// # Errors
    /// As [`Adapter::step`].
    pub fn step(&mut self) -> Result<StepReport, AdapterError> {
        let s = self.settings;
        if self.step.is_multiple_of(s.wave_interval.max(1)) && self.step / s.wave_interval.max(1) < s.waves {
            self.launch_wave()?;
        }
        self.step += 1;
        self.adapter.step(&mut self.world)
    }

    /// Runs every step.
    ///
    /// # Errors
    /// As [`step`](Self::step).
    pub fn run(&mut self) -> Result<RainTotals, AdapterError> {
        let mut totals = RainTotals::default();
        for i in 0..self.settings.steps {
            let r = self.step()?;
            totals.steps += 1;
            totals.physics_seconds += r.physics_seconds;
            totals.dent_seconds += r.dent_seconds;
            totals.collider_seconds += r.collider_seconds;
            totals.dents.extend(r.dents.into_iter().map(|d| (i, d)));
        }
        Ok(totals)
    }

    /// One wave: half the wave's balls over the bunny, half over the block, 1.2–2.2 m above
    /// their tops, falling at 1 m/s.
    fn launch_wave(&mut self) -> Result<(), AdapterError> {
        let per_wave = self.settings.balls.div_ceil(self.settings.waves.max(1));
        for k in 0..per_wave {
            if self.balls.len() >= self.settings.balls {
                break;
            }
            let (centre, half, top) = if k % 2 == 0 {
                (BUNNY_AT, 0.45, 1.45)
            } else {
                (BLOCK_AT, 0.5 * BLOCK_SIZE.x - 0.15, BLOCK_AT.y + 0.5 * BLOCK_SIZE.y)
            };
            let x = centre.x + self.rng.range(-half, half);
            let z = centre.z + self.rng.range(-half, half);
            let y = top + self.rng.range(1.2, 2.2);
            self.add_ball(Vec3::new(x, y, z), Vec3::new(0.0, -1.0, 0.0))?;
        }
        Ok(())
    }

    /// A ball at `at` moving at `velocity` (world, m and m/s): dentable, or a rigid projectile
    /// when the settings say so; its damage recorded when the scene's is.
    fn add_ball(&mut self, at: Vec3, velocity: Vec3) -> Result<(), AdapterError> {
        let density = BALL_MASS / self.ball_mesh.volume();
        let body = self.world.bodies.insert(RigidBodyBuilder::dynamic().translation(at).linvel(velocity));
        let collider = convex_collider(&self.ball_mesh)?
            .density(density)
            .restitution(0.3)
            .active_events(ActiveEvents::CONTACT_FORCE_EVENTS)
            .contact_force_event_threshold(0.0);
        let collider = self.world.colliders.insert_with_parent(collider, body, &mut self.world.bodies);
        let dentables = &mut self.adapter.dentables;
        if self.settings.rigid_balls {
            dentables.insert_projectile(&self.world.colliders, collider, self.ball_mesh.clone())?;
        } else {
            dentables.insert(
                &self.world.colliders,
                &self.world.bodies,
                collider,
                self.ball_mesh.clone(),
                ball_dent(),
            )?;
            self.initial.insert(collider, self.ball_mesh.clone());
            if self.recording {
                dentables.record_damage(collider, format!("ball-{}", self.balls.len()))?;
            }
        }
        self.balls.push((body, collider));
        Ok(())
    }
}

/// A fixed tri-mesh collider of `mesh` (its own coordinates) on a fixed body at `at`, m.
fn add_fixed(world: &mut PhysicsWorld, mesh: &TriMesh, at: Vec3) -> Result<ColliderHandle, AdapterError> {
    let body = world.bodies.insert(RigidBodyBuilder::fixed().translation(at));
    let collider = trimesh_collider(mesh)?
        .active_events(ActiveEvents::CONTACT_FORCE_EVENTS)
        .contact_force_event_threshold(0.0)
        .friction(0.6);
    Ok(world.colliders.insert_with_parent(collider, body, &mut world.bodies))
}
