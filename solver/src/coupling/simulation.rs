//! A world with denting in the loop: each step advances the bodies, then dents what was hit
//! (paper Algorithm 1, lines 9–21), and optionally skins the bending bodies (Algorithm 2, step
//! 13), timing the parts separately.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::{BendDenter, Bending, FractureEvent, Fracturer, Skinner, dent_step, step_motions};
use crate::sim::{DentRecord, Denter, GpuDevice, SimError, StepReport, World};
use dentbend::cpu::Skinned;
use dentbend::mesh::TriMesh;

/// Wall times and counts of one step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StepTiming {
    /// Step number (1 = the first).
    pub step: u64,
    /// Broad phase, contacts and impulses, and bending (the collisions found again after
    /// splits, splits, condensation), ms.
    pub dynamics_ms: f64,
    /// Dent batch and collider rebuilds, ms.
    pub denting_ms: f64,
    /// Skinning the bending bodies at the end of the step (see
    /// [`Simulation::skin_every_step`]; on the GPU: uploads of changed rest meshes, the bone
    /// matrices, the dispatches and the wait for them), ms; 0 when the step does not skin.
    pub skinning_ms: f64,
    /// Collision events.
    pub events: usize,
    /// Dents made.
    pub dents: usize,
    /// Bodies broken (prescored fracture, after the dents; timed in `denting_ms`).
    #[serde(default)]
    pub fractures: usize,
}

impl StepTiming {
    /// The whole step: dynamics, denting and skinning, ms.
    pub fn total_ms(&self) -> f64 {
        self.dynamics_ms + self.denting_ms + self.skinning_ms
    }
}

/// A [`World`] whose collisions dent its dentable bodies, with its bending bodies skinned on the
/// GPU or the CPU.
#[derive(Debug)]
pub struct Simulation {
    world: World,
    denter: Denter,
    dents: Vec<DentRecord>,
    fracturer: Fracturer,
    fractures: Vec<FractureEvent>,
    bending: Bending,
    bend_denter: BendDenter,
    skinner: Skinner,
    skin_every_step: bool,
    /// The world step the skinner's results are of; `None` when they are stale.
    skinned_at: Option<u64>,
}

impl Simulation {
    /// Wraps `world`; dents run on `gpu` when given (see [`Denter::new`]), else on the CPU, and
    /// so does skinning (see [`skin_on`](Self::skin_on)).
    ///
    /// # Errors
    /// [`SimError::Gpu`] when the dentable meshes cannot be uploaded.
    pub fn new(world: World, gpu: Option<&'static GpuDevice>) -> Result<Self, SimError> {
        let denter = Denter::new(&world, gpu)?;
        Ok(Self {
            world,
            denter,
            dents: Vec::new(),
            fracturer: Fracturer::new(),
            fractures: Vec::new(),
            bending: Bending::default(),
            bend_denter: BendDenter::new(),
            skinner: Skinner::new(gpu),
            skin_every_step: false,
            skinned_at: None,
        })
    }

    /// Builder: the bending bodies already added to the world (see [`Bending::add`]); each step
    /// then runs through [`Bending::step`] (dynamic articulation, joint and bend records).
    pub fn with_bending(mut self, bending: Bending) -> Self {
        self.bending = bending;
        self.skinned_at = None;
        self
    }

    /// Builder: where the bending bodies are skinned, the `skin` kernel on `gpu` (each body's rest
    /// mesh resident, see [`GpuSkinner`](crate::coupling::GpuSkinner)) or its CPU twin (`None`); by
    /// default where [`new`](Self::new) was told to dent.
    pub fn skin_on(mut self, gpu: Option<&'static GpuDevice>) -> Self {
        self.skinner = Skinner::new(gpu);
        self.skinned_at = None;
        self
    }

    /// Builder: whether every step ends by skinning the bending bodies, as a game does before
    /// drawing them (timed as [`StepTiming::skinning_ms`]); off by default, when
    /// [`skinned`](Self::skinned) and [`skinned_meshes`](Self::skinned_meshes) skin on demand.
    pub fn skin_every_step(mut self, every: bool) -> Self {
        self.skin_every_step = every;
        self
    }

    /// Whether skinning runs on the GPU.
    pub fn skins_on_gpu(&self) -> bool {
        self.skinner.on_gpu()
    }

    /// Whether every step ends by skinning (see [`skin_every_step`](Self::skin_every_step)).
    pub fn skins_every_step(&self) -> bool {
        self.skin_every_step
    }

