//! The per-step bending driver (paper Algorithm 2): steps a [`World`] holding bending bodies,
//! with the dummy step of dynamic articulation (find the step's collisions, split where fast hits
//! land, find them again, solve), and records the joints made and the plastic bends.

use std::time::Instant;

use glam::Vec3;
use serde::Serialize;

use super::condensation::Condenser;
use super::{ArticulatedBody, BendableDesc, CondenseSettings};
use crate::sim::{CollisionEvent, SimError, StepReport, World};
use dentbend::mesh::TriMesh;

/// A joint made by dynamic articulation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointRecord {
    /// Step during which it was made (1 = the first).
    pub frame: u64,
    /// The bending body's name.
    pub body: String,
    /// Where it was made, world, m.
    pub position: Vec3,
    /// Where it is in the body's rest (model) frame, m.
    pub rest_position: Vec3,
    /// Its index in [`World::joints`].
    pub joint: usize,
    /// Time the split took (weights of the split bone, sub-bodies, world edits), ms.
    pub split_ms: f64,
}

/// A plastic bend of a joint during a step (from [`StepReport::bends`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BendRecord {
    /// The step (1 = the first).
    pub frame: u64,
    /// Index of the joint in [`World::joints`].
    pub joint: usize,
    /// Angle the joint's target turned by during the step, rad.
    pub angle: f32,
}

/// Every bending body of a world, and what bending did so far.
#[derive(Debug, Clone, Default)]
pub struct Bending {
    pub(super) bodies: Vec<ArticulatedBody>,
    joints: Vec<JointRecord>,
    bends: Vec<BendRecord>,
    condenser: Option<Condenser>,
}

impl Bending {
    /// No bending bodies.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a bending body to `world` (see [`ArticulatedBody::new`]; a copy of a body added
    /// before, same mesh, skeleton, weights and density, reuses its rest state); returns its
    /// index here.
    ///
    /// # Errors
    /// As [`ArticulatedBody::new`]; also a name already used by another bending body.
    pub fn add(&mut self, world: &mut World, desc: BendableDesc) -> Result<usize, SimError> {
        if self.bodies.iter().any(|b| b.name() == desc.name) || world.find(&desc.name).is_some() {
            return Err(SimError::Invalid {
                what: "bendable body name".into(),
                value: format!("{:?}", desc.name),
                reason: "is already taken",
            });
        }
        // Copies of one body share its rest state (see `ArticulatedBody::new_like`).
        let template = self.bodies.iter().rev().find(|b| b.rest_mesh().vertex_count() == desc.mesh.vertex_count());
        let body = match template {
            Some(template) => ArticulatedBody::new_like(world, desc, template)?,
            None => ArticulatedBody::new(world, desc)?,
        };
        self.bodies.push(body);
        Ok(self.bodies.len() - 1)
    }

    /// Turns condensation on (paper §4.2): from then on every group of bodies joined by quiet
    /// joints in the world is simulated as one rigid cluster, dissolved for a step by a hit
    /// that could bend it (see [`CondenseSettings`]).
    ///
    /// # Errors
    /// [`SimError::Invalid`] for bad settings.
    pub fn condense(&mut self, settings: CondenseSettings) -> Result<(), SimError> {
        settings.validate()?;
        self.condenser = Some(Condenser::new(settings));
        Ok(())
    }

    /// The condensation settings, `None` when condensation is off.
    pub fn condensation(&self) -> Option<CondenseSettings> {
        self.condenser.as_ref().map(|c| c.settings)
    }

