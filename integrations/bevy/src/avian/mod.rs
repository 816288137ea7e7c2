//! Avian 0.8 as the contact source and collider owner: contacts the solver pushed on become
//! [`DentContact`](crate::DentContact)s, dented meshes refit the entities' `Collider`s, and the
//! pieces of broken bodies become Avian bodies.
//!
//! The states of the bodies the plug-in knows (dentables, projectiles and bendable bodies'
//! bones) are recorded just before Avian's step, in the schedule it steps in (`FixedPostUpdate`
//! by default); after the step, each dentable's and bone's contact pairs with those bodies in
//! Avian's contact graph are read, so the cost follows their contacts, not the number of bodies.
//! Bones are Avian bodies joined by `SphericalJoint` entities; their joint rules turn them
//! just before each step.

mod bend_joints;
mod contacts;
mod give_way;

use avian3d::math::SymmetricTensor;
use avian3d::prelude::{
    AngularInertia, AngularVelocity, CenterOfMass, Collider, ColliderDensity, Friction, JointCollisionDisabled,
    LinearVelocity, Mass, NoAutoAngularInertia, NoAutoCenterOfMass, NoAutoMass, PhysicsSystems, RigidBody,
    SphericalJoint,
};
use bevy::ecs::schedule::{InternedScheduleLabel, ScheduleLabel};
use bevy::prelude::*;
use parry3d::shape::SharedShape;

use crate::engine::{self, Engine};
use crate::{DentPiece, DentSystems};

/// Avian's colliders.
pub(crate) struct Avian;

impl Engine for Avian {
    type Collider = Collider;
    type Body = RigidBody;
    const NAME: &'static str = "Avian";

    fn shape(collider: &Collider) -> &SharedShape {
        collider.shape()
    }

    fn set_shape(collider: &mut Collider, shape: SharedShape) {
        collider.set_shape(shape);
    }

    fn piece_body(hull: &[Vec3], piece: &DentPiece) -> Option<impl Bundle> {
        let inertia = AngularInertia::from_tensor(SymmetricTensor::from_mat3_unchecked(piece.mass.inertia));
        let mass = (
            Mass(piece.mass.mass),
            inertia,
            CenterOfMass(piece.mass.center),
            NoAutoMass,
            NoAutoAngularInertia,
            NoAutoCenterOfMass,
        );
        let motion = (LinearVelocity(piece.linear_velocity), AngularVelocity(piece.angular_velocity));
        Some((RigidBody::Dynamic, Collider::convex_hull(hull)?, mass, motion))
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
        // Avian reads every contact pair of a bone from its contact graph (see `contacts`).
        Some((
            RigidBody::Dynamic,
            Collider::convex_hull(hull)?,
            ColliderDensity(density),
            Friction::new(friction),
            transform,
            LinearVelocity(linear),
            AngularVelocity(angular),
        ))
    }

    fn join(commands: &mut Commands, parent: Entity, child: Entity, point: Vec3) -> Option<Entity> {
        let joint = SphericalJoint::new(parent, child).with_local_anchor1(point).with_local_anchor2(point);
        Some(commands.spawn((joint, JointCollisionDisabled)).id())
    }

    fn is_dynamic(body: &RigidBody) -> bool {
        body.is_dynamic()
    }

    fn place(commands: &mut Commands, entity: Entity, transform: Transform, (linear, angular): (Vec3, Vec3)) {
        commands.entity(entity).insert((transform, LinearVelocity(linear), AngularVelocity(angular)));
    }

    fn add_joint_rules(app: &mut App, physics: InternedScheduleLabel) {
        app.add_systems(
            physics,
            bend_joints::apply_joint_rules
                .after(PhysicsSystems::Prepare)
                .before(contacts::record_states)
                .before(PhysicsSystems::StepSimulation),
        );
    }
}

/// Adds the Avian contact source, collider refits and piece bodies (added by
/// [`DentbendPlugin`](crate::DentbendPlugin) when the `avian` feature is on and Avian steps in
/// `physics`): states recorded before each step and contacts read after it, dents decided in
/// `PostUpdate` after them.
pub(crate) fn build(app: &mut App, physics: InternedScheduleLabel) {
    app.init_resource::<contacts::AvianImpacts>()
        .add_systems(
            physics,
            contacts::record_states.after(PhysicsSystems::Prepare).before(PhysicsSystems::StepSimulation),
        )
        .add_systems(
            physics,
            contacts::send_contacts.after(PhysicsSystems::StepSimulation).before(PhysicsSystems::Writeback),
        )
        .add_systems(PostUpdate, give_way::give_way.in_set(DentSystems::Apply));
    engine::add_shared_systems::<Avian>(app);
    if physics == PostUpdate.intern() {
        app.configure_sets(PostUpdate, DentSystems::Decide.after(PhysicsSystems::Writeback));
    }
}

/// The schedule Avian steps in (the one whose `PhysicsSystems::StepSimulation` holds its step),
/// if Avian is set up.
pub(crate) fn physics_schedule(app: &App) -> Option<InternedScheduleLabel> {
    engine::schedule_stepping(app, PhysicsSystems::StepSimulation.intern())
}
