//! Registers dentable bodies and projectiles as their meshes become available, moves bodies to
//! the GPU path once Bevy's device is ready, and forgets despawned ones.

use bevy::prelude::*;

use crate::link::{GpuStatus, MainLink, ToRender};
use dentbend::TriMesh;

use crate::mesh_data::{SlabLayout, add_missing_normals, private_copy, slab_layout, tri_mesh, write_vertices};
use crate::scale::{entity_scale, rigid, scaled};
use crate::world::BodyInfo;
use crate::{DentPath, DentProjectile, DentWorld, Dentable};
use bevy::mesh::VertexAttributeValues;

/// Marks an entity the plug-in has registered.
#[derive(Component, Debug, Clone, Copy)]
pub struct DentRegistered;

/// Marks an entity the plug-in refused, with the reason (also logged once).
#[derive(Component, Debug, Clone)]
pub struct DentRefused(pub String);

/// Marks a registered body the plug-in dents, but not well, with what is wrong and what fixes it
/// (also logged once, naming the entity by its `Name`).
#[derive(Component, Debug, Clone)]
pub struct DentAdvice(pub String);

/// How many times its largest dent (`DentMaterial::cap`) a kernel-only body's mean edge may be
/// before its dents are called too coarse for it. A dent's map spans the projectile's contact
/// footprint and about 1.5 cap (3σ, σ = cap/2) around it; past 8 caps most dents land inside a
/// face or two and move a few vertices, or none.
const COARSE_EDGE_CAPS: f32 = 8.0;

pub(crate) type Unregistered = (Without<DentRegistered>, Without<DentRefused>);

/// Projectiles (that do not dent themselves) not registered yet.
type NewProjectile = (With<DentProjectile>, Without<Dentable>, Unregistered);

/// `entity`'s mesh made ready to register: a private copy (normals added when missing), its
/// triangles for the damage API and its vertex layout for the GPU path; otherwise why its mesh
/// cannot `verb` ("dent", "bend").
pub(crate) fn prepare_mesh(entity: Entity, mesh: &Mesh, verb: &str) -> Result<(Mesh, TriMesh, SlabLayout), String> {
    let mut copy = private_copy(mesh);
    let prepared = tri_mesh(&copy).and_then(|tri| {
        if add_missing_normals(&mut copy, &tri)? {
            info!("bevy_dentbend: {entity}'s mesh had no normals; smooth normals were added");
        }
        let mut tri = with_asset_normals(entity, &copy, tri);
        let snapped = close_seams(&mut tri);
        if snapped > 0 {
            info!("bevy_dentbend: {entity}'s mesh had {snapped} seam vertices a few ulps off their twins; snapped together");
            write_vertices(&mut copy, tri.positions(), tri.normals())?;
        }
        let layout = slab_layout(&copy)?;
        Ok((tri, layout))
    });
    prepared.map(|(tri, layout)| (copy, tri, layout)).map_err(|e| format!("its mesh cannot {verb}: {e}"))
}

/// Seam vertices closer than this fraction of a mesh's bounding-box diagonal to their twin are
/// snapped onto it: generators and exporters leave a UV seam or a pole a few ulps apart (Bevy's
/// UV sphere computes its seam column at 2π), which the dent stages would refuse.
const SEAM_SNAP_FRACTION: f32 = 1e-5;

/// `tri` carrying `mesh`'s own normals (so surfaces no dent touched keep their shading bit for
/// bit, hard edges included); its smooth normals when the asset's are unusable.
fn with_asset_normals(entity: Entity, mesh: &Mesh, tri: TriMesh) -> TriMesh {
    let Ok(Some(VertexAttributeValues::Float32x3(normals))) = mesh.try_attribute_option(Mesh::ATTRIBUTE_NORMAL) else {
        return tri;
    };
    let normals: Vec<Vec3> = normals.iter().map(|&n| Vec3::from_array(n)).collect();
    match TriMesh::with_normals(tri.positions().to_vec(), tri.faces().to_vec(), normals) {
        Ok(authored) => authored,
        Err(e) => {
            warn!("bevy_dentbend: {entity}'s normals are unusable ({e}); smooth normals are used instead");
            tri
        }
    }
}

