//! One call per step: record the bodies' states, step Rapier, split and bend the bendable
//! bodies, dent the dentable colliders — timing each part.

use std::time::Instant;

use dentbend::damage::{AppliedDent, CpuBackend, DentBackend};
use rapier3d::prelude::{ColliderHandle, EventHandler, PhysicsHooks};

use crate::{AdapterError, Bendable, BodyStates, BrokenCollider, Contact, Dentables, ImpactReader, PhysicsWorld};

/// What one [`Adapter::step`] did, with wall-clock timings (s).
#[derive(Debug, Clone, Default)]
pub struct StepReport {
    /// Impacts reported by Rapier this step.
    pub contacts: Vec<Contact>,
    /// Dents made.
    pub dents: Vec<AppliedDent<ColliderHandle>>,
    /// Colliders refitted, with the vertices that moved, ascending (a bendable body's pieces:
    /// its rest mesh's).
    pub refitted: Vec<(ColliderHandle, Vec<u32>)>,
    /// Contacts left out because a collider or body they name was removed after the step.
    pub skipped: Vec<Contact>,
    /// Dentable or projectile colliders no longer in the collider set, forgotten.
    pub forgotten: Vec<ColliderHandle>,
    /// Breakable colliders that broke, with the bodies made of their pieces (a collider the
    /// pattern took whole is removed, with its body when that had no other collider).
    pub fractures: Vec<BrokenCollider>,
    /// Joints made by dynamic articulation.
    pub joints_created: usize,
    /// Plastic joints that yielded.
    pub plastic_bends: usize,
    /// Rapier's `PhysicsPipeline::step`, s.
    pub physics_seconds: f64,
    /// Dents: the body states recorded before the step, contact extraction and checks, dent
    /// decisions, maps, meshes, damage records, s.
    pub dent_seconds: f64,
    /// Collider refits, s.
    pub collider_seconds: f64,
    /// Splits and joint rules, s.
    pub bend_seconds: f64,
}

/// Dentable colliders and bendable bodies of one [`PhysicsWorld`], and where dents run.
pub struct Adapter {
    /// The dentable colliders.
    pub dentables: Dentables,
    /// The bendable bodies.
    pub bendables: Vec<Bendable>,
    reader: ImpactReader,
    /// The last step's body states, kept for their memory.
    states: BodyStates,
    backend: Box<dyn DentBackend<ColliderHandle>>,
}

impl Default for Adapter {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for Adapter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Adapter").field("dentables", &self.dentables).field("bendables", &self.bendables).finish()
    }
}

impl Adapter {
    /// Whether collider `handle` is one the adapter dents, dents with or bends.
    fn knows(&self, handle: ColliderHandle) -> bool {
        self.dentables.knows(handle) || self.bendables.iter().any(|b| b.owns(handle))
    }

    /// Nothing dentable or bendable yet; dents on all CPU cores.
    pub fn new() -> Self {
        Self::with_backend(Box::new(CpuBackend))
    }

    /// As [`new`](Self::new), dents on `backend` (the GPU one, or your own).
    pub fn with_backend(backend: Box<dyn DentBackend<ColliderHandle>>) -> Self {
        let (reader, states) = (ImpactReader::new(), BodyStates::default());
        Self { dentables: Dentables::new(), bendables: Vec::new(), reader, states, backend }
    }

    /// Steps `world` once, then splits and bends the bendable bodies and dents the dentable
    /// colliders from the step's impacts (read from the narrow phase: the colliders' event
    /// settings play no part). [`step_with`](Self::step_with) passes the game's hooks and
    /// event handler to Rapier.
    ///
    /// # Errors
    /// A bad contact, an unknown or removed body or collider: Rapier's step has run, the adapter
    /// changed no mesh, collider, body or joint (contacts and the bodies they name are checked
    /// before anything else). A dent that fails on the backend (a lost GPU) after the bendable
    /// bodies were split and bent leaves the meshes and colliders unchanged.
    pub fn step(&mut self, world: &mut PhysicsWorld) -> Result<StepReport, AdapterError> {
        self.step_with(world, &(), &())
    }

