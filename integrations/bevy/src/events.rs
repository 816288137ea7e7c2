//! Messages the plug-in writes.

use bevy::prelude::*;
use dentbend::dent::Impact;
use dentbend::fracture::FractureCause;

use crate::DentPath;

/// A dent was decided (and on the CPU path made). On the GPU path it is made by the render
/// world's next batch it can run (usually this frame's), or dropped and counted in
/// [`DentStats::rejected_contacts`](crate::DentStats::rejected_contacts) when its body is gone.
#[derive(Message, Debug, Clone, Copy)]
pub struct DentApplied {
    /// The dented entity.
    pub target: Entity,
    /// What hit it.
    pub projectile: Entity,
    /// The impact, world coordinates at the start of the step.
    pub impact: Impact,
    /// How deep the dent was decided to be, m.
    pub dent_distance: f32,
    /// How deep it really is, m: its largest vertex displacement (0 when it moved nothing; less
    /// than `dent_distance` when the intersection guard limited it or the mesh under it is
    /// coarse). `None` on the GPU path, whose dents are made after this message.
    pub depth_made: Option<f32>,
    /// Fraction of the displacement the intersection guard kept (`None`: not limited, or on the
    /// GPU path).
    pub limited_to: Option<f32>,
    /// Where it was computed.
    pub path: DentPath,
}

/// A dentable entity's main-world mesh ([`DentWorld::mesh`](crate::DentWorld::mesh)) changed: the
/// vertices listed moved (on the GPU path, once their read-back arrives). A physics adapter
/// refits the entity's collider from it.
#[derive(Message, Debug, Clone)]
pub struct MeshDented {
    /// The dented entity.
    pub entity: Entity,
    /// Vertices that moved, ascending (every vertex past the old count when refined).
    pub moved: Vec<u32>,
    /// Whether the faces changed (a refining dent on the CPU path): rebuild, do not refit.
    pub topology_changed: bool,
}

/// A breakable dentable entity broke (on the CPU path, the step its hit was decided): its mesh is
/// now the rest (or the entity was despawned, the pattern having taken it whole), and each piece
/// is a new entity with a [`DentPiece`](crate::DentPiece).
#[derive(Message, Debug, Clone)]
pub struct BodyBroken {
    /// The entity that broke.
    pub entity: Entity,
    /// What broke it.
    pub projectile: Entity,
    /// Why.
    pub cause: FractureCause,
    /// The pieces' entities, in the fracture's order.
    pub pieces: Vec<Entity>,
    /// Whether the pattern took the whole body (the entity was despawned).
    pub whole: bool,
    /// The projectile's (linear m/s, angular rad/s) velocity from before the step, less the
    /// energy the break used up: the body gave way instead of stopping it (with the `rapier`
    /// feature the projectile's `Velocity` is set to it); `None` for a projectile that takes no
    /// impulse.
    pub projectile_velocity: Option<(Vec3, Vec3)>,
}
