//! Avian's contacts as [`DentContact`]s: the pairs of a dentable's or a bendable bone's collider
//! with another body the plug-in knows that the solver pushed on this step, with the two bodies
//! as they were before it.

use std::collections::{HashMap, HashSet};

use avian3d::math::SymmetricTensor;
use avian3d::prelude::{
    AngularVelocity, ColliderOf, Collisions, ComputedAngularInertia, ComputedCenterOfMass, ComputedMass, ContactPair,
    DefaultRestitution, LinearVelocity, LockedAxes, Position, Restitution, RigidBody, Rotation,
};
use avian3d::schedule::LastPhysicsTick;
use bevy::ecs::change_detection::Tick;
use bevy::prelude::*;
use dentbend::dent::BodyState;
use dentbend::glam::Affine3A;

use crate::{BendPiece, DentBody, DentContact, DentWorld};

/// The bodies the plug-in knows as they were before the step, and the pairs that pushed.
#[derive(Resource, Default)]
pub(crate) struct AvianImpacts {
    /// Each known mesh's body before the step (its entity, pose and state), by its collider's
    /// entity.
    before: HashMap<Entity, DentBody>,
    /// Collider pairs (as Avian orders them) between known bodies the solver pushed on in the
    /// previous step.
    pushing: HashSet<(Entity, Entity)>,
    /// Avian's last step when the states were recorded: a step that did not run (physics time
    /// paused) sends nothing.
    recorded_at: Tick,
    /// The bendable bodies' bones recorded before the step (their own colliders): their pairs
    /// are read as the dentables' are, for bends, splits and dents.
    bones: HashSet<Entity>,
}

/// A collider's pose, the body it belongs to and its restitution.
type ColliderData = (&'static Position, &'static Rotation, Option<&'static ColliderOf>, Option<&'static Restitution>);

/// What a body's [`BodyState`] is made of.
type BodyData = (
    &'static RigidBody,
    &'static Position,
    &'static Rotation,
    &'static LinearVelocity,
    &'static AngularVelocity,
    &'static ComputedMass,
    &'static ComputedAngularInertia,
    &'static ComputedCenterOfMass,
    Option<&'static LockedAxes>,
);

/// One body's [`BodyData`].
type BodyItem<'a> = <BodyData as bevy::ecs::query::QueryData>::Item<'a, 'a>;

/// Records the dentables', projectiles' and bones' poses and states just before Avian's step
/// (O(bodies the plug-in knows), never a walk over the world).
pub(crate) fn record_states(
    mut impacts: ResMut<AvianImpacts>,
    world: Res<DentWorld>,
    bones: Query<Entity, With<BendPiece>>,
    (last_step, default_restitution): (Res<LastPhysicsTick>, Res<DefaultRestitution>),
    colliders: Query<ColliderData>,
    bodies: Query<BodyData>,
) {
    impacts.before.clear();
    impacts.bones.clear();
    impacts.bones.extend(bones.iter());
    impacts.recorded_at = last_step.0;
    let aliased = world.aliased_colliders();
    for mesh in world.bodies.keys().chain(world.surfaces.keys()).copied().chain(bones.iter()) {
        let (collider, to_collider) = aliased.get(&mesh).copied().unwrap_or((mesh, Affine3A::IDENTITY));
        let Ok((position, rotation, of, restitution)) = colliders.get(collider) else { continue };
        let pose = Affine3A::from_rotation_translation(rotation.0, position.0) * to_collider;
        let mut state = of.and_then(|of| bodies.get(of.body).ok()).map_or(BodyState::FIXED, state_of);
        // The collider's coefficient, else Avian's default (as Avian's narrow phase takes it).
        let coefficient = restitution.copied().unwrap_or(default_restitution.0).coefficient;
        state.restitution = if coefficient.is_finite() { coefficient.clamp(0.0, 1.0) } else { 0.0 };
        impacts.before.insert(collider, DentBody { entity: mesh, pose, state });
    }
}

