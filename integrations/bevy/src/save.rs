//! Save and restore: the damage of the dentable bodies a game asked to record, as dentbend's
//! damage file (exact mesh edits, whatever path made the dents, and fractures), and the
//! [`RestoreDamage`] message that replays a saved body's damage onto a body spawned undamaged.

use bevy::prelude::*;
use dentbend::TriMesh;
use dentbend::damage::BodyFracture;
use dentbend::mesh::{MeshEdit, Refinement, content_hash};
use dentbend::record::{
    BodyDamage, DamageFile, DamageRecord, DentBatch, DentForm, FracturePiece, FractureRecord, MeshStamp, Projectiles,
    ReplayStep, replay_body_traced,
};

use crate::fracture_attributes::{Broken, carry_attributes};
use crate::link::{MainLink, ToRender};
use crate::mesh_data::{bevy_mesh, slab_layout, write_dented};
use crate::scale::for_asset;
use crate::{DentPath, DentWorld, MeshDented};

/// One recorded body: its damage so far, its mesh when last recorded, and dents queued on the
/// GPU path whose result has not come back yet.
#[derive(Debug, Clone)]
struct Recorded {
    entity: Entity,
    damage: BodyDamage,
    last: TriMesh,
    pending: u32,
}

/// The bodies being recorded.
#[derive(Debug, Clone, Default)]
pub(crate) struct Records {
    bodies: Vec<Recorded>,
}

impl Records {
    /// Starts (or restarts) recording `entity`, called `name`, whose mesh is now `mesh`.
    pub fn track(&mut self, entity: Entity, name: String, mesh: &TriMesh) {
        self.bodies.retain(|r| r.entity != entity);
        let damage = BodyDamage::new(name, mesh);
        self.bodies.push(Recorded { entity, damage, last: mesh.clone(), pending: 0 });
    }

    /// Continues recording `entity` from `damage` (restored), its mesh now `mesh`.
    fn resume(&mut self, entity: Entity, damage: BodyDamage, mesh: &TriMesh) {
        if let Some(r) = self.bodies.iter_mut().find(|r| r.entity == entity) {
            (r.damage, r.last, r.pending) = (damage, mesh.clone(), 0);
        }
    }

    /// A dent of `entity` was queued on the GPU path.
    pub fn queued(&mut self, entity: Entity) {
        if let Some(r) = self.bodies.iter_mut().find(|r| r.entity == entity) {
            r.pending += 1;
        }
    }

    /// `entity`'s mesh is now `now`, after `dents` dents (plus those queued on the GPU path).
    pub fn changed(&mut self, entity: Entity, now: &TriMesh, dents: u32) {
        let Some(r) = self.bodies.iter_mut().find(|r| r.entity == entity) else { return };
        let edit = match MeshEdit::between(&r.last, now) {
            Ok(edit) => edit,
            Err(e) => {
                error!(
                    "bevy_dentbend: {entity}'s damage record stops: its mesh changed in a way no record holds ({e})"
                );
                self.bodies.retain(|r| r.entity != entity);
                return;
            }
        };
        let after = MeshStamp::of(now);
        let dents = dents + std::mem::take(&mut r.pending);
        r.damage.records.push(DamageRecord::Dents(DentBatch {
            dents,
            impacts: Vec::new(),
            edit: Some(edit),
            after: after.hash,
            refinement: None,
        }));
        r.damage.final_mesh = after;
        r.last = now.clone();
    }

    /// `fracture` broke a body at `step`: its rest is its mesh from then on (a body the pattern
    /// took whole stops being recorded).
    pub fn fractured(&mut self, fracture: &BodyFracture<Entity>, step: u64) {
        let Some(r) = self.bodies.iter_mut().find(|r| r.entity == fracture.body) else { return };
        let Some(rest) = &fracture.rest else {
            warn!("bevy_dentbend: {} broke whole; its damage record ends with its last dents", fracture.body);
            self.bodies.retain(|r| r.entity != fracture.body);
            return;
        };
        let name = &r.damage.name;
        let pieces = fracture
            .pieces
            .iter()
            .map(|p| FracturePiece {
                name: format!("{name}/piece{}", p.id.index),
                index: p.id.index,
                shift: Vec3::ZERO,
                hash: content_hash(&p.mesh),
            })
            .collect();
        let after = MeshStamp::of(rest);
        r.damage.records.push(DamageRecord::Fracture(FractureRecord {
            frame: step,
            fracture: fracture.record,
            to_model: Vec3::ZERO,
            rest_shift: Vec3::ZERO,
            pieces,
            after: after.hash,
        }));
        r.damage.final_mesh = after;
        r.last = rest.clone();
    }

    /// Forgets `entity` (despawned).
    pub fn forget(&mut self, entity: Entity) {
        self.bodies.retain(|r| r.entity != entity);
    }

    /// Every recorded body's damage, in the order recording started.
    pub fn file(&self) -> DamageFile {
        DamageFile { scene: None, bodies: self.bodies.iter().map(|r| r.damage.clone()).collect() }
    }
}

/// Replays `damage` (saved from a body spawned with the mesh `entity` has now: its dents'
/// exact edits and its fractures) onto `entity`, a registered dentable body (or the entity
/// carrying its `Dentable`). Answered by a [`DamageRestored`].
#[derive(Message, Debug, Clone)]
pub struct RestoreDamage {
    /// The body.
    pub entity: Entity,
    /// Its saved damage (one body of a [`DamageFile`]).
    pub damage: BodyDamage,
}

/// The outcome of a [`RestoreDamage`]: `Err` names why nothing changed (another mesh, a body
/// not registered yet, a damage file that does not replay).
#[derive(Message, Debug, Clone)]
pub struct DamageRestored {
    /// The body.
    pub entity: Entity,
    /// What happened.
    pub result: Result<(), String>,
}

