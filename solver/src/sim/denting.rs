//! Denting in the simulation loop (paper Algorithm 1, lines 13–21): after each step, every
//! collision above a dentable body's threshold dents it — both bodies of a pair when both are
//! dentable, maps built from the undented meshes (Jacobi) — through one batch per step on the
//! GPU (targets resident there) or on all CPU cores; then colliders are refitted. A thin user of
//! the world-free [`Damage`] API, with world body indices as the ids.

use super::{BodyKind, CollisionEvent, DentRecord, GpuDevice, SimError, StepContext, World, body_state};
use dentbend::damage::{CpuBackend, Damage, DamageError, DentBackend, DentTargets, Hit, TargetView};
use dentbend::dent::DentError;
#[cfg(feature = "gpu")]
use dentbend::gpu::GpuBackend;
#[cfg(feature = "gpu")]
use dentbend::mesh::TriMesh;

/// Runs the dents of each step's collisions.
pub struct Denter {
    #[cfg(feature = "gpu")]
    gpu: Option<GpuBackend<usize>>,
    damage: Damage<usize>,
}

impl std::fmt::Debug for Denter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Denter").field("gpu", &self.on_gpu()).finish()
    }
}

/// The world's bodies as the damage API asks about them.
struct WorldTargets<'w>(&'w World);

impl DentTargets<usize> for WorldTargets<'_> {
    fn contains(&self, key: usize) -> bool {
        key < self.0.bodies().len()
    }

    fn target(&self, key: usize) -> Option<TargetView<'_>> {
        let body = self.0.bodies().get(key)?;
        let settings = body.dent.as_ref()?;
        let radius = body.shape().compute_local_bounding_sphere().radius;
        // The world breaks its bodies after the step's dents (`coupling`'s fracture step).
        Some(TargetView { mesh: body.mesh(), to_world: body.transform(), settings, radius, fracture: None })
    }
}

impl Denter {
    /// A denter for `world`'s dentable bodies, on `gpu` when given (the dentable bodies'
    /// meshes are uploaded once and stay resident), else on the CPU.
    ///
    /// # Errors
    /// [`SimError::Gpu`] when the upload fails.
    pub fn new(world: &World, gpu: Option<&'static GpuDevice>) -> Result<Self, SimError> {
        #[cfg(feature = "gpu")]
        let gpu = match gpu {
            None => None,
            Some(context) => {
                let mut backend = GpuBackend::new(context);
                // The plain dentable bodies go resident now, once, instead of at their first hit.
                let (keys, meshes): (Vec<usize>, Vec<TriMesh>) = (world.bodies().iter().enumerate())
                    .filter(|(_, body)| body.dent.as_ref().is_some_and(|d| !d.progressive))
                    .map(|(k, body)| (k, body.mesh().clone()))
                    .unzip();
                backend.make_resident(&keys, &meshes).map_err(|e| SimError::Gpu(e.to_string()))?;
                Some(backend)
            }
        };
        #[cfg(not(feature = "gpu"))]
        let _ = (world, gpu.map(|device| match *device {}));
        Ok(Self {
            #[cfg(feature = "gpu")]
            gpu,
            damage: Damage::new(),
        })
    }

    /// Forgets what the denter holds of body `key`: its progressive dents under way (their
    /// pre-dent surfaces) and its resident GPU mesh. Call when something other than a dent
    /// replaced the body's mesh (a fracture leaving its rest), or a contact under way would
    /// rebuild its dent from the surface the body had before.
    pub fn forget(&mut self, key: usize) {
        self.damage.forget(key);
        #[cfg(feature = "gpu")]
        if let Some(gpu) = &mut self.gpu {
            gpu.forget(key);
        }
    }

    /// Whether dents run on the GPU.
    pub fn on_gpu(&self) -> bool {
        #[cfg(feature = "gpu")]
        return self.gpu.is_some();
        #[cfg(not(feature = "gpu"))]
        false
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
        let bodies = world.bodies();
        let mut hits = Vec::new();
        for event in events {
            for (target, projectile) in [(event.a, event.b), (event.b, event.a)] {
                let Some(settings) = bodies.get(target).and_then(|b| b.dent.as_ref()) else { continue };
                let Some(impact) = event.impact_on(target, context.motion(target)) else { continue };
                if !settings.may_dent(&impact) {
                    continue;
                }
                hits.push(Hit {
                    target,
                    projectile,
                    impact,
                    target_state: body_state(&bodies[target]),
                    projectile_state: body_state(&bodies[projectile]),
                    projectile_surface: context.surface(world, projectile),
                });
            }
        }
        #[cfg(feature = "gpu")]
        let backend: &mut dyn DentBackend<usize> = match &mut self.gpu {
            Some(gpu) => gpu,
            None => &mut CpuBackend,
        };
        #[cfg(not(feature = "gpu"))]
        let backend: &mut dyn DentBackend<usize> = &mut CpuBackend;
        let plan =
            self.damage.plan(&WorldTargets(world), &hits, step, backend).map_err(|e| damage_error(world, &hits, e))?;
        let records: Vec<DentRecord> = plan
            .dents
            .iter()
            .map(|d| DentRecord {
                step,
                target: world.bodies()[d.target].name.clone(),
                projectile: context.name(world, d.projectile).to_owned(),
                point: d.impact.point,
                normal: d.impact.normal,
                relative_velocity: d.impact.relative_velocity,
                dent_distance: d.dent_distance,
                volume_change: d.volume_change,
                cavity_volume: d.cavity_volume,
            })
            .collect();
        for target in plan.targets {
            world.bodies_mut()[target.key].set_mesh(target.mesh)?;
        }
        for d in &plan.dents {
            let projectile = &mut world.bodies_mut()[d.projectile];
            if projectile.kind == BodyKind::Dynamic {
                projectile.position += d.projectile_offset;
            }
        }
        Ok(records)
    }
}

/// A damage error in world terms: the dented body named, a backend failure as a GPU error.
fn damage_error(world: &World, hits: &[Hit<'_, usize>], error: DamageError) -> SimError {
    let name = |key: usize| world.bodies().get(key).map_or_else(|| key.to_string(), |b| b.name.clone());
    match error {
        DamageError::Dent { error: DentError::Backend(message), .. } => SimError::Gpu(message),
        DamageError::Dent { hit, error, .. } => SimError::Dent { body: name(hits[hit].target), error },
        DamageError::UnknownBody { body, .. } => super::error::invalid("dent body", body, "is not in the world"),
        DamageError::Fracture { hit, error, .. } => SimError::Fracture { body: name(hits[hit].target), error },
    }
}
