//! Fracture in the damage API: after a step's dents, each breakable body whose hit passes its
//! toughness, or whose accumulated dent passes its limit, breaks along its pattern placed at its
//! most energetic breaking hit ([`crate::fracture::break_body`] on the dented mesh, so the pieces
//! keep the dent). The rest stays the caller's body; each piece leaves moving as the body's
//! material moved at the piece's centre (v + ω × r), with an id the caller maps to a body of its
//! own; the projectile that broke it carries on with its velocity from before the step, less the
//! energy the break used up.

use glam::{Affine3A, Mat3, Vec3};
use serde::{Deserialize, Serialize};

use super::{DentTargets, Hit};
use crate::dent::{BodyState, Impact, normal_energy_lost};
use crate::fracture::{
    DentTally, FractureCause, FractureError, FractureRecord, FractureSettings, Placement, VertexOrigin,
};
use crate::mesh::{MassProperties, TriMesh};

/// A piece's id: the number of the fracture that made it (counted by one [`Damage`](super::Damage)
/// from 0) and its index among that fracture's pieces. Deterministic: the same hits on the same
/// bodies give the same ids, so a client replaying a server's damage names pieces alike.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct PieceId {
    /// The fracture's number.
    pub fracture: u64,
    /// The piece's index in [`BodyFracture::pieces`].
    pub index: u32,
}

/// How much of its size a piece's collider keeps: its hull shrunk toward its centre of mass
/// (the piece's mesh and mass properties are unchanged), so that pieces start apart.
pub const PIECE_HULL_SCALE: f32 = 0.97;

/// The points of a piece's collider hull, for any engine: the vertices of `mesh` shrunk by
/// [`PIECE_HULL_SCALE`] toward `centre` (its centre of mass, the mesh's coordinates). Pieces
/// fill the hole they leave exactly; hulls of these start clear of the rest and of each other
/// instead of wedged in, touching on every side.
pub fn piece_hull_points(mesh: &TriMesh, centre: Vec3) -> Vec<Vec3> {
    mesh.positions().iter().map(|&p| centre + (p - centre) * PIECE_HULL_SCALE).collect()
}

/// One piece that broke loose, for the caller to make a body of.
#[derive(Debug, Clone)]
pub struct BrokenPiece {
    /// Its id.
    pub id: PieceId,
    /// Its closed surface in the broken body's mesh coordinates (not re-centred: place it with
    /// the body's `to_world`), m.
    pub mesh: TriMesh,
    /// Mass, kg, centre of mass (mesh coordinates) and inertia about it, at the body's density.
    pub mass: MassProperties,
    /// Index of the pattern cell it came from.
    pub cell: usize,
    /// Velocity of its centre of mass, world, m/s (the body's material there before the step).
    pub linear_velocity: Vec3,
    /// Angular velocity, world, rad/s (the body's).
    pub angular_velocity: Vec3,
    /// Where each of its vertices lies on [`BodyFracture::broken_mesh`], one per vertex: for
    /// carrying UVs and other attributes over.
    pub origins: Vec<VertexOrigin>,
}

/// A body that broke.
#[derive(Debug, Clone)]
pub struct BodyFracture<K> {
    /// The body that broke; its rest keeps this id.
    pub body: K,
    /// The fracture's number, counted by one [`Damage`](super::Damage) from 0 (its pieces'
    /// [`PieceId::fracture`]).
    pub number: u64,
    /// The body that broke it.
    pub projectile: K,
    /// Why it broke.
    pub cause: FractureCause,
    /// The energy the breaking hit removed along its normal, J.
    pub energy: f32,
    /// The body's accumulated dent when it broke (this step's dents included), m.
    pub accumulated_dent: f32,
    /// The fracture as data, in the body's mesh coordinates: [`crate::fracture::replay`] on
    /// [`broken_mesh`](Self::broken_mesh) rebuilds the rest and the pieces bit for bit.
    pub record: FractureRecord,
    /// The body's mesh when it broke (this step's dents included).
    pub broken_mesh: TriMesh,
    /// The body's new mesh, same coordinates; `None` when the pattern took the whole body
    /// (remove it then).
    pub rest: Option<TriMesh>,
    /// Where each vertex of the rest lies on `broken_mesh`, one per vertex (empty with no rest).
    pub rest_origins: Vec<VertexOrigin>,
    /// The rest's mass properties at the body's density (`None` with no rest).
    pub rest_mass: Option<MassProperties>,
    /// The pieces, by pattern cell then connected part.
    pub pieces: Vec<BrokenPiece>,
    /// The projectile's (linear m/s, angular rad/s) velocity from before the step, scaled so
    /// that its kinetic energy lost the toughness an energy break used up: the body gave way
    /// instead of stopping it. `None` for a projectile that takes no impulse (fixed, kinematic).
    pub projectile_velocity: Option<(Vec3, Vec3)>,
}

