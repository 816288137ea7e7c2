//! The collider read-backs under way, applied in the order they were recorded: a mesh's
//! read-backs each carry the final positions of what their batch moved, so a later one must land
//! after an earlier one even when both finish in the same frame.

use std::collections::HashSet;

use bevy::prelude::*;
use dentbend::TriMesh;
use dentbend::dent::moved_vertices;
use dentbend::gpu::{GpuDenter, MovedVertices, PendingMoved};

use crate::link::{RenderLink, ToMain};
use crate::mesh_data::moved_positions;

/// Read-backs in recording order.
#[derive(Default)]
pub(crate) struct Readbacks {
    pending: Vec<(Entity, PendingMoved)>,
}

/// Where a finished read-back's target is: its slot in the denter and its mirror.
pub(crate) trait Mirrors {
    /// The slot and mirror of `entity`, if it is still resident.
    fn mirror(&mut self, entity: Entity) -> Option<(usize, &mut TriMesh)>;
}

impl Readbacks {
    /// Whether none is under way.
    pub fn is_empty(&self) -> bool {
        self.pending.is_empty()
    }

    /// Adds read-backs whose encoder was just submitted.
    pub fn submitted(&mut self, reads: Vec<(Entity, PendingMoved)>) {
        for (entity, mut read) in reads {
            read.submitted();
            self.pending.push((entity, read));
        }
    }

    /// Advances every read-back without blocking; applies the finished ones to their mirrors and
    /// sends them to the main world, each mesh's in recording order. A failed read-back is
    /// replaced by a blocking read of the whole mesh from `denter` (a rare path, counted as
    /// collider bytes), so the mirror never misses a dent.
    pub fn poll(&mut self, targets: &mut impl Mirrors, denter: Option<&GpuDenter>, link: &RenderLink) {
        let mut waiting: HashSet<Entity> = HashSet::new();
        let mut i = 0;
        while i < self.pending.len() {
            let (entity, read) = &mut self.pending[i];
            let entity = *entity;
            if waiting.contains(&entity) {
                i += 1;
                continue;
            }
            let outcome = read.poll();
            let bytes = read.bytes_read();
            match outcome {
                Ok(None) if !read.is_done() => {
                    waiting.insert(entity);
                    i += 1;
                    continue;
                }
                Ok(None) => {}
                Ok(Some(moved)) => {
                    if let Some((_, mirror)) = targets.mirror(entity) {
                        apply(mirror, &moved);
                    }
                    link.send(ToMain::Moved { entity, moved, bytes });
                }
                Err(e) => {
                    warn!("bevy_dentbend: the collider read-back of {entity} failed ({e}); reading the whole mesh");
                    resync(entity, targets, denter, link);
                }
            }
            self.pending.remove(i);
        }
    }
}

/// Moves `mirror`'s vertices as `moved` says.
fn apply(mirror: &mut TriMesh, moved: &MovedVertices) {
    let Some(positions) = moved_positions(mirror, &moved.indices, &moved.positions) else {
        error!("bevy_dentbend: a read-back names vertices past its mesh; ignored");
        return;
    };
    if let Err(e) = mirror.set_positions(positions) {
        error!("bevy_dentbend: a dented mesh read back unusable ({e})");
    }
}

/// Reads `entity`'s whole mesh back (blocking) into its mirror and sends what differs.
fn resync(entity: Entity, targets: &mut impl Mirrors, denter: Option<&GpuDenter>, link: &RenderLink) {
    let (Some((slot, mirror)), Some(denter)) = (targets.mirror(entity), denter) else { return };
    match denter.read_positions(slot) {
        Ok(positions) => {
            let indices = moved_vertices(mirror.positions(), &positions);
            let moved = MovedVertices { positions: indices.iter().map(|&v| positions[v as usize]).collect(), indices };
            let bytes = 16 * positions.len() as u64;
            apply(mirror, &moved);
            link.send(ToMain::Moved { entity, moved, bytes });
        }
        Err(e) => error!("bevy_dentbend: {entity} could not be read back ({e}); its collider keeps its shape"),
    }
}