/// Snaps `tri`'s nearly coincident seam vertices together ([`SEAM_SNAP_FRACTION`]); how many
/// moved.
fn close_seams(tri: &mut TriMesh) -> usize {
    let (lo, hi) = tri.bounds();
    tri.snap_seams(SEAM_SNAP_FRACTION * lo.distance(hi)).unwrap_or(0)
}

/// Registers each new dentable body once its mesh asset is loaded ([`prepare_mesh`]): the
/// mesh on the [`Dentable`]'s own entity, or, when it has none, on the one descendant that has
/// one (a glTF scene puts each mesh on a child of its node).
pub(crate) fn register_dentables(
    mut commands: Commands,
    mut world: ResMut<DentWorld>,
    mut meshes: ResMut<Assets<Mesh>>,
    new: Query<(Entity, &Dentable, Option<&Name>), Unregistered>,
    with_mesh: Query<(&Mesh3d, &GlobalTransform)>,
    children: Query<&Children>,
) {
    for (owner, dentable, name) in &new {
        let entity = match mesh_entity(owner, &with_mesh, &children) {
            Ok(Some(entity)) => entity,
            Ok(None) => continue,
            Err(reason) => {
                refuse(&mut commands, owner, reason);
                continue;
            }
        };
        let Ok((mesh3d, transform)) = with_mesh.get(entity) else { continue };
        let scale = match entity_scale(transform) {
            Ok(scale) => scale,
            Err(reason) => {
                refuse(&mut commands, owner, reason);
                continue;
            }
        };
        let Some(mesh) = meshes.get(&mesh3d.0) else { continue };
        let prepared = prepare_mesh(entity, mesh, "dent").and_then(|(copy, tri, layout)| match scale {
            Some(s) => scaled(&tri, s).map(|tri| (copy, tri, layout)).map_err(|e| format!("its scaled mesh: {e}")),
            None => Ok((copy, tri, layout)),
        });
        let (copy, tri, _) = match prepared {
            Ok(done) => done,
            Err(reason) => {
                refuse(&mut commands, owner, reason);
                continue;
            }
        };
        if let Some(advice) = coarseness_advice(dentable, &tri) {
            let who = name.map_or_else(|| format!("{owner}"), |n| format!("{n} ({owner})"));
            warn!("bevy_dentbend: {who}: {advice}");
            commands.entity(owner).insert(DentAdvice(format!("{who}: {advice}")));
        }
        let handle = meshes.add(copy);
        // The GPU path writes the dented mesh straight into Bevy's slab: unscaled bodies only.
        let gpu_servable = dentable.gpu_servable() && scale.is_none();
        let info = BodyInfo { mesh: handle.clone(), path: DentPath::Cpu, gpu_servable, owner, scale };
        let settings = dentable.settings.clone();
        if let Err(e) = world.insert_dentable(entity, tri, rigid(transform), settings, info) {
            refuse(&mut commands, owner, format!("its dent settings are invalid: {e}"));
            continue;
        }
        if let Err(e) = world.targets.set_fracture(entity, dentable.fracture.clone()) {
            world.remove(entity);
            refuse(&mut commands, owner, format!("it cannot break: {e} (give it a closed mesh, or no fracture)"));
            continue;
        }
        commands.entity(entity).insert(Mesh3d(handle));
        commands.entity(owner).insert(DentRegistered);
    }
}

/// The entity whose mesh the [`Dentable`] on `owner` dents: `owner` when it has a [`Mesh3d`],
/// else its one descendant that has one; `None` while there is none (a scene still spawning).
///
/// # Errors
/// Several descendants with meshes: which one is meant, and the fix.
fn mesh_entity(
    owner: Entity,
    with_mesh: &Query<(&Mesh3d, &GlobalTransform)>,
    children: &Query<&Children>,
) -> Result<Option<Entity>, String> {
    if with_mesh.contains(owner) {
        return Ok(Some(owner));
    }
    let found: Vec<Entity> = children.iter_descendants(owner).filter(|&c| with_mesh.contains(c)).collect();
    match found.as_slice() {
        [] => Ok(None),
        [one] => Ok(Some(*one)),
        many => Err(format!(
            "it has no Mesh3d and {} descendants do ({many:?}): put a Dentable on each mesh entity that should dent",
            many.len()
        )),
    }
}

