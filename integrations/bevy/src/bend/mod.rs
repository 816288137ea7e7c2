//! Bendable bodies (paper §4) in Bevy, on bevy_rapier3d or Avian: a body whose bones are the
//! engine's rigid bodies (one entity per bone, its collider the convex hull of the bone's
//! sub-body) joined by the engine's spherical joints, whose plastic or elastic rule
//! ([`dentbend::bend::JointState`], the same for every engine) the plug-in applies before each
//! step; the body's own mesh is skinned from the bones' poses every frame, on Bevy's GPU by
//! dentbend's `skin` kernel straight into Bevy's vertex slab (or on the CPU into the mesh asset).
//!
//! A bendable body given dent settings ([`Bendable::dentable`]) dents where its bones are hit:
//! its rest mesh skinned to the bones' poses is dented, the dent mapped back to the rest mesh
//! through each vertex's blended bone rotation ([`dentbend::bend::Rig`]), and the bones owning
//! a moved vertex get new hulls. With `settings.split_speed`, a hit at least that fast splits the
//! bone it lands on where it lands (dynamic articulation): a new bone entity and a joint.

mod dents;
mod rig;
mod skinning;
mod split;

use std::collections::HashMap;

use bevy::ecs::schedule::InternedScheduleLabel;
use bevy::prelude::*;
use dentbend::TriMesh;
use dentbend::bend::{self, BendSettings, JointState, Skeleton};
use dentbend::cpu::{SkinBone, SkinInfluence};
use dentbend::damage::Damage;
use dentbend::dent::{DentSettings, Refine};
use dentbend::glam::Affine3A;

use crate::engine::Engine;
use crate::{DentPath, DentSystems};

/// An entity whose mesh ([`Mesh3d`], its own coordinates, m) bends: `skeleton` (same
/// coordinates) cut into one rigid body per bone, joined by `settings.joint`'s rule. The entity
/// keeps its transform (the rest pose); its bones move.
#[derive(Component, Debug, Clone)]
pub struct Bendable {
    /// The bones (rest frame = the mesh's coordinates).
    pub skeleton: Skeleton,
    /// Density, friction, the joints' rule, skinning weights.
    pub settings: BendSettings,
    /// How its mesh dents where its bones are hit (`None`: it does not; never refined: the
    /// skinning weights belong to its vertices).
    pub dent: Option<DentSettings>,
}

impl Bendable {
    /// A body of `skeleton`'s bones with `settings`, that does not dent.
    pub fn new(skeleton: Skeleton, settings: BendSettings) -> Self {
        Self { skeleton, settings, dent: None }
    }

    /// The body also dents with `settings` (refinement is turned off).
    pub fn dentable(mut self, mut settings: DentSettings) -> Self {
        settings.params.refine = Refine::Off;
        self.dent = Some(settings);
        self
    }
}

/// One bone of a bendable body: a dynamic rigid body whose frame is the body's rest frame.
#[derive(Component, Debug, Clone, Copy, PartialEq, Eq)]
pub struct BendPiece {
    /// The bendable entity.
    pub owner: Entity,
    /// Its bone.
    pub bone: usize,
}

/// A joint between two bones and its rule's state.
#[derive(Debug)]
pub(crate) struct Joint {
    pub parent: usize,
    pub child: usize,
    /// Where it joins them, rest frame, m.
    pub point: Vec3,
    pub rule: JointState,
    /// The engine's joint entity, where it makes one (Avian); bevy_rapier3d's joint is a
    /// component of the child's entity.
    pub link: Option<Entity>,
}

/// One registered bendable body.
#[derive(Debug)]
pub(crate) struct Rig {
    /// Rest frame → world when it was registered.
    pub pose: Affine3A,
    /// One entity per bone, in bone order.
    pub pieces: Vec<Entity>,
    pub joints: Vec<Joint>,
    /// Rest mesh, skeleton, weights, influences and sub-bodies.
    pub core: bend::Rig,
    /// Its dents (`None`: it does not dent), their progressive state and step count.
    pub dent: Option<(DentSettings, Damage<Entity>, u64)>,
    pub path: DentPath,
    /// Its private mesh asset.
    pub mesh: Handle<Mesh>,
    /// The bone matrices last skinned with.
    pub last: Vec<SkinBone>,
    /// Density, friction, joint rule and dynamic articulation.
    pub settings: BendSettings,
}

/// Every bendable body, by entity.
#[derive(Resource, Default)]
pub struct Bends {
    pub(crate) rigs: HashMap<Entity, Rig>,
}

impl Bends {
    /// The bone entities of bendable `entity`, in bone order.
    pub fn pieces(&self, entity: Entity) -> Option<&[Entity]> {
        self.rigs.get(&entity).map(|r| r.pieces.as_slice())
    }

    /// Net plastic bend of each joint of `entity` since it was made, rad (0 for elastic joints).
    pub fn bend_angles(&self, entity: Entity) -> Option<Vec<f32>> {
        self.rigs.get(&entity).map(|rig| rig.joints.iter().map(|j| j.rule.bend_angle()).collect())
    }

    /// The rest mesh of `entity` (rest frame, m) and each vertex's bone influences.
    pub fn rest(&self, entity: Entity) -> Option<(&TriMesh, &[SkinInfluence])> {
        self.rigs.get(&entity).map(|r| (r.core.rest(), r.core.influences()))
    }

    /// The bone matrices `entity` was last skinned with (rest frame → its own coordinates).
    pub fn skinned_with(&self, entity: Entity) -> Option<&[SkinBone]> {
        self.rigs.get(&entity).map(|r| r.last.as_slice())
    }

    /// Where `entity`'s mesh is skinned: on Bevy's GPU into its vertex slab, or on the CPU into
    /// its mesh asset.
    pub fn skinning_path(&self, entity: Entity) -> Option<DentPath> {
        self.rigs.get(&entity).map(|r| r.path)
    }
}

/// Adds bending to the app on engine `E`: the joint rules before every step of `physics` (the
/// schedule `E` steps in), bones registered, split and dented in `PostUpdate`.
pub(crate) fn build<E: Engine>(app: &mut App, physics: InternedScheduleLabel) {
    app.init_resource::<Bends>()
        .add_systems(PostUpdate, rig::register_bendables::<E>.in_set(DentSystems::Register))
        .add_systems(
            PostUpdate,
            (split::split_bones::<E>, dents::dent_bendables::<E>)
                .chain()
                .in_set(DentSystems::Decide)
                .after(crate::decide::decide_dents),
        )
        .add_systems(PostUpdate, (rig::forget_removed, skinning::pose_bendables).chain().in_set(DentSystems::Apply));
    E::add_joint_rules(app, physics);
}
