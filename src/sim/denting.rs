//! Denting in the simulation loop (paper Algorithm 1, lines 13–21): after each step, every
//! collision above a dentable body's threshold dents it — both bodies of a pair when both are
//! dentable, maps built from the undented meshes (Jacobi) — through one batch per step on the
//! GPU (targets resident there) or on all CPU cores; then colliders are rebuilt.

use glam::{Affine3A, Vec3};
use serde::Serialize;

use super::energy::energy_dent_distance;
use super::{BodyKind, CollisionEvent, SimError, World};
use crate::dent::{DentJob, DentParams, Impact, dent_batch};
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
    /// Contact point, world, m.
    pub point: Vec3,
    /// Denting normal (into the target), world.
    pub normal: Vec3,
    /// Projectile's velocity relative to the target at the contact, m/s.
    pub relative_velocity: Vec3,
    /// Dent distance used, m (for progressive dents: the accumulated distance).
    pub dent_distance: f32,
}

/// A dent decided for this step, before batching.
#[derive(Clone, Copy)]
struct Pending {
    target: usize,
    projectile: usize,
    /// Impact in world coordinates.
    impact: Impact,
    dent_distance: f32,
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
    gpu: Option<(GpuDenter<'static>, Vec<Option<usize>>)>,
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
    ///
    /// # Errors
    /// A dent or GPU error; bodies keep their meshes then.
    pub fn process(
        &mut self,
        world: &mut World,
        events: &[CollisionEvent],
        step: u64,
    ) -> Result<Vec<DentRecord>, SimError> {
        let mut pending = Vec::new();
        for event in events {
            for (target, projectile, sign) in [(event.a, event.b, 1.0f32), (event.b, event.a, -1.0)] {
                if let Some(p) = decide(world, event, target, projectile, sign)? {
                    pending.push(p);
                }
            }
        }
        self.progress.retain(|p| p.last_step + 1 >= step);
        if pending.is_empty() {
            return Ok(Vec::new());
        }
        let (progressive, plain): (Vec<Pending>, Vec<Pending>) =
            pending.into_iter().partition(|p| world.bodies()[p.target].dent.as_ref().is_some_and(|d| d.progressive));
        let mut records = self.dent_plain(world, &plain, step)?;
        records.extend(self.dent_progressive(world, &progressive, step)?);
        for p in plain.iter().chain(&progressive) {
            move_projectile(world, p);
        }
        Ok(records)
    }

    /// Ordinary dents: one batch, on the GPU or all CPU cores.
    fn dent_plain(&mut self, world: &mut World, pending: &[Pending], step: u64) -> Result<Vec<DentRecord>, SimError> {
        if pending.is_empty() {
            return Ok(Vec::new());
        }
        // Dents whose projectile has nothing near the impact are dropped before the targets are
        // listed, so no target is copied or read back for nothing.
        let (pending, projectiles): (Vec<Pending>, Vec<TriMesh>) =
            pending.iter().filter_map(|p| Some((*p, projectile_in_target(world, p)?))).unzip();
        let pending = pending.as_slice();
        if pending.is_empty() {
            return Ok(Vec::new());
        }
        let mut targets: Vec<usize> = pending.iter().map(|p| p.target).collect();
        targets.sort_unstable();
        targets.dedup();
        let jobs: Vec<DentJob<'_>> = pending
            .iter()
            .zip(&projectiles)
            .map(|(p, mesh)| job(world, p, mesh, targets.binary_search(&p.target).unwrap_or(0)))
            .collect();
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
        Ok(pending.iter().map(|p| record(world, p, p.dent_distance, step)).collect())
    }

    /// Progressive dents (paper Figure 3): while a contact lasts, the dent is rebuilt from the
    /// pre-dent surface with the accumulated distance, so it deepens instead of stacking.
    fn dent_progressive(
        &mut self,
        world: &mut World,
        pending: &[Pending],
        step: u64,
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
            let Some(projectile) = projectile_in_target(world, p) else { continue };
            let deeper = Pending { dent_distance: distance, ..*p };
            let mut meshes = vec![state.pre_dent.clone()];
            dent_batch(&mut meshes, &[job(world, &deeper, &projectile, 0)])
                .map_err(|e| SimError::Dent { body: world.bodies()[p.target].name.clone(), error: e.error })?;
            state.accumulated = distance;
            state.last_step = step;
            world.bodies_mut()[p.target].set_mesh(meshes.pop().expect("one mesh"))?;
            records.push(record(world, p, distance, step));
        }
        Ok(records)
    }
}

/// Whether `target` dents from `event` (it is dentable and the normal speed is above its
/// threshold), and how deep. `sign` = 1 when the target is body a of the event.
fn decide(
    world: &World,
    event: &CollisionEvent,
    target: usize,
    projectile: usize,
    sign: f32,
) -> Result<Option<Pending>, SimError> {
    let body = &world.bodies()[target];
    let Some(settings) = &body.dent else { return Ok(None) };
    // Into the target, and the projectile's velocity relative to it.
    let impact =
        Impact { point: event.point, normal: -sign * event.normal, relative_velocity: sign * event.relative_velocity };
    let dent_error = |error| SimError::Dent { body: body.name.clone(), error };
    let Some(mut distance) = settings.material.dent_distance(&impact).map_err(dent_error)? else {
        return Ok(None);
    };
    if let Some(hardness) = settings.hardness {
        let projectile_mesh = world.bodies()[projectile].world_mesh();
        let lost = normal_energy_lost(world, event, target, projectile);
        let params = DentParams { dent_distance: settings.material.cap, ..settings.params.clone() };
        distance = energy_dent_distance(&projectile_mesh, &impact, &params, hardness, lost).map_err(dent_error)?;
        if distance <= 0.0 {
            return Ok(None);
        }
    }
    Ok(Some(Pending { target, projectile, impact, dent_distance: distance }))
}

