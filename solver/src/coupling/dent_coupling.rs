//! Denting coupled with bending (paper §4, last paragraph; ARCHITECTURE.md §4): each step, a hit on a
//! sub-body of a dentable bending body dents the whole body's skinned mesh, mapped back to its
//! rest mesh ([`ArticulatedBody::dent_in_pose`](super::ArticulatedBody::dent_in_pose)), and the
//! sub-bodies are refitted.
//!
//! Both bodies of a pair dent from the undented surfaces (Jacobi), as plain pairs do: the step's
//! bending dents are computed first ([`BendDenter::prepare`]), plain bodies are then dented by
//! the [`Denter`] with each sub-body denting as the whole undented skinned mesh, and the bending
//! dents are applied last ([`StagedBendDents::commit`]).

use glam::Affine3A;

use super::contact_merge::merge_contacts;
use super::{Bending, PoseDent};
use crate::sim::{
    CollisionEvent, DecidedDent, DentRecord, Denter, RigidBody, SimError, StepContext, SurfaceOverride, World,
    body_state,
};
use dentbend::dent::{Surface, decide_dent_distance};
use dentbend::mesh::TriMesh;

/// Progressive denting state of one (bending body, projectile) contact.
#[derive(Debug, Clone)]
struct Progress {
    body: usize,
    projectile: usize,
    /// Rest mesh before the contact's first dent.
    pre_dent: TriMesh,
    accumulated: f32,
    last_step: u64,
}

/// One dent applied to a bending body.
#[derive(Debug, Clone)]
struct Made {
    dent: DecidedDent,
    /// Dent distance used, m (a progressive dent's accumulated one).
    distance: f32,
    /// The projectile's name (a bending body's for its sub-bodies).
    projectile: String,
}

impl Made {
    /// `dent` made with `distance` m, its projectile named as `context` names it.
    fn of(dent: DecidedDent, distance: f32, world: &World, context: &StepContext<'_>) -> Self {
        Self { dent, distance, projectile: context.name(world, dent.projectile).to_owned() }
    }
}

/// Dents the bending bodies hit in each step's collisions, keeping progressive dents' state.
#[derive(Debug, Clone, Default)]
pub struct BendDenter {
    progress: Vec<Progress>,
}

/// One step's dents of bending bodies, computed but not applied.
#[derive(Debug)]
pub struct StagedBendDents {
    step: u64,
    /// The step's events, each projectile's contacts with one bending body merged.
    events: Vec<CollisionEvent>,
    /// Name, sub-body world indices and undented skinned mesh (world) of every bending body hit.
    skinned: Vec<(String, Vec<usize>, TriMesh)>,
    /// Per dented bending body: its index in [`Bending::bodies`], the dent and what made it.
    dents: Vec<(usize, PoseDent, Vec<Made>)>,
    progress: Vec<Progress>,
}

impl BendDenter {
    /// No progressive dents under way.
    pub fn new() -> Self {
        Self::default()
    }

    /// Computes the dents that `events` (from the step numbered `step`) make on `bending`'s
    /// dentable bodies in `world`'s pose, changing nothing. A projectile's contacts with several
    /// sub-bodies of one bending body are first merged into one (`merge_contacts`). A hit
    /// dents a bending body when its sub-body is one side of the event and the other side is
    /// not one of its own sub-bodies; whether and how deep is decided as for a plain body
    /// (`decide_dent`), the projectile denting with its undented surface (another bending
    /// body's: its whole skinned mesh). All of a body's dents of the step are applied on its one
    /// skinned mesh; progressive settings rebuild a contact's dent from its pre-dent rest mesh
    /// with the accumulated distance. `motions`: each world body's rigid motion during the step
    /// (see [`StepContext::motions`]; `step_motions`), empty when nothing moved.
    ///
    /// # Errors
    /// As [`ArticulatedBody::dent_in_pose`](super::ArticulatedBody::dent_in_pose) and
    /// `decide_dent`.
    pub fn prepare(
        &self,
        bending: &Bending,
        world: &World,
        events: &[CollisionEvent],
        step: u64,
        motions: &[Affine3A],
    ) -> Result<StagedBendDents, SimError> {
        let owners = bending.owners(world.bodies().len());
        let owner = |index: usize| owners.get(index).copied().flatten().map(|(k, _)| k);
        let events = merge_contacts(owner, events);
        let bodies = &bending.bodies;
        let mut progress: Vec<Progress> = self.progress.iter().filter(|p| p.last_step + 1 >= step).cloned().collect();
        let dentable =
            |index: usize| owner(index).map_or(world.bodies()[index].dent.is_some(), |k| bodies[k].dent.is_some());
        // Events between two bodies other than two sub-bodies of one bending body.
        let cross: Vec<&CollisionEvent> =
            events.iter().filter(|e| owner(e.a).is_none() || owner(e.a) != owner(e.b)).collect();
        // A bending body's skinned mesh is needed where it dents or dents something.
        let mut skin: Vec<usize> = cross
            .iter()
            .filter(|e| dentable(e.a) || dentable(e.b))
            .flat_map(|e| [owner(e.a), owner(e.b)])
            .flatten()
            .collect();
        skin.sort_unstable();
        skin.dedup();
        let skinned = skin
            .iter()
            .map(|&k| Ok((bodies[k].name.clone(), bodies[k].bodies.clone(), bodies[k].skinned_mesh(world)?)))
            .collect::<Result<Vec<_>, SimError>>()?;
        let surfaces = surfaces_of(&skinned);
        let context = StepContext { surfaces: &surfaces, motions };
        let mut decided: Vec<Vec<DecidedDent>> = vec![Vec::new(); bodies.len()];
        for event in &cross {
            for (target, projectile) in [(event.a, event.b), (event.b, event.a)] {
                let Some(k) = owner(target) else { continue };
                let Some(settings) = &bodies[k].dent else { continue };
                let Some(impact) = event.impact_on(target, context.motion(target)) else { continue };
                let states = (body_state(&world.bodies()[target]), body_state(&world.bodies()[projectile]));
                let surface = context.surface(world, projectile);
                let distance = decide_dent_distance(settings, &impact, &states.0, &states.1, &surface)
                    .map_err(|error| SimError::Dent { body: bodies[k].name.clone(), error })?;
                decided[k].extend(distance.map(|dent_distance| DecidedDent {
                    target,
                    projectile,
                    impact,
                    dent_distance,
                }));
            }
        }
        let mut dents = Vec::new();
        for (k, list) in decided.into_iter().enumerate().filter(|(_, l)| !l.is_empty()) {
            let staged = match bodies[k].dent.as_ref().is_some_and(|s| s.progressive) {
                false => Some(stage_plain(bending, k, &list, world, &context)?),
                true => stage_progressive(bending, k, &list, world, &context, (&mut progress, step))?,
            };
            dents.extend(staged.map(|(pose, made)| (k, pose, made)));
        }
        drop(surfaces);
        Ok(StagedBendDents { step, events, skinned, dents, progress })
    }