/// A body's state: static bodies are fixed, kinematic ones move but take no impulse. The
/// inverse inertia is the one Avian's solver uses: world axes, with the rows and columns of
/// locked rotation axes zero (a body that cannot turn about an axis takes no angular impulse
/// about it). Locked translation leaves the inverse mass as it is, as Avian's solver does in 3D.
fn state_of((kind, position, rotation, linear, angular, mass, inertia, centre, locked): BodyItem<'_>) -> BodyState {
    if kind.is_static() {
        return BodyState::FIXED;
    }
    let (inverse_mass, inverse_inertia) = if kind.is_dynamic() {
        let axes = Mat3::from_quat(rotation.0);
        let local: SymmetricTensor = inertia.inverse();
        let locked = locked.copied().unwrap_or_default();
        let free = |is_locked: bool| if is_locked { 0.0 } else { 1.0 };
        // keep · I⁻¹ · keep zeroes the rows and columns of the locked axes.
        let keep = Mat3::from_diagonal(Vec3::new(
            free(locked.is_rotation_x_locked()),
            free(locked.is_rotation_y_locked()),
            free(locked.is_rotation_z_locked()),
        ));
        (mass.inverse(), keep * axes * local.to_mat3() * axes.transpose() * keep)
    } else {
        (0.0, Mat3::ZERO)
    };
    BodyState {
        center_of_mass: position.0 + rotation.0 * centre.0,
        linear_velocity: linear.0,
        angular_velocity: angular.0,
        inverse_mass,
        inverse_inertia,
        restitution: 0.0,
    }
}

/// This step's pushes on each dentable's and bone's collider (those recorded before the step),
/// between bodies the plug-in knows, as
/// [`DentContact`]s (`started` on the first step a pair pushes).
pub(crate) fn send_contacts(
    mut impacts: ResMut<AvianImpacts>,
    world: Res<DentWorld>,
    last_step: Res<LastPhysicsTick>,
    collisions: Collisions,
    mut out: MessageWriter<DentContact>,
) {
    if last_step.0 == impacts.recorded_at {
        // Avian did not step (its time is paused): the contact graph holds the last step's.
        return;
    }
    let mut seen = HashSet::new();
    let mut pushing = HashSet::new();
    // The dentables' and bones' colliders, as recorded before the step.
    let read = |(collider, body): (&Entity, &DentBody)| {
        (world.path(body.entity).is_some() || impacts.bones.contains(collider)).then_some(*collider)
    };
    for collider in impacts.before.iter().filter_map(read) {
        for pair in collisions.collisions_with(collider) {
            let key = (pair.collider1, pair.collider2);
            if !seen.insert(key) {
                continue;
            }
            let Some((point, normal)) = strongest_push(pair) else { continue };
            let (Some(&a), Some(&b)) = (impacts.before.get(&pair.collider1), impacts.before.get(&pair.collider2))
            else {
                continue;
            };
            // Only pairs sent count as pushing: a body registered mid-push starts its impact.
            pushing.insert(key);
            let started = !impacts.pushing.contains(&key);
            out.write(DentContact { a, b, point, normal, started });
        }
    }
    impacts.pushing = pushing;
}

/// The point and normal (world, from the pair's first collider to its second) of the contact
/// the solver pushed hardest on this step, `None` when it pushed on none.
fn strongest_push(pair: &ContactPair) -> Option<(Vec3, Vec3)> {
    if !pair.is_touching() {
        return None;
    }
    pair.manifolds
        .iter()
        .flat_map(|m| m.points.iter().map(move |p| (p, m.normal)))
        .filter(|(p, _)| p.normal_impulse > 0.0)
        .max_by(|(p, _), (q, _)| p.normal_impulse.total_cmp(&q.normal_impulse))
        .map(|(p, normal)| (p.point, normal))
}