/// A hit that breaks its body: what [`Damage`](super::Damage) decides before it breaks one, for
/// a solver that breaks bodies itself ([`judge`](Self::judge) each hit, keep each body's
/// strongest with [`keep_strongest`](Self::keep_strongest)).
#[derive(Debug, Clone, Copy)]
pub struct BreakingHit<K> {
    /// Index of the hit (or collision event) among the step's.
    pub hit: usize,
    /// The body it breaks.
    pub target: K,
    /// What hit it.
    pub projectile: K,
    /// The contact, normal into the target.
    pub impact: Impact,
    /// The target's state before the step.
    pub target_state: BodyState,
    /// The projectile's state before the step.
    pub projectile_state: BodyState,
    /// Why it breaks.
    pub cause: FractureCause,
    /// Kinetic energy the impact removes along the normal, J.
    pub energy: f32,
    /// The target's accumulated dent, m.
    pub accumulated: f32,
}

/// Each breakable body's most energetic breaking hit among `hits`, in order of the body's first
/// breaking hit. `tally` holds the accumulated dents, this step's included.
pub(crate) fn breaking_hits<K: Copy + PartialEq>(
    targets: &impl DentTargets<K>,
    hits: &[Hit<'_, K>],
    tally: &DentTally<K>,
) -> Vec<BreakingHit<K>> {
    let mut breaks: Vec<BreakingHit<K>> = Vec::new();
    for (k, hit) in hits.iter().enumerate() {
        let Some(settings) = targets.target(hit.target).and_then(|t| t.fracture) else { continue };
        let states = (hit.target_state, hit.projectile_state);
        let accumulated = tally.total(hit.target);
        if let Some(b) = BreakingHit::judge(k, (hit.target, hit.projectile), hit.impact, states, settings, accumulated)
        {
            BreakingHit::keep_strongest(&mut breaks, b);
        }
    }
    breaks
}

impl<K: Copy + PartialEq> BreakingHit<K> {
    /// Hit number `hit` of `projectile` on `target` (its impact and the two bodies' states),
    /// as a break of `target` by `settings` with `accumulated` m of dent so far, if it breaks it.
    pub fn judge(
        hit: usize,
        (target, projectile): (K, K),
        impact: Impact,
        (target_state, projectile_state): (BodyState, BodyState),
        settings: &FractureSettings,
        accumulated: f32,
    ) -> Option<Self> {
        let cause = settings.breaks(&impact, &target_state, &projectile_state, accumulated)?;
        let energy = normal_energy_lost(&impact, &target_state, &projectile_state);
        Some(Self { hit, target, projectile, impact, target_state, projectile_state, cause, energy, accumulated })
    }

    /// Adds `candidate` to `breaks`, keeping one break per body: its most energetic hit.
    pub fn keep_strongest(breaks: &mut Vec<Self>, candidate: Self) {
        match breaks.iter_mut().find(|b| b.target == candidate.target) {
            Some(b) if b.energy < candidate.energy => *b = candidate,
            Some(_) => {}
            None => breaks.push(candidate),
        }
    }
}

/// Breaks `mesh` (the body's, its own coordinates, placed by the rigid `to_world`) at `b`: the
/// fracture numbered `number`, or `None` when the pattern misses the body.
///
/// # Errors
/// A `to_world` that scales (bake the scale into the mesh), a mesh that is not closed, or a
/// degenerate placement ([`FractureError`]).
pub(crate) fn break_at<K: Copy>(
    mesh: &TriMesh,
    to_world: Affine3A,
    settings: &FractureSettings,
    b: &BreakingHit<K>,
    number: u64,
) -> Result<Option<BodyFracture<K>>, FractureError> {
    if !is_rigid(to_world) {
        return Err(FractureError::InvalidParameter {
            name: "to_world",
            value: format!("{:?}", to_world.matrix3),
            reason: "a breakable body's mesh → world transform must be rigid: bake its scale into the mesh",
        });
    }
    let to_mesh = to_world.inverse();
    let placement = Placement {
        point: to_mesh.transform_point3(b.impact.point),
        normal: to_mesh.transform_vector3(b.impact.normal),
    };
    let density = density(mesh, settings, &b.target_state);
    let Some(outcome) = settings.break_mesh(mesh, &placement, density)? else { return Ok(None) };
    let record = FractureRecord { pattern: settings.pattern.params(), placement, density, weld_output: false };
    let pieces = outcome
        .pieces
        .into_iter()
        .enumerate()
        .map(|(index, piece)| {
            let (linear_velocity, angular_velocity) = piece.velocity(&b.target_state, to_world);
            BrokenPiece {
                id: PieceId { fracture: number, index: index as u32 },
                mesh: piece.mesh,
                mass: piece.mass,
                cell: piece.cell,
                linear_velocity,
                angular_velocity,
                origins: piece.origins,
            }
        })
        .collect();
    let used = if b.cause == FractureCause::Energy { settings.toughness.unwrap_or(0.0) } else { 0.0 };
    Ok(Some(BodyFracture {
        body: b.target,
        number,
        projectile: b.projectile,
        cause: b.cause,
        energy: b.energy,
        accumulated_dent: b.accumulated,
        record,
        broken_mesh: mesh.clone(),
        rest: outcome.rest,
        rest_origins: outcome.rest_origins,
        rest_mass: outcome.rest_mass,
        pieces,
        projectile_velocity: b.projectile_state.velocity_after_giving_way(used),
    }))
}

/// The density of the broken body, kg/m³: a body that takes impulses has its own (mass over
/// its mesh's volume); a fixed or kinematic one takes the settings'.
fn density(mesh: &TriMesh, settings: &FractureSettings, state: &BodyState) -> f32 {
    let volume = mesh.volume().abs();
    if state.inverse_mass > 0.0 && volume > 0.0 {
        let density = 1.0 / (state.inverse_mass * volume);
        if density.is_finite() && density > 0.0 {
            return density;
        }
    }
    settings.density
}

/// Whether `to_world`'s linear part is a rotation (columns unit and orthogonal within 1e-4).
fn is_rigid(to_world: Affine3A) -> bool {
    let m = Mat3::from(to_world.matrix3);
    let gram = m.transpose() * m;
    let error = (gram - Mat3::IDENTITY).to_cols_array().iter().fold(0.0f32, |a, x| a.max(x.abs()));
    error < 1e-4 && m.determinant() > 0.0
}

impl BodyState {
    /// The (linear, angular) velocity this body carries on with when a break took `used` J of
    /// its kinetic energy (computed from its velocities and inverse mass and inertia); `None`
    /// for a body that takes no impulse.
    pub fn velocity_after_giving_way(&self, used: f32) -> Option<(Vec3, Vec3)> {
        if self.inverse_mass <= 0.0 {
            return None;
        }
        let linear = 0.5 * self.linear_velocity.length_squared() / self.inverse_mass;
        let inertia = self.inverse_inertia.inverse();
        let angular = if inertia.is_finite() {
            0.5 * self.angular_velocity.dot(inertia * self.angular_velocity).max(0.0)
        } else {
            0.0
        };
        let before = linear + angular;
        let keep = if before > 0.0 { ((before - used.max(0.0)) / before).clamp(0.0, 1.0).sqrt() } else { 0.0 };
        Some((self.linear_velocity * keep, self.angular_velocity * keep))
    }
}