    /// One step's denting of bending bodies alone: [`prepare`](Self::prepare), then
    /// [`StagedBendDents::commit`]. (Plain bodies are not dented; see [`dent_step`] for both.)
    ///
    /// # Errors
    /// As those two; nothing changes then.
    pub fn process(
        &mut self,
        bending: &mut Bending,
        world: &mut World,
        events: &[CollisionEvent],
        step: u64,
        motions: &[Affine3A],
    ) -> Result<Vec<DentRecord>, SimError> {
        self.prepare(bending, world, events, step, motions)?.commit(self, bending, world)
    }
}

impl StagedBendDents {
    /// The surface each sub-body of a bending body hit this step dents others with: the whole
    /// undented skinned mesh, world coordinates (for [`Denter::process_with`]).
    pub fn surfaces(&self) -> Vec<SurfaceOverride<'_>> {
        surfaces_of(&self.skinned)
    }

    /// The step's events as denting sees them: the contacts of a pair of which one is a bending
    /// body merged into one (`merge_contacts`), so a ball landing on a joint dents once.
    pub fn events(&self) -> &[CollisionEvent] {
        &self.events
    }

    /// Applies the dents ([`ArticulatedBody::apply_pose_dent`](super::ArticulatedBody::apply_pose_dent)),
    /// keeps the progressive state in `denter`, moves dynamic projectiles into the dents when the
    /// settings ask, and returns the dents' records (named after the bending bodies).
    ///
    /// # Errors
    /// A sub-body's hull could not be built; no bending body, projectile or state changes then.
    pub fn commit(
        self,
        denter: &mut BendDenter,
        bending: &mut Bending,
        world: &mut World,
    ) -> Result<Vec<DentRecord>, SimError> {
        for (_, pose, _) in &self.dents {
            pose.uncondense_refitted(world)?;
        }
        let mut refitted: Vec<(usize, RigidBody)> = Vec::new();
        for (k, pose, _) in &self.dents {
            refitted.extend(bending.bodies[*k].refit_sub_bodies(world, pose)?);
        }
        for (index, body) in refitted {
            world.bodies_mut()[index] = body;
        }
        denter.progress = self.progress;
        let mut records = Vec::new();
        for (k, pose, made) in self.dents {
            let body = &mut bending.bodies[k];
            body.set_rest_mesh(pose.rest_mesh)?;
            for m in made {
                records.push(m.dent.record(&body.name, &m.projectile, m.distance, self.step));
                if let Some(settings) = &body.dent {
                    // By the step's own distance, as the Denter moves plain bodies' projectiles.
                    m.dent.move_projectile(world, settings);
                }
            }
        }
        Ok(records)
    }
}

/// Bending body `k`'s dents `list` (not empty), all on its rest mesh skinned once.
fn stage_plain(
    bending: &Bending,
    k: usize,
    list: &[DecidedDent],
    world: &World,
    context: &StepContext<'_>,
) -> Result<(PoseDent, Vec<Made>), SimError> {
    let body = &bending.bodies[k];
    let pairs: Vec<_> = list.iter().map(|&d| (d, context.surface(world, d.projectile))).collect();
    let pose = body.dent_in_pose(world, body.rig.rest(), &pairs)?;
    let made = pose.applied.iter().map(|&i| Made::of(list[i], list[i].dent_distance, world, context)).collect();
    Ok((pose, made))
}