/// Replays each [`RestoreDamage`] onto its body: the main world's mesh, the asset (without the
/// entity's scale), the collider (through [`MeshDented`]) and, on the GPU path, the resident
/// copy; the body's record, when it is recorded, continues from the restored damage.
pub(crate) fn restore_damage(
    mut requests: MessageReader<RestoreDamage>,
    mut world: ResMut<DentWorld>,
    mut meshes: ResMut<Assets<Mesh>>,
    link: Res<MainLink>,
    mut dented: MessageWriter<MeshDented>,
    mut restored: MessageWriter<DamageRestored>,
) {
    for request in requests.read() {
        let entity = world.mesh_of_owner(request.entity).unwrap_or(request.entity);
        let result = restore_one(&mut world, &mut meshes, &link, entity, &request.damage);
        match &result {
            Ok(moved) => {
                let moved = moved.clone();
                dented.write(MeshDented { entity, moved, topology_changed: true });
            }
            Err(e) => warn!("bevy_dentbend: {} keeps its mesh: {e}", request.entity),
        }
        restored.write(DamageRestored { entity: request.entity, result: result.map(|_| ()) });
    }
}

/// Restores `damage` onto registered body `entity`; the vertices of its new mesh. The asset
/// keeps its UVs and other attributes through every record, as it would have in play: the
/// vertices refinement added interpolate their edge's, a fracture's rest carries the broken
/// mesh's over ([`carry_step`]).
fn restore_one(
    world: &mut DentWorld,
    meshes: &mut Assets<Mesh>,
    link: &MainLink,
    entity: Entity,
    damage: &BodyDamage,
) -> Result<Vec<u32>, String> {
    let now = world.mesh(entity).ok_or("it is not a registered dentable body (yet)")?;
    let body = world.bodies.get(&entity).ok_or("it is not a registered dentable body")?;
    let scale = body.scale;
    let original = meshes.get(&body.mesh).ok_or("its mesh asset is gone")?;
    // The asset followed record by record, while it holds the body's mesh vertex for vertex.
    let mut working = (original.try_attributes().is_ok() && original.count_vertices() == now.vertex_count())
        .then(|| original.clone());
    let mut each = |step: ReplayStep<'_>| {
        if let Some(asset) = &mut working
            && let Err(e) = carry_step(asset, step, scale)
        {
            warn!("bevy_dentbend: {entity}'s restored mesh keeps positions and normals only ({e})");
            working = None;
        }
    };
    let replayed = replay_body_traced(damage, now, (DentForm::Edits, &Projectiles::new()), &mut each);
    let mesh = replayed.map_err(|e| e.to_string())?.mesh;
    let written = for_asset(&mesh, scale).map_err(|e| e.to_string())?;
    let mut asset = meshes.get_mut(&body.mesh).ok_or("its mesh asset is gone")?;
    match working {
        Some(mut carried) if carried.count_vertices() == written.vertex_count() => {
            write_dented(&mut carried, &written, &Refinement::default()).map_err(|e| e.to_string())?;
            *asset = carried;
        }
        _ if asset.count_vertices() == written.vertex_count() => {
            write_dented(&mut asset, &written, &Default::default()).map_err(|e| e.to_string())?;
        }
        _ => *asset = bevy_mesh(&written),
    }
    let layout = slab_layout(&asset).map_err(|e| e.to_string())?;
    let (handle, path) = (body.mesh.clone(), body.path);
    world.replace_mesh(entity, mesh.clone());
    world.damage.forget(entity);
    world.records.resume(entity, damage.clone(), &mesh);
    if path == DentPath::Gpu {
        link.send(ToRender::Register { entity, asset: handle.id(), mesh: mesh.clone(), layout });
    }
    Ok((0..mesh.vertex_count() as u32).collect())
}

/// Carries `asset`'s attributes (one value per vertex of the step's mesh before it, without the
/// entity's `scale`) over one replayed record: a refinement's new vertices take their edge's
/// ([`ReplayStep::splits`]), a fracture's rest the broken mesh's ([`carry_attributes`]); its positions,
/// normals and indices become the mesh after the step's.
///
/// # Errors
/// A mesh that cannot be unscaled, or an asset whose data left the main world.
fn carry_step(asset: &mut Mesh, step: ReplayStep<'_>, scale: Option<Vec3>) -> Result<(), String> {
    match step {
        ReplayStep::Edited { before, after } => {
            if after.vertex_count() == before.vertex_count() && after.faces() == before.faces() {
                return Ok(());
            }
            let refinement = Refinement {
                base_vertex_count: before.vertex_count(),
                base_face_count: before.face_count(),
                vertices: step.splits(),
                ..Default::default()
            };
            let after = for_asset(after, scale).map_err(|e| e.to_string())?;
            // With new vertices this writes the new faces too; a record may also rebuild the
            // faces over the same vertices (a progressive dent's surface).
            write_dented(asset, &after, &refinement).map_err(|e| e.to_string())?;
            if refinement.vertices.is_empty() {
                let indices = after.faces().iter().flatten().copied().collect();
                asset.try_insert_indices(bevy::mesh::Indices::U32(indices)).map_err(|e| e.to_string())?;
            }
            Ok(())
        }
        ReplayStep::Broke { before, rest, origins } => {
            let rest = for_asset(rest, scale).map_err(|e| e.to_string())?;
            let mut made = bevy_mesh(&rest);
            carry_attributes(&mut made, &Broken::new(asset, before.faces(), scale.unwrap_or(Vec3::ONE)), origins);
            *asset = made;
            Ok(())
        }
    }
}