    /// The bending bodies.
    pub fn bodies(&self) -> &[ArticulatedBody] {
        &self.bodies
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// The bending body called `name`.
    pub fn find(&self, name: &str) -> Option<&ArticulatedBody> {
        self.bodies.iter().find(|b| b.name() == name)
    }

    /// Whether world body `index` is a sub-body of a bending body (not to be drawn or written).
    pub fn is_sub_body(&self, index: usize) -> bool {
        self.bodies.iter().any(|b| b.bone_of(index).is_some())
    }

    /// Joints made by dynamic articulation so far, in order.
    pub fn joints(&self) -> &[JointRecord] {
        &self.joints
    }

    /// Plastic bends so far, in order.
    pub fn bends(&self) -> &[BendRecord] {
        &self.bends
    }

    /// Every bending body's skinned mesh now, world coordinates: (name, mesh, colour).
    ///
    /// # Errors
    /// As [`ArticulatedBody::skinned_mesh`].
    pub fn skinned_meshes(&self, world: &World) -> Result<Vec<(String, TriMesh, [f32; 3])>, SimError> {
        self.bodies.iter().map(|b| Ok((b.name().to_owned(), b.skinned_mesh(world)?, b.color()))).collect()
    }

    /// One step of `world`. With dynamic articulation or condensation (Algorithm 2 steps 4–13):
    /// the step's collisions are found first, with their closing speeds before any impulse
    /// (Algorithm 2's dummy step, without solving it). If one involving a sub-body of such a body
    /// closes faster than its threshold, or hits a cluster faster than its wake speed, the
    /// clusters hit are dissolved, each body is split at its fastest such hit
    /// ([`ArticulatedBody::split_at`]), and the collisions are found again on the edited world.
    /// Then the step is solved, and quiet groups are condensed. Records the joints made and the
    /// plastic bends of the step. Without bending bodies or condensation this is [`World::step`].
    ///
    /// # Errors
    /// A split or a wake failed (a bug). The body that failed is unchanged; earlier edits of the
    /// step stand and the world has not stepped.
    pub fn step(&mut self, world: &mut World) -> Result<StepReport, SimError> {
        let dynamic = self.bodies.iter().any(|b| b.dynamic().is_some());
        let clustered = self.condenser.is_some() && !world.clusters().is_empty();
        let mut detected = world.detect();
        if dynamic || clustered {
            let impacts = world.impacts(&detected);
            let owners = self.owners(world.bodies().len());
            let hits = self.fast_hits(&impacts, &owners);
            let woken = self.condenser.as_ref().map_or_else(Vec::new, |c| {
                c.hit_clusters(world, &impacts, |body| {
                    owners[body].and_then(|(k, _)| self.bodies[k].dynamic().map(|d| d.speed_threshold))
                })
            });
            if !hits.is_empty() || !woken.is_empty() {
                if let Some(condenser) = self.condenser.as_mut() {
                    condenser.wake(world, &woken)?;
                }
                self.split(world, hits)?;
                detected = world.redetect(detected);
            }
        }
        let report = world.advance(detected);
        let frame = world.steps();
        self.bends.extend(report.bends.iter().map(|b| BendRecord { frame, joint: b.joint, angle: b.angle }));
        if let Some(condenser) = self.condenser.as_mut() {
            condenser.update(world, &report)?;
        }
        Ok(report)
    }

    /// Splits each bending body at its hit (before the step is solved) and records the joints
    /// made.
    fn split(&mut self, world: &mut World, hits: Vec<(usize, usize, Vec3)>) -> Result<(), SimError> {
        let frame = world.steps() + 1;
        for (body, index, point) in hits {
            if let Some(cluster) = world.cluster_of(index) {
                world.uncondense(cluster)?;
            }
            let started = Instant::now();
            let outcome = self.bodies[body].split_at(world, index, point)?;
            if let Some(o) = outcome {
                let name = self.bodies[body].name().to_owned();
                log::info!("{name}: joint {} at {:?} (step {frame})", o.joint, o.world_point);
                self.joints.push(JointRecord {
                    frame,
                    body: name,
                    position: o.world_point,
                    rest_position: o.rest_point,
                    joint: o.joint,
                    split_ms: started.elapsed().as_secs_f64() * 1e3,
                });
            }
        }
        Ok(())
    }

    /// Per world body (of `count`), the bending body and bone it simulates: one pass over the
    /// bones, where [`is_sub_body`](Self::is_sub_body) per body would search them all each time.
    pub fn owners(&self, count: usize) -> Vec<Option<(usize, usize)>> {
        let mut owners = vec![None; count];
        for (k, body) in self.bodies.iter().enumerate() {
            for (bone, &index) in body.body_indices().iter().enumerate() {
                if let Some(slot) = owners.get_mut(index) {
                    *slot = Some((k, bone));
                }
            }
        }
        owners
    }

    /// Per bending body with dynamic articulation, the fastest hit on one of its sub-bodies above
    /// its threshold: (body, world body index hit, contact point). `owners` as [`Self::owners`].
    fn fast_hits(&self, impacts: &[CollisionEvent], owners: &[Option<(usize, usize)>]) -> Vec<(usize, usize, Vec3)> {
        let mut best: Vec<Option<(f32, usize, Vec3)>> = vec![None; self.bodies.len()];
        for event in impacts {
            let (owner_a, owner_b) = (owners[event.a].map(|o| o.0), owners[event.b].map(|o| o.0));
            if owner_a.is_some() && owner_a == owner_b {
                continue; // two of one body's own sub-bodies touching
            }
            for (index, owner) in [(event.a, owner_a), (event.b, owner_b)] {
                let Some(k) = owner else { continue };
                let Some(dynamic) = self.bodies[k].dynamic() else { continue };
                if event.normal_speed <= dynamic.speed_threshold {
                    continue;
                }
                if best[k].is_none_or(|(speed, _, _)| event.normal_speed > speed) {
                    best[k] = Some((event.normal_speed, index, event.point));
                }
            }
        }
        best.into_iter().enumerate().filter_map(|(k, b)| b.map(|(_, index, point)| (k, index, point))).collect()
    }
}
