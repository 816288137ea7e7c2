//! A world with denting in the loop: each step advances the bodies, then dents what was hit
//! (paper Algorithm 1, lines 9–21), timing the two parts separately.

use std::time::Instant;

use serde::Serialize;

use super::{DentRecord, Denter, SimError, StepReport, World};
use crate::bend::{BendDenter, Bending, dent_step};
use crate::gpu::GpuContext;

/// Wall times and counts of one step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StepTiming {
    /// Step number (1 = the first).
    pub step: u64,
    /// Broad phase, contacts and impulses, and bending (the dummy step and its repeat, splits,
    /// condensation), ms.
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
    bending: Bending,
    bend_denter: BendDenter,
}

impl Simulation {
    /// Wraps `world`; dents run on `gpu` when given (see [`Denter::new`]), else on the CPU.
    ///
    /// # Errors
    /// [`SimError::Gpu`] when the dentable meshes cannot be uploaded.
    pub fn new(world: World, gpu: Option<&'static GpuContext>) -> Result<Self, SimError> {
        let denter = Denter::new(&world, gpu)?;
        Ok(Self { world, denter, dents: Vec::new(), bending: Bending::default(), bend_denter: BendDenter::new() })
    }

    /// Builder: the bending bodies already added to the world (see [`Bending::add`]); each step
    /// then runs through [`Bending::step`] (dynamic articulation, joint and bend records).
    pub fn with_bending(mut self, bending: Bending) -> Self {
        self.bending = bending;
        self
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

    /// Whether dents run on the GPU.
    pub fn dents_on_gpu(&self) -> bool {
        self.denter.on_gpu()
    }

    /// One step: dynamics, then the step's dents (bending bodies' included, see
    /// [`dent_step`](crate::bend::dent_step)).
    ///
    /// # Errors
    /// A dent failed (the bodies keep their meshes; the step's motion stands), or a bone split
    /// (see [`Bending::step`]).
    pub fn step(&mut self) -> Result<(StepTiming, StepReport), SimError> {
        // Model transforms before the step: dents land where the targets were hit.
        let before: Vec<_> = self.world.bodies().iter().map(|b| b.model_transform()).collect();
        let started = Instant::now();
        let report = self.bending.step(&mut self.world)?;
        let dynamics_ms = started.elapsed().as_secs_f64() * 1e3;
        let step = self.world.steps();
        let started = Instant::now();
        let (bending, world, events) = (&mut self.bending, &mut self.world, &report.events);
        let records = dent_step(&mut self.bend_denter, &mut self.denter, bending, world, events, step, &before)?;
        let timing = StepTiming {
            step,
            dynamics_ms,
            denting_ms: started.elapsed().as_secs_f64() * 1e3,
            events: report.events.len(),
            dents: records.len(),
        };
        self.dents.extend(records);
        Ok((timing, report))
    }
}

/// Step-time statistics of a run (or part of one), ms.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct StepStats {
    /// Steps summarized.
    pub steps: usize,
    /// Mean dynamics time per step (broad phase, contacts, impulses), ms.
    pub dynamics_mean: f64,
    /// Mean denting time per step (dent batch, collider refits), ms.
    pub denting_mean: f64,
    /// Mean of both, ms.
    pub total_mean: f64,
    /// Median dynamics time, ms.
    pub dynamics_median: f64,
    /// Median denting time, ms.
    pub denting_median: f64,
    /// Median of both, ms.
    pub total_median: f64,
    /// Mean dents per step.
    pub dents_per_step_mean: f64,
    /// Denting time per dent (the batched pipeline's per-dent cost), ms; 0 without dents.
    pub denting_per_dent: f64,
}

impl StepStats {
    /// Means and medians of `steps` (all zero for none).
    pub fn of(steps: &[StepTiming]) -> Self {
        let n = steps.len().max(1) as f64;
        let sum = |f: fn(&StepTiming) -> f64| steps.iter().map(f).sum::<f64>();
        let median = |f: fn(&StepTiming) -> f64| {
            let mut values: Vec<f64> = steps.iter().map(f).collect();
            values.sort_by(f64::total_cmp);
            values.get(values.len() / 2).copied().unwrap_or(0.0)
        };
        let dents = sum(|t| t.dents as f64);
        Self {
            steps: steps.len(),
            dynamics_mean: sum(|t| t.dynamics_ms) / n,
            denting_mean: sum(|t| t.denting_ms) / n,
            total_mean: sum(|t| t.dynamics_ms + t.denting_ms) / n,
            dynamics_median: median(|t| t.dynamics_ms),
            denting_median: median(|t| t.denting_ms),
            total_median: median(|t| t.dynamics_ms + t.denting_ms),
            dents_per_step_mean: dents / n,
            denting_per_dent: if dents > 0.0 { sum(|t| t.denting_ms) / dents } else { 0.0 },
        }
    }
}