/// Kinetic energy the collision removes along the normal, J: ½·m_eff·v_n²·(1 − e²), with m_eff
/// the pair's effective mass along the normal at the contact point (rotation included).
fn normal_energy_lost(world: &World, event: &CollisionEvent, target: usize, projectile: usize) -> f32 {
    let inverse = |k: usize| {
        let body = &world.bodies()[k];
        if body.kind != BodyKind::Dynamic {
            return 0.0;
        }
        let rn = (event.point - body.position).cross(event.normal);
        body.inverse_mass + (body.inverse_inertia_world() * rn).dot(rn)
    };
    let k = inverse(target) + inverse(projectile);
    if k <= 0.0 {
        return 0.0;
    }
    let (a, b) = (&world.bodies()[target].surface, &world.bodies()[projectile].surface);
    let e = a.restitution.max(b.restitution);
    0.5 / k * event.normal_speed.powi(2) * (1.0 - e * e)
}

/// The part of the projectile's surface that can shape the dent, in the target's body
/// coordinates: triangles with a corner within [`reach`] of the impact point. Far parts of a
/// large projectile (a bunny landing on a small ball) cannot touch the target, and leaving them
/// out keeps the dent's depth origin at the part that hit instead of the projectile's farthest
/// point. `None` when nothing is that close.
fn projectile_in_target(world: &World, p: &Pending) -> Option<TriMesh> {
    let (target, projectile) = (&world.bodies()[p.target], &world.bodies()[p.projectile]);
    let centre = projectile.transform().inverse().transform_point3(p.impact.point);
    let mut mesh = crop_to_ball(&projectile.mesh, centre, reach(world, p))?;
    // A rigid motion of a valid mesh stays finite.
    let _ = mesh.transform(target.transform().inverse() * projectile.transform());
    Some(mesh)
}

/// How far from the impact point the projectile can matter, m: the target's size (its dent
/// cannot be wider), plus the deepest dent and the Gaussian tails.
fn reach(world: &World, p: &Pending) -> f32 {
    let target = &world.bodies()[p.target];
    let radius = target.shape().compute_local_bounding_sphere().radius;
    let settings = target.dent.as_ref();
    let cap = settings.map_or(p.dent_distance, |d| d.material.cap.max(p.dent_distance));
    let sigma = settings.and_then(|d| d.params.sigma).unwrap_or(0.5 * cap);
    2.0 * radius + cap + 4.0 * sigma
}

/// The triangles of `mesh` with a corner within `radius` of `centre`, vertices renumbered;
/// the whole mesh (cloned) when all of it is that close.
fn crop_to_ball(mesh: &TriMesh, centre: glam::Vec3, radius: f32) -> Option<TriMesh> {
    let near: Vec<bool> = mesh.positions().iter().map(|p| p.distance_squared(centre) <= radius * radius).collect();
    if near.iter().all(|&n| n) {
        return Some(mesh.clone());
    }
    let mut index = vec![u32::MAX; mesh.vertex_count()];
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for face in mesh.faces() {
        if !face.iter().any(|&v| near[v as usize]) {
            continue;
        }
        faces.push(face.map(|v| {
            if index[v as usize] == u32::MAX {
                index[v as usize] = positions.len() as u32;
                positions.push(mesh.positions()[v as usize]);
            }
            index[v as usize]
        }));
    }
    TriMesh::new(positions, faces).ok()
}

/// The dent job of `p` in the target's body coordinates, against batch target `slot`.
fn job<'a>(world: &World, p: &Pending, projectile: &'a TriMesh, slot: usize) -> DentJob<'a> {
    let target = &world.bodies()[p.target];
    let to_body: Affine3A = target.transform().inverse();
    let impact = Impact {
        point: to_body.transform_point3(p.impact.point),
        normal: to_body.transform_vector3(p.impact.normal),
        relative_velocity: to_body.transform_vector3(p.impact.relative_velocity),
    };
    let settings = target.dent.as_ref().expect("only dentable bodies get jobs");
    DentJob {
        target: slot,
        projectile,
        impact,
        params: DentParams { dent_distance: p.dent_distance, ..settings.params.clone() },
    }
}

fn record(world: &World, p: &Pending, dent_distance: f32, step: u64) -> DentRecord {
    DentRecord {
        step,
        target: world.bodies()[p.target].name.clone(),
        projectile: world.bodies()[p.projectile].name.clone(),
        point: p.impact.point,
        normal: p.impact.normal,
        relative_velocity: p.impact.relative_velocity,
        dent_distance,
    }
}

/// Moves a dynamic projectile into the dent it made, when the target asks for it.
fn move_projectile(world: &mut World, p: &Pending) {
    let wants = world.bodies()[p.target].dent.as_ref().is_some_and(|d| d.move_projectile);
    let projectile = &mut world.bodies_mut()[p.projectile];
    if wants && projectile.kind == BodyKind::Dynamic {
        projectile.position += p.impact.unit_normal() * p.dent_distance;
    }
}

fn batch_error(world: &World, pending: &[Pending], message: String) -> SimError {
    let names: Vec<&str> = pending.iter().map(|p| world.bodies()[p.target].name.as_str()).collect();
    SimError::Gpu(format!("{message} (targets: {})", names.join(", ")))
}
