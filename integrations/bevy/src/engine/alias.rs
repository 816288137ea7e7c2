//! Dentable meshes whose collider sits on another entity: a glTF node's collider over its mesh
//! child, or a parent body's collider over a child mesh. The engine's contacts name the
//! collider's entity; the plug-in maps them to the mesh entity, and refits the collider on its
//! own entity.

use bevy::prelude::*;

use super::Engine;
use crate::DentWorld;
use crate::scale::scale_refusal;
use crate::world::ColliderAlias;

/// Marks a registered mesh entity whose collider the plug-in has looked for.
#[derive(Component)]
pub(crate) struct ColliderFound;

/// For each newly registered dentable mesh without a collider of its own: the collider on the
/// entity carrying its `Dentable`, else on its nearest ancestor, becomes its alias (with the
/// mesh → collider transform now). A mesh with no collider anywhere, or one whose collider
/// entity is scaled, is named in one warning with the fix: the engine's contacts would never
/// dent it.
pub(crate) fn find_colliders<E: Engine>(
    mut commands: Commands,
    mut world: ResMut<DentWorld>,
    colliders: Query<(&E::Collider, &GlobalTransform)>,
    transforms: Query<&GlobalTransform>,
    parents: Query<&ChildOf>,
    done: Query<(), With<ColliderFound>>,
) {
    let unseen: Vec<(Entity, Entity)> =
        world.bodies.iter().filter(|(e, _)| !done.contains(**e)).map(|(&e, b)| (e, b.owner)).collect();
    for (mesh, owner) in unseen {
        commands.entity(mesh).insert(ColliderFound);
        if colliders.contains(mesh) {
            continue;
        }
        let ancestors = std::iter::successors(Some(mesh), |&e| parents.get(e).ok().map(ChildOf::parent)).skip(1);
        let found = std::iter::once(owner).chain(ancestors).find(|&e| e != mesh && colliders.contains(e));
        let Some(collider) = found else {
            warn!(
                "bevy_dentbend: {mesh} dents, but neither it nor {owner} nor an ancestor has a Collider ({}): its \
                 contacts will never dent it; give the entity with the Dentable (or its mesh) a Collider built from \
                 the mesh, or write DentContact messages for it",
                E::NAME
            );
            continue;
        };
        let (Ok((_, at)), Ok(mesh_at)) = (colliders.get(collider), transforms.get(mesh)) else { continue };
        if let Some(reason) = scale_refusal(at) {
            warn!(
                "bevy_dentbend: {mesh}'s collider is on {collider}, and {reason}: its contacts cannot be mapped to the \
                 mesh, so it will not dent; give the mesh entity its own Collider"
            );
            continue;
        }
        let to_collider = at.affine().inverse() * mesh_at.affine();
        info!("bevy_dentbend: {mesh} dents through the collider on {collider}");
        world.aliases.insert(collider, ColliderAlias { mesh, to_collider });
    }
}
