//! bevy_rapier3d as the contact source and collider owner: impacts from Rapier's solver become
//! [`DentContact`](crate::DentContact)s, and dented meshes refit the entities' `Collider`s.
//!
//! Dentable colliders get `ActiveEvents::CONTACT_FORCE_EVENTS` with a 0 N threshold, so Rapier
//! reports each impact on the step a pair first pushes (dentbend-rapier's
//! [`ImpactCollector`](dentbend_rapier::ImpactCollector) turns the solver's contacts into one
//! point and normal); body states are recorded just before Rapier's step.

mod bend_joints;
mod contacts;
mod give_way;

use bevy::ecs::schedule::{InternedScheduleLabel, ScheduleLabel};
use bevy::prelude::*;
use bevy_rapier3d::plugin::PhysicsSet;
use bevy_rapier3d::prelude::{
    ActiveEvents, Collider, ColliderMassProperties, ContactForceEventThreshold, Friction, ImpulseJoint, MassProperties,
    RigidBody, SphericalJointBuilder, Velocity,
};
use bevy_rapier3d::rapier::prelude::MassProperties as RapierMass;
use parry3d::shape::SharedShape;

use crate::engine::{self, Engine};
use crate::{DentPiece, DentSystems};

/// bevy_rapier3d's colliders.
pub(crate) struct Rapier;

impl Engine for Rapier {
    type Collider = Collider;
    type Body = RigidBody;
    const NAME: &'static str = "bevy_rapier3d";

    fn shape(collider: &Collider) -> &SharedShape {
        &collider.raw
    }

    fn set_shape(collider: &mut Collider, shape: SharedShape) {
        *collider = Collider::from(shape);
    }

    fn piece_body(hull: &[Vec3], piece: &DentPiece) -> Option<impl Bundle> {
        let mass = RapierMass::with_inertia_matrix(piece.mass.center, piece.mass.mass, piece.mass.inertia);
        Some((
            RigidBody::Dynamic,
            Collider::convex_hull(hull)?,
            ColliderMassProperties::MassProperties(MassProperties::from_rapier(mass)),
            Velocity { linear: piece.linear_velocity, angular: piece.angular_velocity },
        ))
    }

    fn hull(points: &[Vec3]) -> Option<Collider> {
        Collider::convex_hull(points)
    }

    fn bone_body(
        hull: &[Vec3],
        (density, friction): (f32, f32),
        transform: Transform,
        (linear, angular): (Vec3, Vec3),
    ) -> Option<impl Bundle> {
        Some((
            RigidBody::Dynamic,
            Collider::convex_hull(hull)?,
            ColliderMassProperties::Density(density),
            Friction::coefficient(friction),
            transform,
            Velocity { linear, angular },
            // A bone reports every push (its impacts dent and split it).
            ActiveEvents::CONTACT_FORCE_EVENTS,
            ContactForceEventThreshold(0.0),
        ))
    }

    fn join(commands: &mut Commands, parent: Entity, child: Entity, point: Vec3) -> Option<Entity> {
        let joint = SphericalJointBuilder::new().local_anchor1(point).local_anchor2(point).contacts_enabled(false);
        // The child's one joint: inserting replaces the one it had.
        commands.entity(child).insert(ImpulseJoint::new(parent, joint));
        None
    }

    fn is_dynamic(body: &RigidBody) -> bool {
        *body == RigidBody::Dynamic
    }

    fn place(commands: &mut Commands, entity: Entity, transform: Transform, (linear, angular): (Vec3, Vec3)) {
        commands.entity(entity).insert((transform, Velocity { linear, angular }));
    }

    fn add_joint_rules(app: &mut App, physics: InternedScheduleLabel) {
        app.add_systems(
            physics,
            bend_joints::apply_joint_rules
                .after(PhysicsSet::SyncBackend)
                .before(contacts::record_states)
                .before(PhysicsSet::StepSimulation),
        );
    }
}

/// Adds the bevy_rapier3d contact source and collider refits (added by
/// [`DentbendPlugin`](crate::DentbendPlugin) when the `rapier` feature is on): states recorded
/// before each step and impacts read after it in `physics` (the schedule bevy_rapier3d steps
/// in), dents decided in `PostUpdate` after them.
pub(crate) fn build(app: &mut App, physics: InternedScheduleLabel) {
    app.init_resource::<contacts::RapierImpacts>()
        .add_systems(
            physics,
            (contacts::install_collector, contacts::enable_force_events, contacts::record_states)
                .chain()
                .after(PhysicsSet::SyncBackend)
                .before(PhysicsSet::StepSimulation),
        )
        .add_systems(physics, contacts::send_contacts.after(PhysicsSet::StepSimulation).before(PhysicsSet::Writeback))
        .add_systems(PostUpdate, give_way::give_way.in_set(DentSystems::Apply));
    engine::add_shared_systems::<Rapier>(app);
    if physics == PostUpdate.intern() {
        app.configure_sets(PostUpdate, DentSystems::Decide.after(PhysicsSet::Writeback));
    }
}

/// The schedule bevy_rapier3d steps in (the one whose `PhysicsSet::StepSimulation` holds its
/// step), if it is set up.
pub(crate) fn physics_schedule(app: &App) -> Option<InternedScheduleLabel> {
    engine::schedule_stepping(app, PhysicsSet::StepSimulation.intern())
}
