//! The main world's dentbend state: every dentable body's mesh (its own coordinates, m), pose,
//! settings and path, the projectiles' surfaces, and the progressive dents under way.

use std::collections::{HashMap, HashSet};

use bevy::prelude::*;
use dentbend::TriMesh;
use dentbend::damage::{Damage, DentedTarget, TargetSet};
use dentbend::dent::DentSettings;
use dentbend::glam::Affine3A;
use dentbend::mesh::Refinement;

use crate::DentPath;
use crate::mesh_data::moved_positions;

/// One dentable body.
#[derive(Debug, Clone)]
pub(crate) struct BodyInfo {
    /// Its private mesh asset.
    pub mesh: Handle<Mesh>,
    pub path: DentPath,
    /// Whether the GPU path can make its dents (all but progressive ones, which rebuild each
    /// dent from the surface before the contact).
    pub gpu_servable: bool,
    /// The entity carrying its [`Dentable`](crate::Dentable) (itself, or an ancestor whose mesh
    /// sits on this child, as in a glTF scene).
    pub owner: Entity,
    /// Its entity's scale, baked into the mesh the plug-in keeps (`None`: unscaled); the asset
    /// and the collider hold the mesh without it.
    pub scale: Option<Vec3>,
}

/// A collider on another entity than the mesh it follows (a glTF node's collider over its
/// mesh child, or a parent body's): contacts naming `collider` are the mesh entity's.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ColliderAlias {
    /// The mesh entity.
    pub mesh: Entity,
    /// Mesh coordinates → the collider entity's coordinates (rigid).
    pub to_collider: Affine3A,
}

/// Every body the plug-in knows, by entity.
#[derive(Resource, Default)]
pub struct DentWorld {
    pub(crate) targets: TargetSet<Entity>,
    pub(crate) damage: Damage<Entity>,
    pub(crate) surfaces: HashMap<Entity, TriMesh>,
    pub(crate) bodies: HashMap<Entity, BodyInfo>,
    /// Bodies on the GPU path (the keys the split backend queues).
    pub(crate) on_gpu: HashSet<Entity>,
    pub(crate) step: u64,
    /// Bodies whose first dent that moved nothing has been logged.
    pub(crate) warned_empty: HashSet<Entity>,
    /// Id of the next dent queued for the GPU path.
    pub(crate) next_job: u64,
    /// GPU-path dents made with their host stages whose report has not come back yet, by id:
    /// their [`DentApplied`](crate::DentApplied) is written when it does.
    pub(crate) awaiting_report: HashMap<u64, crate::DentApplied>,
    /// Colliders on other entities than their dentable meshes, by collider entity.
    pub(crate) aliases: HashMap<Entity, ColliderAlias>,
    /// The bodies whose damage is recorded.
    pub(crate) records: crate::save::Records,
}

impl DentWorld {
    /// Dentable `entity`'s mesh as the main world knows it (its own coordinates with its
    /// entity's scale baked in, m). On the GPU path it follows the GPU a few frames behind (as
    /// the collider read-backs arrive).
    pub fn mesh(&self, entity: Entity) -> Option<&TriMesh> {
        self.targets.mesh(entity)
    }

    /// The path `entity`'s dents take; `None` when it is not a registered dentable body.
    pub fn path(&self, entity: Entity) -> Option<DentPath> {
        self.bodies.get(&entity).map(|b| b.path)
    }

