//! Prescored fracture in the simulation loop (paper Figure 3): after a step's dents, every
//! breakable body whose hit passes its toughness (or whose accumulated dent passes its limit)
//! breaks along its pattern placed at the hit ([`dentbend::fracture::break_body`]). Its rest stays
//! the same world body with its mesh replaced (collider and mass properties rebuilt, same
//! index, so joints and names hold; a body the pattern would take whole does not break); each piece becomes a new dynamic body moving as the body's
//! material moved at the piece's centre (v + ω × r). The projectile that broke it gets back its
//! velocity from before the step, less the toughness an energy break used up: the body gave way
//! instead of stopping it.

use glam::{Affine3A, Vec3};
use serde::Serialize;

use crate::sim::{
    BodyDesc, BodyKind, ColliderKind, CollisionEvent, DentRecord, RigidBody, SimError, World, body_state,
};
use dentbend::damage::BreakingHit;
use dentbend::fracture::{DentTally, FractureCause, FractureOutcome, FractureRecord, FractureSettings, Placement};
use dentbend::mesh::{TriMesh, content_hash};
use dentbend::record::FracturePiece;

/// One fracture made during a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FractureEvent {
    /// Step at which it happened (1 = after the first step).
    pub step: u64,
    /// The body that broke (its rest keeps the name).
    pub body: String,
    /// The body that broke it.
    pub projectile: String,
    /// Why: the impact's energy or the accumulated dent.
    pub cause: FractureCause,
    /// The energy the impact removed along the normal, J.
    pub energy: f32,
    /// The body's accumulated dent when it broke, m.
    pub accumulated_dent: f32,
    /// The new bodies, one per piece, in the order they were added to the world.
    pub pieces: Vec<String>,
    /// The fracture as data, in the body's model coordinates (the coordinates its mesh was
    /// given in): [`dentbend::fracture::replay`] on the body's mesh then rebuilds it.
    pub record: FractureRecord,
    /// The fracture as damage data (see [`dentbend::record::FractureRecord`]): how the body's
    /// mesh, its rest and its pieces moved between body and model coordinates.
    #[serde(skip)]
    pub damage: dentbend::record::FractureRecord,
    /// The body's mesh when it broke (its own coordinates, its dents of the step included).
    #[serde(skip)]
    pub mesh_before: std::sync::Arc<TriMesh>,
}

/// Breaks the world's breakable bodies, counting their dents.
#[derive(Debug, Clone, Default)]
pub(crate) struct Fracturer {
    tally: DentTally<usize>,
}

impl Fracturer {
    /// Nothing dented or broken yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Counts the step's `dents`, then breaks every breakable body that a hit of `events` (from
    /// the step numbered `step`, contacts carried by `motions` as for denting) breaks: at most
    /// once per body per step, at its most energetic breaking hit. `velocities_before`: every
    /// body's (linear, angular) velocity before the step.
    ///
    /// # Errors
    /// A fracture or a world edit failed; that body and the world are left as they were (the
    /// fractures before it in the same step stand).
    pub fn process(
        &mut self,
        world: &mut World,
        events: &[CollisionEvent],
        dents: &[DentRecord],
        step: u64,
        (motions, velocities_before): (&[Affine3A], &[(Vec3, Vec3)]),
    ) -> Result<Vec<FractureEvent>, SimError> {
        for record in dents {
            let Some(target) = world.find(&record.target) else { continue };
            let projectile = world.find(&record.projectile).unwrap_or(usize::MAX);
            let progressive = world.bodies()[target].dent.as_ref().is_some_and(|d| d.progressive);
            self.tally.add(target, projectile, record.dent_distance, step, progressive);
        }
        let breaks = self.decide(world, events, motions);
        let mut made = Vec::new();
        for b in breaks {
            if let Some(event) = self.break_one(world, &b, step, velocities_before)? {
                self.tally.forget(b.target);
                made.push(event);
            }
        }
        Ok(made)
    }

    /// Each breakable body's most energetic breaking hit of the step, in body order.
    fn decide(&self, world: &World, events: &[CollisionEvent], motions: &[Affine3A]) -> Vec<BreakingHit<usize>> {
        let bodies = world.bodies();
        let mut breaks = Vec::new();
        for (k, event) in events.iter().enumerate() {
            for (target, projectile) in [(event.a, event.b), (event.b, event.a)] {
                let body = &bodies[target];
                let Some(settings) = &body.fracture else { continue };
                if !body.is_simulated() {
                    continue;
                }
                let motion = motions.get(target).copied().unwrap_or(Affine3A::IDENTITY);
                let Some(impact) = event.impact_on(target, motion) else { continue };
                let states = (body_state(body), body_state(&bodies[projectile]));
                let accumulated = self.tally.total(target);
                if let Some(b) = BreakingHit::judge(k, (target, projectile), impact, states, settings, accumulated) {
                    BreakingHit::keep_strongest(&mut breaks, b);
                }
            }
        }
        breaks.sort_by_key(|b| b.target);
        breaks
    }

