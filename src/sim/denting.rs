//! Denting in the simulation loop (paper Algorithm 1, lines 13–21): after each step, every
//! collision above a dentable body's threshold dents it — both bodies of a pair when both are
//! dentable, maps built from the undented meshes (Jacobi) — through one batch per step on the
//! GPU (targets resident there) or on all CPU cores; then colliders are rebuilt.

use glam::Vec3;
use serde::Serialize;

use super::{
    CollisionEvent, DecidedDent, DentSurface, DentTarget, SimError, StepContext, World, decide_dent, dent_job,
    projectile_near_impact,
};
use crate::dent::{DentJob, dent_batch};
use crate::gpu::{GpuContext, GpuDenter};
use crate::mesh::TriMesh;

/// One dent made during a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DentRecord {
    /// Step at which it happened (1 = after the first step).
    pub step: u64,
    /// The dented body.
    pub target: String,
    /// The body that dented it.
    pub projectile: String,
    /// Contact point, world, m (carried with the target to where it is after the step).
    pub point: Vec3,
    /// Denting normal (into the target), world.
    pub normal: Vec3,
    /// Projectile's velocity relative to the target at the contact, m/s.
    pub relative_velocity: Vec3,
    /// Dent distance used, m (for progressive dents: the accumulated distance).
    pub dent_distance: f32,
}

/// Progressive denting state of one (target, projectile) contact.
struct Progress {
    target: usize,
    projectile: usize,
    pre_dent: TriMesh,
    accumulated: f32,
    last_step: u64,
}

/// Runs the dents of each step's collisions.
pub struct Denter {
    gpu: Option<(GpuDenter, Vec<Option<usize>>)>,
    progress: Vec<Progress>,
}

impl std::fmt::Debug for Denter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Denter").field("gpu", &self.gpu.is_some()).finish()
    }
}

impl Denter {
    /// A denter for `world`'s dentable bodies, on `gpu` when given (the dentable bodies'
    /// meshes are uploaded once and stay resident), else on the CPU.
    ///
    /// # Errors
    /// [`SimError::Gpu`] when the upload fails.
    pub fn new(world: &World, gpu: Option<&'static GpuContext>) -> Result<Self, SimError> {
        let gpu = match gpu {
            None => None,
            Some(context) => {
                let mut slots = vec![None; world.bodies().len()];
                let mut meshes = Vec::new();
                for (k, body) in world.bodies().iter().enumerate() {
                    if body.dent.as_ref().is_some_and(|d| !d.progressive) {
                        slots[k] = Some(meshes.len());
                        meshes.push(body.mesh().clone());
                    }
                }
                let denter = GpuDenter::new(context, &meshes).map_err(|e| SimError::Gpu(e.to_string()))?;
                Some((denter, slots))
            }
        };
        Ok(Self { gpu, progress: Vec::new() })
    }

    /// Whether dents run on the GPU.
    pub fn on_gpu(&self) -> bool {
        self.gpu.is_some()
    }

    /// Dents the bodies hit in `events` (from the step numbered `step`) and returns what it did.
    /// Every body dents others with its own surface: [`process_with`](Self::process_with) with
    /// no overrides.
    ///
    /// # Errors
    /// A dent or GPU error; bodies keep their meshes then.
    pub fn process(
        &mut self,
        world: &mut World,
        events: &[CollisionEvent],
        step: u64,
    ) -> Result<Vec<DentRecord>, SimError> {
        self.process_with(world, events, step, &StepContext::default())
    }

    /// As [`process`](Self::process), with `context`: the bodies listed in its surfaces dent
    /// others with the surface given there instead of their own (a bending body's sub-bodies dent
    /// with the whole undented skinned mesh, world coordinates), and each target's contact is
    /// carried with the target's motion during the step. Every dent map is built from the
    /// undented surfaces (Jacobi), dynamic projectiles move into the dents after all of them.
    ///
    /// # Errors
    /// A dent or GPU error; bodies keep their meshes then.
    pub fn process_with(
        &mut self,
        world: &mut World,
        events: &[CollisionEvent],
        step: u64,
        context: &StepContext<'_>,
    ) -> Result<Vec<DentRecord>, SimError> {
        let mut pending = Vec::new();
        for event in events {
            for (target, projectile) in [(event.a, event.b), (event.b, event.a)] {
                let Some(target) = DentTarget::of_body(world, target) else { continue };
                let target = DentTarget { motion: context.motion(target.body), ..target };
                let projectile = context.surface(world, projectile);
                if let Some(p) = decide_dent(world, event, &target, &projectile)? {
                    pending.push(p);
                }
            }
        }
        self.progress.retain(|p| p.last_step + 1 >= step);
        if pending.is_empty() {
            return Ok(Vec::new());
        }
        let (progressive, plain): (Vec<DecidedDent>, Vec<DecidedDent>) =
            pending.into_iter().partition(|p| world.bodies()[p.target].dent.as_ref().is_some_and(|d| d.progressive));
        let surfaces = context.surfaces;
        let mut records = self.dent_plain(world, &plain, step, surfaces)?;
        records.extend(self.dent_progressive(world, &progressive, step, surfaces)?);
        for p in plain.iter().chain(&progressive) {
            if let Some(settings) = world.bodies()[p.target].dent.clone() {
                p.move_projectile(world, &settings);
            }
        }
        Ok(records)
    }

