//! A world with denting in the loop: each step advances the bodies, then dents what was hit
//! (paper Algorithm 1, lines 9–21), timing the two parts separately.

use std::time::Instant;

use serde::Serialize;

use super::{DentRecord, Denter, SimError, StepReport, World};
use crate::gpu::GpuContext;

/// Wall times and counts of one step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StepTiming {
    /// Step number (1 = the first).
    pub step: u64,
    /// Broad phase, contacts and impulses, ms.
    pub dynamics_ms: f64,
    /// Dent batch and collider rebuilds, ms.
    pub denting_ms: f64,
    /// Collision events.
    pub events: usize,
    /// Dents made.
    pub dents: usize,
}

/// A [`World`] whose collisions dent its dentable bodies.
#[derive(Debug)]
pub struct Simulation {
    world: World,
    denter: Denter,
    dents: Vec<DentRecord>,
}

impl Simulation {
    /// Wraps `world`; dents run on `gpu` when given (see [`Denter::new`]), else on the CPU.
    ///
    /// # Errors
    /// [`SimError::Gpu`] when the dentable meshes cannot be uploaded.
    pub fn new(world: World, gpu: Option<&'static GpuContext>) -> Result<Self, SimError> {
        let denter = Denter::new(&world, gpu)?;
        Ok(Self { world, denter, dents: Vec::new() })
    }

    /// The world.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// Every dent made so far, in order.
    pub fn dents(&self) -> &[DentRecord] {
        &self.dents
    }

    /// Whether dents run on the GPU.
    pub fn dents_on_gpu(&self) -> bool {
        self.denter.on_gpu()
    }

    /// One step: dynamics, then the step's dents.
    ///
    /// # Errors
    /// A dent failed (the bodies keep their meshes; the step's motion stands).
    pub fn step(&mut self) -> Result<(StepTiming, StepReport), SimError> {
        let report = self.world.step();
        let step = self.world.steps();
        let started = Instant::now();
        let records = self.denter.process(&mut self.world, &report.events, step)?;
        let timing = StepTiming {
            step,
            dynamics_ms: report.seconds * 1e3,
            denting_ms: started.elapsed().as_secs_f64() * 1e3,
            events: report.events.len(),
            dents: records.len(),
        };
        self.dents.extend(records);
        Ok((timing, report))
    }
}