    /// Breaks one body; `None` when the pattern missed it.
    fn break_one(
        &mut self,
        world: &mut World,
        b: &BreakingHit<usize>,
        step: u64,
        velocities_before: &[(Vec3, Vec3)],
    ) -> Result<Option<FractureEvent>, SimError> {
        let body = &world.bodies()[b.target];
        let Some(settings) = body.fracture.clone() else { return Ok(None) };
        let fail = |error| SimError::Fracture { body: body.name.clone(), error };
        let to_model = body.model_transform().inverse();
        let mesh_before = body.mesh.clone();
        let mut mesh = body.mesh().clone();
        // Body coordinates → model coordinates (the centre of mass is at the body origin).
        let to_model_shift = -body.model_offset;
        mesh.transform(Affine3A::from_translation(to_model_shift))?;
        let placement = Placement {
            point: to_model.transform_point3(b.impact.point),
            normal: to_model.transform_vector3(b.impact.normal),
        };
        let density = match body.kind {
            BodyKind::Dynamic => body.mass / mesh.volume().abs(),
            _ => settings.density,
        };
        let Some(outcome) = settings.break_mesh(&mesh, &placement, density).map_err(fail)? else {
            return Ok(None);
        };
        if outcome.rest.is_none() {
            // The world cannot remove a body: one the pattern would take whole stays whole.
            log::debug!("{}: the fracture pattern holds the whole body; it does not break", body.name);
            return Ok(None);
        }
        let record = FractureRecord { pattern: settings.pattern.params(), placement, density, weld_output: false };
        let projectile = world.bodies()[b.projectile].name.clone();
        let undo = world.record_edit(&[b.target]);
        match apply(world, b.target, outcome, &settings, density) {
            Ok(made) => {
                give_way(world, b, &settings, velocities_before);
                let rest = &world.bodies()[b.target];
                let damage = dentbend::record::FractureRecord {
                    frame: step,
                    fracture: record,
                    to_model: to_model_shift,
                    rest_shift: rest.model_offset,
                    pieces: made.clone(),
                    after: content_hash(rest.mesh()),
                };
                let pieces = made.into_iter().map(|piece| piece.name).collect();
                let event = FractureEvent {
                    step,
                    body: world.bodies()[b.target].name.clone(),
                    projectile,
                    cause: b.cause,
                    energy: b.energy,
                    accumulated_dent: b.accumulated,
                    pieces,
                    record,
                    damage,
                    mesh_before,
                };
                Ok(Some(event))
            }
            Err(e) => {
                world.undo_edit(undo);
                Err(e)
            }
        }
    }
}

/// The world edits of a fracture of body `index`: its rest in place, a body per piece. Returns
/// each piece that became a body (name, index in the outcome, shift to its body coordinates).
fn apply(
    world: &mut World,
    index: usize,
    outcome: FractureOutcome,
    settings: &FractureSettings,
    density: f32,
) -> Result<Vec<FracturePiece>, SimError> {
    let body = world.bodies()[index].clone();
    let model = body.model_transform();
    let (_, orientation, origin) = model.to_scale_rotation_translation();
    let shape = |mesh, name: String, kind, collider| BodyDesc {
        kind,
        position: origin,
        orientation,
        density,
        collider,
        surface: body.surface,
        color: body.color,
        ..BodyDesc::new(name, mesh)
    };
    if let Some(rest) = outcome.rest {
        let mut desc = shape(rest, body.name.clone(), body.kind, body.collider_kind);
        desc.dent = body.dent.clone();
        desc.fracture = Some(settings.clone());
        if let (BodyKind::Dynamic, Some(mass)) = (body.kind, outcome.rest_mass) {
            desc.linear_velocity = body.velocity_at(model.transform_point3(mass.center));
            desc.angular_velocity = body.angular_velocity;
        } else if body.kind == BodyKind::Kinematic {
            (desc.linear_velocity, desc.angular_velocity) = (body.linear_velocity, body.angular_velocity);
        }
        world.rebuild_body(index, desc)?;
    }
    let mut names = Vec::with_capacity(outcome.pieces.len());
    let mut serial = 0usize;
    for (number, piece) in outcome.pieces.into_iter().enumerate() {
        let name = loop {
            let name = format!("{}/piece{serial}", body.name);
            serial += 1;
            if world.find(&name).is_none() {
                break name;
            }
        };
        let centre = model.transform_point3(piece.mass.center);
        let mut desc = shape(piece.mesh, name.clone(), BodyKind::Dynamic, ColliderKind::ConvexHull);
        desc.linear_velocity = body.velocity_at(centre);
        desc.angular_velocity = body.angular_velocity;
        desc.mass_properties = Some(piece.mass);
        match world.add(desc) {
            Ok(k) => {
                let (shift, hash) = (world.bodies()[k].model_offset, content_hash(world.bodies()[k].mesh()));
                names.push(FracturePiece { name, index: number as u32, shift, hash });
            }
            // A sliver whose hull or inertia cannot be built is left out (its volume is lost).
            Err(SimError::BadShape { reason, .. }) => log::debug!("{name}: left out: {reason}"),
            Err(e) => return Err(e),
        }
    }
    Ok(names)
}

/// The projectile of break `b` gets back its velocity from before the step, its kinetic energy
/// less the toughness an energy break used up (a dent break: the dents took theirs).
fn give_way(
    world: &mut World,
    b: &BreakingHit<usize>,
    settings: &FractureSettings,
    velocities_before: &[(Vec3, Vec3)],
) {
    let Some(&(linear_velocity, angular_velocity)) = velocities_before.get(b.projectile) else { return };
    let projectile: &mut RigidBody = &mut world.bodies_mut()[b.projectile];
    if projectile.kind != BodyKind::Dynamic || projectile.is_condensed() {
        return;
    }
    let before = dentbend::dent::BodyState { linear_velocity, angular_velocity, ..body_state(projectile) };
    let used = if b.cause == FractureCause::Energy { settings.toughness.unwrap_or(0.0) } else { 0.0 };
    if let Some((linear, angular)) = before.velocity_after_giving_way(used) {
        projectile.linear_velocity = linear;
        projectile.angular_velocity = angular;
    }
}