    /// Ordinary dents: one batch, on the GPU or all CPU cores.
    fn dent_plain(
        &mut self,
        world: &mut World,
        pending: &[DecidedDent],
        step: u64,
        surfaces: &[(usize, DentSurface<'_>)],
    ) -> Result<Vec<DentRecord>, SimError> {
        if pending.is_empty() {
            return Ok(Vec::new());
        }
        // Dents whose projectile has nothing near the impact are dropped before the targets are
        // listed, so no target is copied or read back for nothing.
        let mut kept = Vec::new();
        let mut projectiles = Vec::new();
        for p in pending {
            let target = target_of(world, p.target)?;
            if let Some(mesh) = projectile_near_impact(&target, p, &DentSurface::lookup(world, p.projectile, surfaces))
            {
                kept.push(*p);
                projectiles.push(mesh);
            }
        }
        let pending = kept.as_slice();
        if pending.is_empty() {
            return Ok(Vec::new());
        }
        let mut targets: Vec<usize> = pending.iter().map(|p| p.target).collect();
        targets.sort_unstable();
        targets.dedup();
        let jobs: Vec<DentJob<'_>> = pending
            .iter()
            .zip(&projectiles)
            .map(|(p, mesh)| {
                let slot = targets.binary_search(&p.target).unwrap_or(0);
                Ok(dent_job(&target_of(world, p.target)?, p, p.dent_distance, mesh, slot))
            })
            .collect::<Result<_, SimError>>()?;
        let dented: Vec<TriMesh> = match &mut self.gpu {
            Some((denter, slots)) => {
                let mut gpu_jobs = jobs.clone();
                for (j, p) in gpu_jobs.iter_mut().zip(pending) {
                    j.target = slots[p.target].unwrap_or(usize::MAX);
                }
                denter.dent_batch(&gpu_jobs).map_err(|e| batch_error(world, pending, e.to_string()))?;
                targets
                    .iter()
                    .map(|&t| denter.read_mesh(slots[t].unwrap_or(usize::MAX)))
                    .collect::<Result<_, _>>()
                    .map_err(|e| SimError::Gpu(e.to_string()))?
            }
            None => {
                let mut meshes: Vec<TriMesh> = targets.iter().map(|&t| world.bodies()[t].mesh().clone()).collect();
                dent_batch(&mut meshes, &jobs).map_err(|e| SimError::Dent {
                    body: world.bodies()[pending[e.job].target].name.clone(),
                    error: e.error,
                })?;
                meshes
            }
        };
        for (&t, mesh) in targets.iter().zip(dented) {
            world.bodies_mut()[t].set_mesh(mesh)?;
        }
        Ok(pending.iter().map(|p| record(world, p, p.dent_distance, step, surfaces)).collect())
    }

    /// Progressive dents (paper Figure 3): while a contact lasts, the dent is rebuilt from the
    /// pre-dent surface with the accumulated distance, so it deepens instead of stacking.
    fn dent_progressive(
        &mut self,
        world: &mut World,
        pending: &[DecidedDent],
        step: u64,
        surfaces: &[(usize, DentSurface<'_>)],
    ) -> Result<Vec<DentRecord>, SimError> {
        let mut records = Vec::new();
        for p in pending {
            let cap = world.bodies()[p.target].dent.as_ref().map_or(f32::INFINITY, |d| d.material.cap);
            let index = self.progress.iter().position(|s| s.target == p.target && s.projectile == p.projectile);
            let state = match index {
                Some(k) => &mut self.progress[k],
                None => {
                    let pre_dent = world.bodies()[p.target].mesh().clone();
                    self.progress.push(Progress {
                        target: p.target,
                        projectile: p.projectile,
                        pre_dent,
                        accumulated: 0.0,
                        last_step: step,
                    });
                    self.progress.last_mut().expect("just pushed")
                }
            };
            let distance = (state.accumulated + p.dent_distance).min(cap);
            let target = target_of(world, p.target)?;
            let deeper = DecidedDent { dent_distance: distance, ..*p };
            let projectile = DentSurface::lookup(world, p.projectile, surfaces);
            let Some(projectile) = projectile_near_impact(&target, &deeper, &projectile) else { continue };
            let mut meshes = vec![state.pre_dent.clone()];
            dent_batch(&mut meshes, &[dent_job(&target, p, distance, &projectile, 0)])
                .map_err(|e| SimError::Dent { body: world.bodies()[p.target].name.clone(), error: e.error })?;
            state.accumulated = distance;
            state.last_step = step;
            world.bodies_mut()[p.target].set_mesh(meshes.pop().expect("one mesh"))?;
            records.push(record(world, p, distance, step, surfaces));
        }
        Ok(records)
    }
}

fn batch_error(world: &World, pending: &[DecidedDent], message: String) -> SimError {
    let names: Vec<&str> = pending.iter().map(|p| world.bodies()[p.target].name.as_str()).collect();
    SimError::Gpu(format!("{message} (targets: {})", names.join(", ")))
}

/// The record of plain dent `p` (`dent_distance` m at `step`), its projectile named as in
/// `surfaces` (a bending body's sub-body by its body's name).
fn record(
    world: &World,
    p: &DecidedDent,
    dent_distance: f32,
    step: u64,
    surfaces: &[(usize, DentSurface<'_>)],
) -> DentRecord {
    let projectile = DentSurface::lookup(world, p.projectile, surfaces).name;
    p.record(&world.bodies()[p.target].name, projectile, dent_distance, step)
}

/// `index` as a dent target (it is dentable: only dentable bodies get dents decided).
fn target_of(world: &World, index: usize) -> Result<DentTarget<'_>, SimError> {
    DentTarget::of_body(world, index).ok_or_else(|| SimError::Invalid {
        what: "dent target".into(),
        value: world.bodies()[index].name.clone(),
        reason: "is not dentable",
    })
}
