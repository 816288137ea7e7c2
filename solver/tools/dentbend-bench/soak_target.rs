//! The soak's target and its random hits: one body in a [`TargetSet`], dented through
//! [`Damage::plan`] (on the CPU or a GPU backend) and [`TargetSet::apply`], as an engine would.

use std::time::{Duration, Instant};

use dentbend::damage::{CpuBackend, Damage, DentBackend, Hit, TargetSet};
use dentbend::dent::{BodyState, DentSettings, Impact, Surface};
use dentbend::glam::{Affine3A, Mat3, Vec3};
use dentbend::mesh::Refinement;
use dentbend::{TriMesh, mesh};

use crate::surface_sample::{Rng, SurfacePoint, direction_in_cone, sample_surface};

/// Projectile speed of a hit at the full dent distance, m/s.
pub const SPEED: f32 = 10.0;

const TARGET: u32 = 0;
const BALL: u32 = 1;

/// Where the soak's dents run.
pub enum SoakBackend {
    /// The CPU twins on all cores.
    Cpu(CpuBackend),
    /// The crate's GPU backend (kernels on the device, the other stages on the host).
    Gpu(Box<dentbend::gpu::GpuBackend<u32>>),
}

impl SoakBackend {
    /// `cpu` or `gpu` (the latter needs an adapter: a clear error otherwise).
    pub fn parse(name: &str) -> Result<Self, String> {
        match name {
            "cpu" => Ok(Self::Cpu(CpuBackend)),
            "gpu" => {
                let context =
                    dentbend::gpu::shared_context().map_err(|e| format!("--backend gpu needs a GPU adapter: {e}"))?;
                Ok(Self::Gpu(Box::new(dentbend::gpu::GpuBackend::new(context))))
            }
            other => Err(format!("--backend {other:?} is neither cpu nor gpu")),
        }
    }

    /// The name `parse` takes.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Cpu(_) => "cpu",
            Self::Gpu(_) => "gpu",
        }
    }

    fn backend(&mut self) -> &mut dyn DentBackend<u32> {
        match self {
            Self::Cpu(cpu) => cpu,
            Self::Gpu(gpu) => gpu.as_mut(),
        }
    }
}

/// How big and how deep each hit is.
#[derive(Debug, Clone, Copy)]
pub struct HitSizes {
    /// Projectile radius, world units: the radius of every hit, or the largest.
    pub radius: f32,
    /// Head-on dent distance, world units: that of every hit, or the largest.
    pub dent_distance: f32,
    /// Whether each hit draws its radius uniformly from (0, `radius`].
    pub draw_radius: bool,
    /// Whether each hit draws its head-on dent distance uniformly from (0, `dent_distance`].
    pub draw_distance: bool,
}

/// One target under fire from a ball.
pub struct SoakTarget {
    set: TargetSet<u32>,
    damage: Damage<u32>,
    backend: SoakBackend,
    /// The built-in sphere, radius 1.
    unit_ball: TriMesh,
    /// The ball scaled to the last radius used.
    ball: (f32, TriMesh),
    sizes: HitSizes,
    half_angle: f32,
}

/// What one hit did, and how long the damage API took over it.
pub struct HitOutcome {
    /// Wall time of planning and applying the dent.
    pub elapsed: Duration,
    /// Dents made (0 or 1) and vertices moved, or the API's error message.
    pub result: Result<(usize, usize), String>,
    /// Faces whose normal the dent turned over (`mesh::turned_over_faces`).
    pub flipped_faces: usize,
}

impl SoakTarget {
    /// `mesh` (in its own coordinates, at the origin) hit by a ball of `sizes.radius` world units
    /// at up to [`SPEED`] within `half_angle` radians of its inward normal, dented
    /// `sizes.dent_distance` deep head-on and that times cos(incidence) otherwise (with
    /// `draw_*`, each hit draws its own fraction of them), on `backend`.
    pub fn new(mesh: TriMesh, sizes: HitSizes, half_angle: f32, backend: SoakBackend) -> Result<Self, String> {
        let unit_ball = mesh::builtin("sphere").map_err(|e| e.to_string())?;
        let ball = (sizes.radius, scaled_ball(&unit_ball, sizes.radius)?);
        // d = gain · v_n, capped at the largest head-on distance.
        let settings = DentSettings::new(0.0, sizes.dent_distance / SPEED, sizes.dent_distance);
        let mut set = TargetSet::new();
        set.insert(TARGET, mesh, Affine3A::IDENTITY, settings).map_err(|e| e.to_string())?;
        set.insert_rigid(BALL);
        Ok(Self { set, damage: Damage::new(), backend, unit_ball, ball, sizes, half_angle })
    }