    /// The dentable bodies registered so far.
    pub fn dentables(&self) -> impl Iterator<Item = Entity> + '_ {
        self.bodies.keys().copied()
    }

    /// The surface `entity` dents others with (its dentable mesh, or its projectile mesh; its own
    /// coordinates, m); `None` for an entity the plug-in has not registered.
    pub fn surface(&self, entity: Entity) -> Option<&TriMesh> {
        surface_in(&self.targets, &self.surfaces, entity)
    }

    /// Records dentable `entity`'s damage from now on (the mesh entity, or the entity carrying
    /// its `Dentable`), as the body `name` of [`damage_file`](Self::damage_file): its mesh now
    /// is the base a [`RestoreDamage`](crate::RestoreDamage) starts from.
    ///
    /// # Errors
    /// A message when `entity` is not a registered dentable body (yet).
    pub fn record_damage(&mut self, entity: Entity, name: impl Into<String>) -> Result<(), String> {
        let entity = self.mesh_of_owner(entity).unwrap_or(entity);
        let mesh = self.targets.mesh(entity).ok_or_else(|| format!("{entity} is not a registered dentable body"))?;
        self.records.track(entity, name.into(), mesh);
        Ok(())
    }

    /// Every recorded body's damage (exact mesh edits, whatever path dented it, and its
    /// fractures), for a save file (`DamageFile::to_json` with dentbend's `io` feature).
    pub fn damage_file(&self) -> dentbend::record::DamageFile {
        self.records.file()
    }

    /// Replaces `entity`'s mesh wholesale (a restored one).
    pub(crate) fn replace_mesh(&mut self, entity: Entity, mesh: TriMesh) {
        let moved = (0..mesh.vertex_count() as u32).collect();
        let dented = DentedTarget { key: entity, mesh, moved, refinement: Default::default(), topology_changed: true };
        self.targets.apply(vec![dented]);
    }

    /// The scale baked into dentable `entity`'s mesh (`None`: unscaled or unknown).
    pub(crate) fn scale(&self, entity: Entity) -> Option<Vec3> {
        self.bodies.get(&entity).and_then(|b| b.scale)
    }

    /// The mesh entity a collider on `entity` stands for (its dentable child's, or its own).
    pub fn mesh_entity(&self, entity: Entity) -> Entity {
        self.aliases.get(&entity).map_or(entity, |a| a.mesh)
    }

    /// Adds dentable `entity`.
    pub(crate) fn insert_dentable(
        &mut self,
        entity: Entity,
        mesh: TriMesh,
        pose: Affine3A,
        settings: DentSettings,
        info: BodyInfo,
    ) -> Result<(), dentbend::DentError> {
        self.targets.insert(entity, mesh, pose, settings)?;
        self.surfaces.remove(&entity);
        self.set_path(entity, info.path);
        self.bodies.insert(entity, info);
        Ok(())
    }

    /// Adds projectile `entity` with surface `mesh`.
    pub(crate) fn insert_projectile(&mut self, entity: Entity, mesh: TriMesh) {
        self.targets.insert_rigid(entity);
        self.surfaces.insert(entity, mesh);
    }

    /// The mesh entity whose collider sits on `collider` and how its mesh maps there; `None`
    /// when `collider` is not such an entity.
    #[cfg(feature = "rapier")]
    pub(crate) fn alias(&self, collider: Entity) -> Option<ColliderAlias> {
        self.aliases.get(&collider).copied()
    }

    /// `body` (a collider's entity, pose and state) as its mesh entity's: a collider standing
    /// for a dentable mesh on another entity names that entity, posed as its mesh.
    #[cfg(feature = "rapier")]
    pub(crate) fn as_mesh(&self, body: crate::DentBody) -> crate::DentBody {
        match self.alias(body.entity) {
            Some(alias) => {
                crate::DentBody { entity: alias.mesh, pose: body.pose * alias.to_collider, state: body.state }
            }
            None => body,
        }
    }

    /// The collider entity of mesh entity `mesh` and its mesh → collider transform: the alias
    /// pointing at it, else `mesh` itself.
    pub(crate) fn collider_of(&self, mesh: Entity) -> (Entity, Affine3A) {
        self.aliases
            .iter()
            .find(|(_, a)| a.mesh == mesh)
            .map_or((mesh, Affine3A::IDENTITY), |(&collider, a)| (collider, a.to_collider))
    }

    /// Every aliased mesh's collider entity and mesh → collider transform, by mesh entity (one
    /// pass over the aliases, for lookups of many bodies; meshes not in it are their own
    /// collider).
    #[cfg(feature = "avian")]
    pub(crate) fn aliased_colliders(&self) -> HashMap<Entity, (Entity, Affine3A)> {
        self.aliases.iter().map(|(&collider, a)| (a.mesh, (collider, a.to_collider))).collect()
    }

    /// The mesh entity registered for the [`Dentable`](crate::Dentable) on `owner`.
    pub(crate) fn mesh_of_owner(&self, owner: Entity) -> Option<Entity> {
        self.bodies.iter().find(|(_, b)| b.owner == owner).map(|(&e, _)| e)
    }

    /// Forgets `entity`; whether it was on the GPU path.
    pub(crate) fn remove(&mut self, entity: Entity) -> bool {
        self.aliases.retain(|_, a| a.mesh != entity);
        self.records.forget(entity);
        self.targets.remove(entity);
        self.surfaces.remove(&entity);
        self.damage.forget(entity);
        self.bodies.remove(&entity);
        self.on_gpu.remove(&entity)
    }

    /// Puts `entity` on the CPU path for good (the GPU could not hold it).
    pub(crate) fn demote(&mut self, entity: Entity) {
        self.set_path(entity, DentPath::Cpu);
        if let Some(body) = self.bodies.get_mut(&entity) {
            body.gpu_servable = false;
        }
    }

    pub(crate) fn set_path(&mut self, entity: Entity, path: DentPath) {
        if let Some(body) = self.bodies.get_mut(&entity) {
            body.path = path;
        }
        match path {
            DentPath::Gpu => self.on_gpu.insert(entity),
            DentPath::Cpu => self.on_gpu.remove(&entity),
        };
    }

    /// Moves the vertices `indices` of `entity`'s mesh to `positions` (its own coordinates);
    /// `false` when it is unknown or the mesh refuses them.
    pub(crate) fn move_vertices(&mut self, entity: Entity, indices: &[u32], positions: &[Vec3]) -> bool {
        let Some(mesh) = self.targets.mesh(entity) else { return false };
        let Some(moved) = moved_positions(mesh, indices, positions) else { return false };
        let mut mesh = mesh.clone();
        if mesh.set_positions(moved).is_err() {
            return false;
        }
        self.records.changed(entity, &mesh, 0);
        let dented = DentedTarget {
            key: entity,
            mesh,
            moved: indices.to_vec(),
            refinement: Default::default(),
            topology_changed: false,
        };
        self.targets.apply(vec![dented]);
        true
    }

    /// Replaces `entity`'s mesh by `mesh`, which refinement grew by `refinement` (`moved`: the
    /// vertices that moved, every new one included); `false` when it is unknown.
    pub(crate) fn take_refined(
        &mut self,
        entity: Entity,
        mesh: TriMesh,
        refinement: Refinement,
        moved: Vec<u32>,
    ) -> bool {
        if self.targets.mesh(entity).is_none() {
            return false;
        }
        self.records.changed(entity, &mesh, 0);
        let dented = DentedTarget { key: entity, mesh, moved, refinement, topology_changed: true };
        self.targets.apply(vec![dented]);
        true
    }
}

/// [`DentWorld::surface`] over the two fields, for callers that borrow the others apart.
pub(crate) fn surface_in<'a>(
    targets: &'a TargetSet<Entity>,
    surfaces: &'a HashMap<Entity, TriMesh>,
    entity: Entity,
) -> Option<&'a TriMesh> {
    targets.mesh(entity).or_else(|| surfaces.get(&entity))
}