    /// As [`step`](Self::step), Rapier's step running the game's `hooks` (contact filters and
    /// modifiers) and reporting to the game's `events` handler, as it would without the adapter.
    ///
    /// # Errors
    /// As [`step`](Self::step).
    pub fn step_with(
        &mut self,
        world: &mut PhysicsWorld,
        hooks: &dyn PhysicsHooks,
        events: &dyn EventHandler,
    ) -> Result<StepReport, AdapterError> {
        let start = Instant::now();
        let mut states = std::mem::take(&mut self.states);
        states.record_again(&world.bodies, &world.colliders);
        let recorded = start.elapsed().as_secs_f64();
        let start = Instant::now();
        world.step_with(hooks, events);
        let physics_seconds = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let known =
            self.dentables.known().chain(self.bendables.iter().flat_map(|b| b.pieces().iter().map(|p| p.collider)));
        let contacts = self.reader.read(&world.narrow_phase, known, &states, &world.bodies, &world.colliders);
        let extraction = start.elapsed().as_secs_f64();
        let report = self.after_step(world, &states, contacts, physics_seconds);
        self.states = states;
        let mut report = report?;
        report.dent_seconds += recorded + extraction;
        Ok(report)
    }

    /// The adapter's half of a step, for callers who step Rapier themselves: `states` recorded
    /// before the step, `contacts` its impacts ([`ImpactReader::read`], or
    /// [`ImpactCollector::take_contacts`](crate::ImpactCollector::take_contacts) from contact
    /// force events).
    ///
    /// # Errors
    /// As [`step`](Self::step).
    pub fn after_step(
        &mut self,
        world: &mut PhysicsWorld,
        states: &BodyStates,
        contacts: Vec<Contact>,
        physics_seconds: f64,
    ) -> Result<StepReport, AdapterError> {
        // Every contact and every body it names is checked before anything changes; contacts
        // naming a collider or body removed since the step are left out (and reported).
        let checks = Instant::now();
        for c in &contacts {
            c.validate()?;
            for handle in [c.collider1, c.collider2] {
                let parent = match states.collider(handle, &world.bodies, &world.colliders) {
                    Ok(collider) => collider.parent(),
                    Err(AdapterError::RemovedBody(_) | AdapterError::RemovedCollider(_)) => None,
                    Err(AdapterError::UnknownCollider(_)) if self.knows(handle) => None,
                    Err(e) => return Err(e),
                };
                match parent.map(|body| states.body(body, &world.bodies)) {
                    Some(Err(AdapterError::RemovedBody(_))) | None | Some(Ok(_)) => {}
                    Some(Err(e)) => return Err(e),
                }
            }
        }
        let (contacts, skipped) =
            crate::dentable::live_contacts(&contacts, states, &world.bodies, &world.colliders, |h| self.knows(h));
        let checked = checks.elapsed().as_secs_f64();
        let start = Instant::now();
        let mut report = StepReport { physics_seconds, ..StepReport::default() };
        let mut removed = Vec::new();
        for b in &mut self.bendables {
            let r = b.after_step(world, states, &contacts)?;
            report.joints_created += r.joints_created;
            report.plastic_bends += r.plastic_bends;
            removed.extend(r.removed_colliders);
        }
        report.bend_seconds = start.elapsed().as_secs_f64();
        let live: Vec<Contact> = contacts
            .iter()
            .filter(|c| !removed.contains(&c.collider1) && !removed.contains(&c.collider2))
            .copied()
            .collect();
        let dents =
            self.dentables.process(&live, states, &mut world.bodies, &mut world.colliders, self.backend.as_mut())?;
        report.dents = dents.dents;
        report.refitted = dents.refitted;
        report.skipped = skipped;
        report.forgotten = dents.forgotten;
        for broken in dents.fractures.iter().filter(|b| b.whole) {
            remove_whole(world, broken.collider);
        }
        report.fractures = dents.fractures;
        report.dent_seconds = dents.dent_seconds;
        report.collider_seconds = dents.collider_seconds;
        let start = Instant::now();
        let Self { bendables, dentables, backend, .. } = self;
        let mut bend_colliders = 0.0;
        for b in bendables.iter_mut() {
            let r = b.dent_parent(world, states, &live, |h| dentables.surface(h), backend.as_mut())?;
            report.dents.extend(r.dents);
            report.refitted.extend(r.refitted.into_iter().map(|c| (c, r.moved.clone())));
            bend_colliders += r.collider_seconds;
        }
        report.dent_seconds += start.elapsed().as_secs_f64() - bend_colliders + checked;
        report.collider_seconds += bend_colliders;
        report.contacts = contacts;
        Ok(report)
    }
}

/// Removes `collider`, which a fracture took whole, and its body when it has no other collider.
fn remove_whole(world: &mut PhysicsWorld, collider: ColliderHandle) {
    let parent = world.colliders.get(collider).and_then(|c| c.parent());
    world.colliders.remove(collider, &mut world.islands, &mut world.bodies, &mut world.soft_bodies, true);
    if let Some(body) = parent
        && world.bodies.get(body).is_some_and(|b| b.colliders().is_empty())
    {
        world.remove_body(body);
    }
}