    /// The target's surface as it is now.
    pub fn mesh(&self) -> &TriMesh {
        self.set.mesh(TARGET).expect("the target was inserted")
    }

    /// Hits the current surface at a point drawn from `rng` (uniform by area), the ball touching
    /// it there and moving within the cone about the inward normal; `step` numbers the hit.
    /// Drawn sizes come after the direction, so a run without them draws what it always did.
    ///
    /// # Errors
    /// When the surface has no area left to draw a point from.
    pub fn hit(&mut self, rng: &mut Rng, step: u64) -> Result<HitOutcome, String> {
        let at = sample_surface(self.mesh(), rng).ok_or("the target's surface has no area left")?;
        let direction = direction_in_cone(-at.normal, self.half_angle, rng);
        // 1 − [0, 1): uniform in (0, 1], never a zero radius or speed.
        let mut fraction = |drawn: bool| if drawn { 1.0 - rng.unit() as f32 } else { 1.0 };
        let radius = self.sizes.radius * fraction(self.sizes.draw_radius);
        let speed = SPEED * fraction(self.sizes.draw_distance);
        if radius != self.ball.0 {
            self.ball = (radius, scaled_ball(&self.unit_ball, radius)?);
        }
        Ok(self.hit_at(at, speed * direction, step))
    }

    /// Hits the current surface at `at`, the ball (of the last radius used) touching it there
    /// and moving at `velocity` (m/s); `step` numbers the hit.
    pub fn hit_at(&mut self, at: SurfacePoint, velocity: Vec3, step: u64) -> HitOutcome {
        let (radius, ball) = (self.ball.0, &self.ball.1);
        let centre = at.point + radius * at.normal;
        let projectile_state = BodyState::moving(centre, velocity, Vec3::ZERO, 1.0, Mat3::IDENTITY);
        let projectile_surface = Surface { mesh: ball, to_world: Affine3A::from_translation(centre) };

        let start = Instant::now();
        let planned = Impact::from_contact(at.point, -at.normal, &BodyState::FIXED, &projectile_state)
            .map_err(|e| e.to_string())
            .and_then(|impact| {
                let hit = Hit {
                    target: TARGET,
                    projectile: BALL,
                    impact,
                    target_state: BodyState::FIXED,
                    projectile_state,
                    projectile_surface,
                };
                self.damage.plan(&self.set, &[hit], step, self.backend.backend()).map_err(|e| e.to_string())
            });
        let mut elapsed = start.elapsed();
        // Counted between plan and apply, outside the timed part.
        let flipped_faces = planned.as_ref().map_or(0, |plan| {
            let before = self.mesh();
            plan.targets.iter().map(|t| flipped_faces(before, &t.mesh, &t.refinement)).sum()
        });
        let start = Instant::now();
        let result = planned.map(|plan| {
            let made = plan.dents.len();
            let moved = self.set.apply(plan.targets).iter().map(|(_, m)| m.len()).sum();
            (made, moved)
        });
        elapsed += start.elapsed();
        HitOutcome { elapsed, result, flipped_faces }
    }
}

/// The unit ball scaled to `radius`.
fn scaled_ball(unit_ball: &TriMesh, radius: f32) -> Result<TriMesh, String> {
    let mut ball = unit_ball.clone();
    ball.transform(Affine3A::from_scale(Vec3::splat(radius)))
        .map_err(|e| format!("the target is too large to scale a projectile for: {e}"))?;
    Ok(ball)
}

/// Faces of `after` (the dented `before`, refined by `refinement`) turned over by the dent: each
/// new vertex is put back where refinement made it on the undented surface, then every face's
/// normal before is compared with its normal after (`mesh::turned_over_faces`).
fn flipped_faces(before: &TriMesh, after: &TriMesh, refinement: &Refinement) -> usize {
    let mut undented = before.positions().to_vec();
    for split in &refinement.vertices {
        let [a, b] = split.parents.map(|p| undented[p as usize]);
        undented.push(a * (1.0 - split.fraction) + b * split.fraction);
    }
    if undented.len() != after.vertex_count() {
        // Not this target's refinement (cannot happen with one target): nothing to compare.
        return 0;
    }
    mesh::turned_over_faces(after.faces(), &undented, after.positions()).len()
}