/// Bending body `k`'s progressive dents `list`: each contact's dent rebuilt from its pre-dent
/// rest mesh with its accumulated distance, one after the other, as the [`Denter`] does for
/// plain bodies (the last one's rest mesh stands). `progress`: the contacts' states and the step.
fn stage_progressive(
    bending: &Bending,
    k: usize,
    list: &[DecidedDent],
    world: &World,
    context: &StepContext<'_>,
    (progress, step): (&mut Vec<Progress>, u64),
) -> Result<Option<(PoseDent, Vec<Made>)>, SimError> {
    let body = &bending.bodies[k];
    let cap = body.dent.as_ref().map_or(f32::INFINITY, |s| s.material.cap);
    let mut current: Option<PoseDent> = None;
    let mut made = Vec::new();
    for &d in list {
        let rest = current.as_ref().map_or(body.rig.rest(), |c| &c.rest_mesh);
        let index = match progress.iter().position(|p| p.body == k && p.projectile == d.projectile) {
            Some(index) => index,
            None => {
                let (pre_dent, accumulated) = (rest.clone(), 0.0);
                progress.push(Progress { body: k, projectile: d.projectile, pre_dent, accumulated, last_step: step });
                progress.len() - 1
            }
        };
        let state = &mut progress[index];
        let distance = (state.accumulated + d.dent_distance).min(cap);
        let deeper = DecidedDent { dent_distance: distance, ..d };
        let surface = context.surface(world, d.projectile);
        let pose = body.dent_in_pose(world, &state.pre_dent, &[(deeper, surface)])?;
        if pose.applied.is_empty() {
            continue;
        }
        (state.accumulated, state.last_step) = (distance, step);
        made.push(Made::of(d, distance, world, context));
        current = Some(pose);
    }
    Ok(current.map(|pose| (pose, made)))
}

/// Every listed sub-body denting as its body's skinned mesh (world coordinates), under its
/// body's name.
fn surfaces_of(skinned: &[(String, Vec<usize>, TriMesh)]) -> Vec<SurfaceOverride<'_>> {
    skinned
        .iter()
        .flat_map(|(name, indices, mesh)| {
            let surface = Surface { mesh, to_world: Affine3A::IDENTITY };
            indices.iter().map(move |&body| SurfaceOverride { body, surface, name })
        })
        .collect()
}

/// Each world body's rigid motion during the step numbered `step` (world then → world now): its
/// model transform now after the inverse of `before[index]`, its model transform before the
/// step. A body added during the step by a split (dynamic articulation) started at the split
/// bone's transform; a body with neither is taken as still.
pub(crate) fn step_motions(bending: &Bending, world: &World, before: &[Affine3A], step: u64) -> Vec<Affine3A> {
    let mut then: Vec<Option<Affine3A>> = before.iter().copied().map(Some).collect();
    then.resize(world.bodies().len(), None);
    for made in bending.joints().iter().filter(|j| j.frame == step) {
        if let Some(joint) = world.joints().get(made.joint)
            && let (Some(&Some(old)), Some(None)) = (then.get(joint.a()), then.get(joint.b()))
        {
            then[joint.b()] = Some(old);
        }
    }
    world
        .bodies()
        .iter()
        .zip(then)
        .map(|(body, then)| then.map_or(Affine3A::IDENTITY, |t| body.model_transform() * t.inverse()))
        .collect()
}

/// One step's denting of a world with bending bodies (paper Algorithm 1 lines 13–21 with §4's
/// coupling): bending dents computed from the undented state, plain dents made by `denter` with
/// sub-bodies denting as their bodies' undented skinned meshes, then the bending dents applied;
/// every contact carried with its target's motion during the step (`before`: every body's model
/// transform before it; see `step_motions`). Returns the plain dents' records, then the
/// bending bodies'.
///
/// # Errors
/// As [`BendDenter::prepare`], [`Denter::process_with`] and [`StagedBendDents::commit`]; the
/// bending bodies keep their meshes when any fails.
pub fn dent_step(
    bend_denter: &mut BendDenter,
    denter: &mut Denter,
    bending: &mut Bending,
    world: &mut World,
    events: &[CollisionEvent],
    step: u64,
    before: &[Affine3A],
) -> Result<Vec<DentRecord>, SimError> {
    let motions = step_motions(bending, world, before, step);
    let staged = bend_denter.prepare(bending, world, events, step, &motions)?;
    let surfaces = staged.surfaces();
    let context = StepContext { surfaces: &surfaces, motions: &motions };
    let mut records = denter.process_with(world, staged.events(), step, &context)?;
    drop(surfaces);
    records.extend(staged.commit(bend_denter, bending, world)?);
    Ok(records)
}
