//! The soak's target and its random hits: one body in a [`TargetSet`], dented through
//! [`Damage::plan`] on the CPU and [`TargetSet::apply`], as an engine would.

use std::time::{Duration, Instant};

use dentbend::dent::{BodyState, CpuBackend, Damage, DentSettings, Hit, Impact, Surface, TargetSet};
use dentbend::glam::{Affine3A, Mat3, Vec3};
use dentbend::{TriMesh, mesh};

use crate::surface_sample::{Rng, SurfacePoint, direction_in_cone, sample_surface};

/// Projectile speed, m/s.
pub const SPEED: f32 = 10.0;

const TARGET: u32 = 0;
const BALL: u32 = 1;

/// One target under fire from a ball.
pub struct SoakTarget {
    set: TargetSet<u32>,
    damage: Damage<u32>,
    ball: TriMesh,
    radius: f32,
    half_angle: f32,
}

/// What one hit did, and how long the damage API took over it.
pub struct HitOutcome {
    /// Wall time of planning and applying the dent.
    pub elapsed: Duration,
    /// Dents made (0 or 1) and vertices moved, or the API's error message.
    pub result: Result<(usize, usize), String>,
}

impl SoakTarget {
    /// `mesh` (in its own coordinates, at the origin) hit by a ball of `radius` world units at
    /// [`SPEED`] within `half_angle` radians of its inward normal, dented `dent_distance` deep
    /// head-on and `dent_distance`·cos(incidence) otherwise.
    pub fn new(mesh: TriMesh, radius: f32, dent_distance: f32, half_angle: f32) -> Result<Self, String> {
        let mut ball = mesh::builtin("sphere").map_err(|e| e.to_string())?;
        ball.transform(Affine3A::from_scale(Vec3::splat(radius)))
            .map_err(|e| format!("the target is too large to scale a projectile for: {e}"))?;
        // d = gain · v_n, capped at the head-on distance.
        let settings = DentSettings::new(0.0, dent_distance / SPEED, dent_distance);
        let mut set = TargetSet::new();
        set.insert(TARGET, mesh, Affine3A::IDENTITY, settings).map_err(|e| e.to_string())?;
        set.insert_rigid(BALL);
        Ok(Self { set, damage: Damage::new(), ball, radius, half_angle })
    }

    /// The target's surface as it is now.
    pub fn mesh(&self) -> &TriMesh {
        self.set.mesh(TARGET).expect("the target was inserted")
    }

    /// Hits the current surface at a point drawn from `rng` (uniform by area), the ball touching
    /// it there and moving within the cone about the inward normal; `step` numbers the hit.
    ///
    /// # Errors
    /// When the surface has no area left to draw a point from.
    pub fn hit(&mut self, rng: &mut Rng, step: u64) -> Result<HitOutcome, String> {
        let at = sample_surface(self.mesh(), rng).ok_or("the target's surface has no area left")?;
        let velocity = SPEED * direction_in_cone(-at.normal, self.half_angle, rng);
        Ok(self.hit_at(at, velocity, step))
    }

    /// Hits the current surface at `at`, the ball touching it there and moving at `velocity`
    /// (m/s); `step` numbers the hit.
    pub fn hit_at(&mut self, at: SurfacePoint, velocity: Vec3, step: u64) -> HitOutcome {
        let centre = at.point + self.radius * at.normal;
        let projectile_state = BodyState::moving(centre, velocity, Vec3::ZERO, 1.0, Mat3::IDENTITY);
        let projectile_surface = Surface { mesh: &self.ball, to_world: Affine3A::from_translation(centre) };

        let start = Instant::now();
        let result = Impact::from_contact(at.point, -at.normal, &BodyState::FIXED, &projectile_state)
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
                self.damage.plan(&self.set, &[hit], step, &mut CpuBackend).map_err(|e| e.to_string())
            })
            .map(|plan| {
                let made = plan.dents.len();
                let moved = self.set.apply(plan.targets).iter().map(|(_, m)| m.len()).sum();
                (made, moved)
            });
        HitOutcome { elapsed: start.elapsed(), result }
    }
}