/// Why `tri` is too coarse for `dentable`'s dents, and the fix: only for kernel-only dents (the
/// paper's, on the GPU path), which move the vertices as they are; refinement makes any mesh
/// take a dent's shape.
fn coarseness_advice(dentable: &Dentable, tri: &TriMesh) -> Option<String> {
    let cap = dentable.settings.material.cap;
    let edge = tri.mean_edge_length();
    (dentable.kernels_only() && edge > COARSE_EDGE_CAPS * cap).then(|| {
        format!(
            "its mesh is too coarse for its dents (edges of {edge:.3} m on average, dents at most {cap:.3} m deep): \
             they move few vertices or none; give it `Dentable::new` (the game dent), whose refinement \
             splits the faces under each dent, or a finer mesh"
        )
    })
}

/// Registers each new projectile once its mesh asset is loaded.
pub(crate) fn register_projectiles(
    mut commands: Commands,
    mut world: ResMut<DentWorld>,
    meshes: Res<Assets<Mesh>>,
    new: Query<(Entity, &Mesh3d, &GlobalTransform), NewProjectile>,
) {
    for (entity, mesh3d, transform) in &new {
        let Some(mesh) = meshes.get(&mesh3d.0) else { continue };
        let surface = entity_scale(transform).and_then(|scale| {
            let tri = tri_mesh(mesh).map_err(|e| e.to_string())?;
            match scale {
                Some(s) => scaled(&tri, s).map_err(|e| e.to_string()),
                None => Ok(tri),
            }
        });
        match surface {
            Ok(tri) => {
                world.insert_projectile(entity, tri);
                commands.entity(entity).insert(DentRegistered);
            }
            Err(e) => refuse(&mut commands, entity, format!("its mesh cannot dent others: {e}")),
        }
    }
}

/// Leaves `entity` out for `reason`, logged once.
pub(crate) fn refuse(commands: &mut Commands, entity: Entity, reason: String) {
    warn!("bevy_dentbend: {entity} is left out: {reason}");
    commands.entity(entity).insert(DentRefused(reason));
}

/// Moves every CPU-path body the GPU path can serve to it once Bevy's device is ready (its mesh
/// as it is now becomes resident).
pub(crate) fn promote_to_gpu(mut world: ResMut<DentWorld>, link: Res<MainLink>, meshes: Res<Assets<Mesh>>) {
    if !matches!(link.status(), GpuStatus::Ready(_)) {
        return;
    }
    let ready: Vec<(Entity, Handle<Mesh>)> = world
        .bodies
        .iter()
        .filter(|(_, b)| b.path == DentPath::Cpu && b.gpu_servable)
        .map(|(e, b)| (*e, b.mesh.clone()))
        .collect();
    for (entity, handle) in ready {
        let (Some(mesh), Some(tri)) = (meshes.get(&handle), world.mesh(entity)) else { continue };
        let layout = match slab_layout(mesh) {
            Ok(layout) => layout,
            Err(e) => {
                warn!("bevy_dentbend: {entity} stays on the CPU path: {e}");
                if let Some(body) = world.bodies.get_mut(&entity) {
                    body.gpu_servable = false;
                }
                continue;
            }
        };
        link.send(ToRender::Register { entity, asset: handle.id(), mesh: tri.clone(), layout });
        world.set_path(entity, DentPath::Gpu);
    }
}

/// Forgets bodies that were despawned or lost their component; an entity that lost it may get
/// it back and is registered again.
pub(crate) fn forget_removed(
    mut commands: Commands,
    mut world: ResMut<DentWorld>,
    link: Res<MainLink>,
    mut dentables: RemovedComponents<Dentable>,
    mut projectiles: RemovedComponents<DentProjectile>,
) {
    for owner in dentables.read() {
        let entity = world.mesh_of_owner(owner).unwrap_or(owner);
        if world.remove(entity) {
            link.send(ToRender::Forget(entity));
        }
        commands.entity(owner).try_remove::<(DentRegistered, DentRefused, DentAdvice)>();
    }
    for entity in projectiles.read() {
        // A dentable body's surface is its dentable mesh: only a plain projectile goes.
        if !world.bodies.contains_key(&entity) {
            world.remove(entity);
            commands.entity(entity).try_remove::<(DentRegistered, DentRefused, DentAdvice)>();
        }
    }
}
