//! The per-step bending driver (paper Algorithm 2): steps a [`World`] holding bending bodies,
//! with the dummy step of dynamic articulation (snapshot, step, split where fast hits landed,
//! restore and step again), and records the joints made and the plastic bends.

use std::time::Instant;

use glam::Vec3;
use serde::Serialize;

use super::{ArticulatedBody, BendableDesc};
use crate::mesh::TriMesh;
use crate::sim::{SimError, StepReport, World};

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
    bodies: Vec<ArticulatedBody>,
    joints: Vec<JointRecord>,
    bends: Vec<BendRecord>,
}

impl Bending {
    /// No bending bodies.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a bending body to `world` (see [`ArticulatedBody::new`]); returns its index here.
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
        self.bodies.push(ArticulatedBody::new(world, desc)?);
        Ok(self.bodies.len() - 1)
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

    /// One step of `world`. With dynamic articulation (Algorithm 2 steps 4–12): snapshot, step;
    /// if a collision involving a sub-body of such a body closed faster than its threshold,
    /// restore the snapshot, split at the fastest such hit of each body
    /// ([`ArticulatedBody::split_at`]) and step again. Records the joints made and the plastic
    /// bends of the step that stands. Without bending bodies this is [`World::step`].
    ///
    /// # Errors
    /// A split failed (a bug; the world is restored to before the step) or the snapshot could not
    /// be restored.
    pub fn step(&mut self, world: &mut World) -> Result<StepReport, SimError> {
        let dynamic = self.bodies.iter().any(|b| b.dynamic().is_some());
        let snapshot = dynamic.then(|| world.snapshot());
        let mut report = world.step();
        if let Some(snapshot) = snapshot {
            let hits = self.fast_hits(&report);
            if !hits.is_empty() {
                world.restore(&snapshot)?;
                let frame = world.steps() + 1;
                for (body, index, point) in hits {
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
                report = world.step();
            }
        }
        let frame = world.steps();
        self.bends.extend(report.bends.iter().map(|b| BendRecord { frame, joint: b.joint, angle: b.angle }));
        Ok(report)
    }

    /// Per bending body with dynamic articulation, the fastest hit on one of its sub-bodies above
    /// its threshold: (body, world body index hit, contact point).
    fn fast_hits(&self, report: &StepReport) -> Vec<(usize, usize, Vec3)> {
        let mut best: Vec<Option<(f32, usize, Vec3)>> = vec![None; self.bodies.len()];
        for event in &report.events {
            for index in [event.a, event.b] {
                for (k, body) in self.bodies.iter().enumerate() {
                    let Some(dynamic) = body.dynamic() else { continue };
                    let own = |i: usize| body.bone_of(i).is_some();
                    if own(event.a) && own(event.b) {
                        continue; // two of its own sub-bodies touching
                    }
                    if body.bone_of(index).is_none() || event.normal_speed <= dynamic.speed_threshold {
                        continue;
                    }
                    if best[k].is_none_or(|(speed, _, _)| event.normal_speed > speed) {
                        best[k] = Some((event.normal_speed, index, event.point));
                    }
                }
            }
        }
        best.into_iter().enumerate().filter_map(|(k, b)| b.map(|(_, index, point)| (k, index, point))).collect()
    }
}