    /// The skinner (on the GPU: its resident meshes and upload count).
    pub fn skinner(&self) -> &Skinner {
        &self.skinner
    }

    /// Every bending body skinned to its pose now, in [`Bending::bodies`] order: positions and
    /// unit normals straight from the kernel (world, m). Skins now unless the step already did.
    ///
    /// # Errors
    /// As [`Skinner::skin`] and [`Skinner::skinned`].
    pub fn skinned(&mut self) -> Result<&[Skinned], SimError> {
        self.skin_now()?;
        self.skinner.skinned()
    }

    /// Every bending body's skinned mesh now: (name, mesh, colour), world coordinates, from
    /// whichever backend skins (see [`Skinner::meshes`]). Skins now unless the step already did.
    ///
    /// # Errors
    /// As [`skinned`](Self::skinned).
    pub fn skinned_meshes(&mut self) -> Result<Vec<(String, TriMesh, [f32; 3])>, SimError> {
        self.skin_now()?;
        self.skinner.meshes(&self.bending)
    }

    /// Skins the bending bodies unless their results are of this step already.
    fn skin_now(&mut self) -> Result<(), SimError> {
        let step = self.world.steps();
        if self.skinned_at != Some(step) {
            self.skinner.skin(&self.bending, &self.world)?;
            self.skinned_at = Some(step);
        }
        Ok(())
    }

    /// The bending bodies and what they did.
    pub fn bending(&self) -> &Bending {
        &self.bending
    }

    /// The world.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// Every dent made so far, in order.
    pub fn dents(&self) -> &[DentRecord] {
        &self.dents
    }

    /// Every fracture so far, in order.
    pub fn fractures(&self) -> &[FractureEvent] {
        &self.fractures
    }

    /// Whether dents run on the GPU.
    pub fn dents_on_gpu(&self) -> bool {
        self.denter.on_gpu()
    }

    /// One step: dynamics, then the step's dents (bending bodies' included, see
    /// [`dent_step`](crate::coupling::dent_step)), then the fractures of breakable bodies (see
    /// `Fracturer::process`), then, with
    /// [`skin_every_step`](Self::skin_every_step), skinning the bending bodies.
    ///
    /// # Errors
    /// A dent failed (the bodies keep their meshes; the step's motion stands), a bone split
    /// (see [`Bending::step`]), or skinning failed (the step's motion and dents stand).
    pub fn step(&mut self) -> Result<(StepTiming, StepReport), SimError> {
        self.skinned_at = None;
        // Model transforms before the step: dents land where the targets were hit.
        let before: Vec<_> = self.world.bodies().iter().map(|b| b.model_transform()).collect();
        let breakable = self.world.bodies().iter().any(|b| b.fracture.is_some());
        let velocities: Vec<_> = match breakable {
            true => self.world.bodies().iter().map(|b| (b.linear_velocity, b.angular_velocity)).collect(),
            false => Vec::new(),
        };
        let started = Instant::now();
        let report = self.bending.step(&mut self.world)?;
        let dynamics_ms = started.elapsed().as_secs_f64() * 1e3;
        let step = self.world.steps();
        let started = Instant::now();
        let (bending, world, events) = (&mut self.bending, &mut self.world, &report.events);
        let motions = if breakable { step_motions(bending, world, &before, step) } else { Vec::new() };
        let records = dent_step(&mut self.bend_denter, &mut self.denter, bending, world, events, step, &before)?;
        let fractures = match breakable {
            true => self.fracturer.process(world, events, &records, step, (&motions, &velocities))?,
            false => Vec::new(),
        };
        for fracture in &fractures {
            // The rest replaced the body's mesh: a progressive dent under way on it restarts
            // from the rest, not from the surface the body had before it broke.
            if let Some(k) = world.find(&fracture.body) {
                self.denter.forget(k);
            }
        }
        let fracture_count = fractures.len();
        self.fractures.extend(fractures);
        let denting_ms = started.elapsed().as_secs_f64() * 1e3;
        let dents = records.len();
        self.dents.extend(records);
        let mut skinning_ms = 0.0;
        if self.skin_every_step && !self.bending.is_empty() {
            let started = Instant::now();
            self.skin_now()?;
            skinning_ms = started.elapsed().as_secs_f64() * 1e3;
        }
        let events = report.events.len();
        let timing =
            StepTiming { step, dynamics_ms, denting_ms, skinning_ms, events, dents, fractures: fracture_count };
        Ok((timing, report))
    }
}
