//! What every physics engine's contact source shares: the engine's collider component and
//! shape, finding a dentable mesh's collider on another entity, refitting colliders after dents,
//! bodies for broken pieces, the bodies and joints of bendable bodies' bones and their joint
//! rules, and finding the schedule the engine steps in. `rapier` and `avian` features.

mod alias;
mod pieces;
mod refit;
mod schedule;

pub(crate) use schedule::schedule_stepping;

use bevy::prelude::*;
use parry3d::shape::SharedShape;

use crate::{DentPiece, DentSystems};

/// A physics engine whose colliders are parry3d shapes on entities.
pub(crate) trait Engine: Send + Sync + 'static {
    /// The engine's collider component.
    type Collider: Component<Mutability = bevy::ecs::component::Mutable>;
    /// The engine's rigid-body component.
    type Body: Component;
    /// The engine's name in log lines, as its users know it.
    const NAME: &'static str;

    /// The collider's shape (bevy_rapier3d's may hold the entity's scale: scaled entities'
    /// colliders are rebuilt whole, never refitted).
    fn shape(collider: &Self::Collider) -> &SharedShape;

    /// Gives the collider `shape` (the engine applies the entity's scale to it).
    fn set_shape(collider: &mut Self::Collider, shape: SharedShape);

    /// The dynamic body `piece` becomes: a convex collider over `hull` (its mesh's coordinates,
    /// m) with the piece's own mass properties (not the collider's), moving as it broke loose;
    /// `None` when the points span no hull (a sliver).
    fn piece_body(hull: &[Vec3], piece: &DentPiece) -> Option<impl Bundle>;

    /// A convex collider over `points` (the entity's frame, m); `None` when they span no hull.
    fn hull(points: &[Vec3]) -> Option<Self::Collider>;

    /// A bone of a bendable body: a dynamic body with a convex collider over `hull` (its rest
    /// frame, m) of `material` (density kg/m³, friction coefficient), at `transform`, moving
    /// with `motion` (linear m/s, angular rad/s), whose contacts the plug-in reads; `None` when
    /// the points span no hull.
    fn bone_body(
        hull: &[Vec3],
        material: (f32, f32),
        transform: Transform,
        motion: (Vec3, Vec3),
    ) -> Option<impl Bundle>;

    /// Joins bone body `child` to `parent` with a spherical joint at `point` (the bodies'
    /// shared rest frame, m), no contacts between them: the engine holds the anchors together
    /// and the joint's rule turns them. Returns the joint's own entity where the engine makes
    /// one, to despawn when the child is joined elsewhere (a child has one joint).
    fn join(commands: &mut Commands, parent: Entity, child: Entity, point: Vec3) -> Option<Entity>;

    /// Whether `body` is a dynamic body (one the solver moves).
    fn is_dynamic(body: &Self::Body) -> bool;

    /// Puts body `entity` at `transform`, moving with `motion` (linear m/s, angular rad/s).
    fn place(commands: &mut Commands, entity: Entity, transform: Transform, motion: (Vec3, Vec3));

    /// Adds the system that applies the bendable bodies' joint rules just before each step of
    /// `physics` (the schedule the engine steps in).
    fn add_joint_rules(app: &mut App, physics: bevy::ecs::schedule::InternedScheduleLabel);
}

/// Adds what every engine's contact source needs in `PostUpdate`: finding colliders on other
/// entities than their meshes, refitting colliders after dents, and bodies for broken pieces.
pub(crate) fn add_shared_systems<E: Engine>(app: &mut App) {
    app.add_systems(
        PostUpdate,
        alias::find_colliders::<E>.after(crate::register::register_dentables).in_set(DentSystems::Register),
    )
    .add_systems(PostUpdate, (refit::refit_colliders::<E>, pieces::give_bodies::<E>).in_set(DentSystems::Apply));
}
