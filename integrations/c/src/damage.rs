//! Damage for games: bodies keyed by the caller's 64-bit ids, one step's hits decided, dented
//! and applied at once (`dentbend::Damage` on a `TargetSet`), the results read back without
//! copies.

use std::collections::HashMap;
use std::ffi::c_int;

use dentbend::TriMesh;
use dentbend::damage::{AppliedDent, CpuBackend, Damage, DamageError, DamagePlan, Hit, TargetSet};
use dentbend::dent::{BodyState, DentSettings, Impact, Surface, VolumeMode};
use dentbend::glam::{Affine3A, Mat3, Vec3};
use dentbend::mesh::Asset;
use dentbend::record::{DamageRecorder, RecordForms};

use crate::attributes::Attributes;
use crate::fracture::{MadeFracture, Patterns};
use crate::handles;
use crate::mesh::DbMesh;
use crate::status::{DB_ERR_DENT, Failure, guarded, guarded_value, hand_out};

/// Most hits one step may take (a larger count is taken for garbage).
pub const DB_MAX_HITS: usize = 1 << 20;

/// The bodies of a world that dent, their damage state and the last step's dents (opaque in
/// C).
#[derive(Debug)]
pub struct DbDamage {
    pub(crate) targets: TargetSet<u64>,
    pub(crate) damage: Damage<u64>,
    step: u64,
    /// The last step's dents.
    dents: Vec<AppliedDent<u64>>,
    /// The vertices the last step moved or added, per body.
    pub(crate) moved: HashMap<u64, Vec<u32>>,
    /// The replication stream of the bodies it carries, and the last step's message.
    pub(crate) stream: crate::replication::Stream,
    /// The damage of the bodies it records, and the last save.
    pub(crate) recorder: DamageRecorder<u64>,
    pub(crate) saved: Vec<u8>,
    /// The last step's fractures.
    pub(crate) fractures: Vec<MadeFracture>,
    /// The fracture patterns built so far.
    pub(crate) patterns: Patterns,
    /// The attributes (UVs, authored normals) of the bodies that have them.
    pub(crate) attributes: Attributes<u64>,
}

/// How a body dents: the dent's depth from the normal impact speed, and its shape. Start from
/// `db_dent_settings_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct DbDentSettings {
    /// Normal impact speed below which nothing dents, m/s.
    pub threshold_speed: f32,
    /// Dent depth per m/s above the threshold, m per m/s.
    pub depth_per_speed: f32,
    /// Deepest dent, m.
    pub max_depth: f32,
    /// Width of the dent's smoothing, m; 0 for half the dent's depth.
    pub sigma: f32,
    /// Non-zero: put each dent's volume back as a raised rim around it.
    pub preserve_volume: c_int,
    /// Non-zero: hits of one body while the contact lasts deepen one dent.
    pub progressive: c_int,
}

/// A body's motion before the step, world coordinates.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct DbBodyState {
    /// Centre of mass, m.
    pub center_of_mass: [f32; 3],
    /// Linear velocity, m/s.
    pub linear_velocity: [f32; 3],
    /// Angular velocity, rad/s.
    pub angular_velocity: [f32; 3],
    /// Mass, kg; 0 for a body that cannot move (static ground, a wall).
    pub mass: f32,
    /// World inverse inertia, 1/(kg*m^2), 3x3 column by column (ignored when `mass` is 0).
    pub inverse_inertia: [f32; 9],
}

/// One contact of the step, as the engine reported it before resolving it.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct DbHit {
    /// The body that may dent.
    pub target: u64,
    /// The body that hit it (a body of `db_damage_add_body` or `db_damage_add_projectile`).
    pub projectile: u64,
    /// Contact point, world, m.
    pub point: [f32; 3],
    /// Contact normal, world, into the target.
    pub normal: [f32; 3],
    /// The target's state before the step.
    pub target_state: DbBodyState,
    /// The projectile's state before the step.
    pub projectile_state: DbBodyState,
    /// The projectile's surface (its own coordinates), not freed before the step returns.
    pub projectile_surface: *const DbMesh,
    /// The projectile's mesh -> world transform, 3x4 column by column (the three axes, then the
    /// translation).
    pub projectile_to_world: [f32; 12],
}

/// One dent a step made.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct DbAppliedDent {
    /// The dented body.
    pub target: u64,
    /// The body that dented it.
    pub projectile: u64,
    /// Contact point, world, m.
    pub point: [f32; 3],
    /// Dent distance the hit earned, m.
    pub dent_distance: f32,
    /// Largest displacement the dent made, m (below `dent_distance` where the crossing guard
    /// limited it).
    pub depth_made: f32,
    /// How far to move the projectile into the dent, world, m (zero: the C API does not ask
    /// for it yet).
    pub projectile_offset: [f32; 3],
    /// Vertices the dent moved.
    pub moved_vertices: usize,
}

/// Settings for a body that dents `depth_per_speed` m per m/s of normal impact speed above
/// `threshold_speed`, at most `max_depth` m: automatic smoothing, no rim, not progressive.
#[unsafe(no_mangle)]
pub extern "C" fn db_dent_settings_default(
    threshold_speed: f32,
    depth_per_speed: f32,
    max_depth: f32,
) -> DbDentSettings {
    DbDentSettings { threshold_speed, depth_per_speed, max_depth, sigma: 0.0, preserve_volume: 0, progressive: 0 }
}

impl Default for DbDamage {
    fn default() -> Self {
        Self {
            targets: TargetSet::default(),
            damage: Damage::default(),
            step: 0,
            dents: Vec::new(),
            moved: HashMap::new(),
            stream: Default::default(),
            recorder: DamageRecorder::new(RecordForms::EDITS),
            saved: Vec::new(),
            fractures: Vec::new(),
            patterns: Patterns::default(),
            attributes: Attributes::default(),
        }
    }
}

impl DbDamage {
    /// The context behind `handle`, checked as meshes are.
    ///
    /// # Safety
    /// `handle` is null or a context of `db_damage_new` not freed yet.
    pub(crate) unsafe fn get<'a>(handle: *const DbDamage) -> Result<&'a DbDamage, Failure> {
        // SAFETY: the caller's contract.
        unsafe { handles::get(handle, "damage") }
    }

    /// As [`get`](Self::get), mutably.
    ///
    /// # Safety
    /// As [`get`](Self::get), and no other reference to it is in use.
    pub(crate) unsafe fn get_mut<'a>(handle: *mut DbDamage) -> Result<&'a mut DbDamage, Failure> {
        // SAFETY: the caller's contract.
        unsafe { handles::get_mut(handle, "damage") }
    }
}

/// A new damage context with no body. Free it with `db_damage_free`.
#[unsafe(no_mangle)]
pub extern "C" fn db_damage_new() -> *mut DbDamage {
    handles::make(DbDamage::default())
}

/// Frees `damage` (null: nothing); as `db_mesh_free` for a second free.
///
/// # Safety
/// `damage` is null or a context of `db_damage_new` not freed yet.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_free(damage: *mut DbDamage) {
    // SAFETY: the caller's contract.
    unsafe { handles::free(damage, "db_damage_free") }
}

impl DbDamage {
    /// Adds body `id` (replacing one of that id, with its fracture settings), which dents:
    /// `asset`'s mesh (its own coordinates, m), placed by `to_world`, denting as `settings`
    /// say. Its attributes (UVs, authored normals, ...) follow every dent and fracture. A
    /// recorded body replaced starts its record again from the new mesh, under the same name.
    ///
    /// # Errors
    /// A mesh or pose the target set refuses (the body set is unchanged then).
    pub fn add_body(
        &mut self,
        id: u64,
        asset: Asset,
        to_world: Affine3A,
        settings: DentSettings,
    ) -> Result<(), Failure> {
        let mesh = asset.mesh().clone();
        self.targets.insert(id, mesh, to_world, settings).map_err(|e| Failure::invalid(e.to_string()))?;
        self.attributes.keep(id, asset);
        self.damage.forget(id);
        self.stream.forget(id);
        self.moved.remove(&id);
        let recorded = self.recorder.body(id).map(|b| b.name.clone());
        if let (Some(name), Some(mesh)) = (recorded, self.targets.mesh(id)) {
            self.recorder.track(id, name, mesh);
        }
        Ok(())
    }

    /// Adds body `id`, which hits others but does not dent (its surface comes with each hit).
    pub fn add_projectile(&mut self, id: u64) {
        self.targets.insert_rigid(id);
    }

    /// Moves body `id` to `to_world`, as the engine moved it.
    ///
    /// # Errors
    /// A body that does not dent, or a pose the target set refuses.
    pub fn set_pose(&mut self, id: u64, to_world: Affine3A) -> Result<(), Failure> {
        if self.targets.mesh(id).is_none() {
            return Err(Failure::invalid(format!("body {id} does not dent (add it as a body that dents first)")));
        }
        self.targets.set_pose(id, to_world).map_err(|e| Failure::invalid(e.to_string()))
    }

    /// Body `id`'s mesh (its own coordinates), if it dents.
    pub fn mesh(&self, id: u64) -> Option<&TriMesh> {
        self.targets.mesh(id)
    }

    /// Body `id`'s authored normals, brought through its dents, when it was added with them.
    pub fn shading_normals(&self, id: u64) -> Option<&[Vec3]> {
        self.attributes.normals(id)
    }

    /// Body `id`'s first UV set, new vertices interpolated, when it was added with UVs.
    pub fn uvs(&self, id: u64) -> Option<&[dentbend::glam::Vec2]> {
        self.attributes.uvs(id)
    }

    /// The last step's dents.
    pub fn dents(&self) -> &[AppliedDent<u64>] {
        &self.dents
    }

    /// The vertices of body `id` the last step (or restore) moved or added, ascending.
    pub fn moved(&self, id: u64) -> &[u32] {
        self.moved.get(&id).map_or(&[], Vec::as_slice)
    }

    /// Decides, makes and applies the dents and fractures of one step's `hits`, all of them or
    /// none: on failure no body changes. A body a fracture took whole is removed.
    ///
    /// # Errors
    /// A projectile pose that is not finite or a hit on a body the context does not know
    /// (`DB_ERR_INVALID_ARGUMENT`), a dent or fracture that cannot be made (`DB_ERR_DENT`), a
    /// record or message that cannot be made.
    pub fn step(&mut self, list: &[Hit<'_, u64>]) -> Result<(), Failure> {
        if let Some(k) = list.iter().position(|h| !h.projectile_surface.to_world.is_finite()) {
            return Err(Failure::invalid(format!("hit {k}: projectile_to_world is not finite")));
        }
        let mut state = self.damage.clone();
        let step = self.step + 1;
        let plan = state.plan(&self.targets, list, step, &mut CpuBackend).map_err(|e| match e {
            DamageError::UnknownBody { .. } => Failure::invalid(e.to_string()),
            _ => Failure { status: DB_ERR_DENT, message: e.to_string() },
        })?;
        // What may fail comes first, before any body changes: the record (it fails on a mesh
        // changed behind its back), then the message, made from the meshes the step gives.
        let mut recorder = self.recorder.clone();
        recorder.record(&self.targets, list, &plan).map_err(|e| Failure::invalid(e.to_string()))?;
        let DamagePlan { dents, targets, fractures, .. } = plan;
        let mut followed = self.attributes.follow(&targets, &fractures)?;
        let after =
            |key: u64| targets.iter().find(|t| t.key == key).map(|t| &t.mesh).or_else(|| self.targets.mesh(key));
        let surface = |key: u64| list.iter().find(|h| h.projectile == key).map(|h| h.projectile_surface.mesh);
        self.stream.after_step(&dents, &fractures, after, surface)?;

        // Everything made: commit.
        let mut moved: HashMap<u64, Vec<u32>> = self.targets.apply(targets).into_iter().collect();
        self.attributes.commit(&mut followed);
        let mut made = Vec::with_capacity(fractures.len());
        for (fracture, assets) in fractures.into_iter().zip(followed.pieces) {
            let body = fracture.body;
            let to_world = self.targets.pose(body).unwrap_or(Affine3A::IDENTITY);
            self.targets.apply_fracture(&fracture);
            match self.targets.mesh(body) {
                // The rest: every vertex is new.
                Some(rest) => {
                    moved.insert(body, (0..rest.vertex_count() as u32).collect());
                }
                None => {
                    moved.remove(&body);
                    state.forget(body);
                    self.stream.forget(body);
                }
            }
            made.push(MadeFracture::new(fracture, to_world, assets));
        }
        self.damage = state;
        self.recorder = recorder;
        self.step = step;
        self.dents = dents;
        self.moved = moved;
        self.fractures = made;
        Ok(())
    }
}

/// Reads a 3x4 mesh -> world transform, column by column; rigid within rounding.
///
/// # Safety
/// `pose` is null or holds 12 floats.
unsafe fn pose(pose: *const f32) -> Result<Affine3A, Failure> {
    if pose.is_null() {
        return Err(Failure::null("to_world"));
    }
    // SAFETY: not null, 12 floats by the caller's contract.
    let values: [f32; 12] = unsafe { *pose.cast::<[f32; 12]>() };
    Ok(Affine3A::from_cols_array(&values))
}

/// Adds body `id` (replacing one of that id, with its fracture settings), which dents: a copy
/// of `mesh` (its own coordinates, m), placed by `to_world` (12 floats, 3x4 column by column)
/// and denting as `settings` says.
///
/// # Safety
/// `damage` and `mesh` are null or live; `to_world` is null or holds 12 floats; `settings` is
/// null or points to a `DbDentSettings`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_add_body(
    damage: *mut DbDamage,
    id: u64,
    mesh: *const DbMesh,
    to_world: *const f32,
    settings: *const DbDentSettings,
) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let (damage, mesh, to_world) =
            unsafe { (DbDamage::get_mut(damage)?, DbMesh::get(mesh, "mesh")?, pose(to_world)?) };
        if settings.is_null() {
            return Err(Failure::null("settings"));
        }
        // SAFETY: not null, a `DbDentSettings` by the caller's contract.
        let settings = dent_settings(unsafe { &*settings });
        damage.add_body(id, mesh.asset.clone(), to_world, settings)
    })
}

/// The library's settings for `settings`.
pub fn dent_settings(settings: &DbDentSettings) -> DentSettings {
    let mut out = DentSettings::new(settings.threshold_speed, settings.depth_per_speed, settings.max_depth);
    if settings.sigma != 0.0 {
        out.params.sigma = Some(settings.sigma);
    }
    out.params.volume = if settings.preserve_volume != 0 { VolumeMode::Preserve } else { VolumeMode::Free };
    out.progressive = settings.progressive != 0;
    out
}

/// Adds body `id`, which hits others but does not dent (its surface comes with each hit).
///
/// # Safety
/// `damage` is null or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_add_projectile(damage: *mut DbDamage, id: u64) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        unsafe { DbDamage::get_mut(damage)? }.add_projectile(id);
        Ok(())
    })
}

/// Moves body `id` to `to_world` (12 floats, 3x4 column by column), as the engine moved it.
///
/// # Safety
/// `damage` is null or live; `to_world` is null or holds 12 floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_set_pose(damage: *mut DbDamage, id: u64, to_world: *const f32) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let (damage, to_world) = unsafe { (DbDamage::get_mut(damage)?, pose(to_world)?) };
        damage.set_pose(id, to_world)
    })
}

/// One hit of a step from its parts: both bodies' states checked, the impact made from the
/// contact. The error names the part at fault.
pub fn hit<'m>(
    target: u64,
    projectile: u64,
    point: Vec3,
    normal: Vec3,
    target_state: &DbBodyState,
    projectile_state: &DbBodyState,
    projectile_surface: Surface<'m>,
) -> Result<Hit<'m, u64>, String> {
    let target_state = body_state(target_state).map_err(|e| format!("target_state: {e}"))?;
    let projectile_state = body_state(projectile_state).map_err(|e| format!("projectile_state: {e}"))?;
    let impact = Impact::from_contact(point, normal, &target_state, &projectile_state).map_err(|e| e.to_string())?;
    Ok(Hit { target, projectile, impact, target_state, projectile_state, projectile_surface })
}

/// The library's state for `state`; a mass that is not finite and >= 0 is refused.
pub fn body_state(state: &DbBodyState) -> Result<BodyState, String> {
    if !(state.mass.is_finite() && state.mass >= 0.0) {
        return Err(format!("mass {} must be finite and >= 0 (0: a body that cannot move)", state.mass));
    }
    if state.mass == 0.0 {
        return Ok(BodyState::FIXED);
    }
    Ok(BodyState::moving(
        Vec3::from_array(state.center_of_mass),
        Vec3::from_array(state.linear_velocity),
        Vec3::from_array(state.angular_velocity),
        state.mass,
        Mat3::from_cols_array(&state.inverse_inertia),
    ))
}

/// Decides, makes and applies the dents and fractures of one step's `count` hits (all of them
/// or none: on failure no body changes). Afterwards `db_damage_dent_count` and `db_damage_dent`
/// read the dents made, `db_damage_fracture_count`, `db_damage_fracture` and `db_damage_piece`
/// the bodies that broke (a body the pattern took whole is removed), `db_damage_positions` and
/// `db_damage_moved` each body's new surface, and `db_damage_message` the step's message for
/// replicas.
///
/// # Safety
/// `damage` is null or live; `hits` is null (with `count` 0) or holds `count` `DbHit`s whose
/// surfaces are live meshes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_step(damage: *mut DbDamage, hits: *const DbHit, count: usize) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let damage = unsafe { DbDamage::get_mut(damage)? };
        if count > DB_MAX_HITS {
            return Err(Failure::invalid(format!("{count} hits: the limit is {DB_MAX_HITS}")));
        }
        let raw: &[DbHit] = match count {
            0 => &[],
            _ if hits.is_null() => return Err(Failure::null("hits")),
            // SAFETY: not null, `count` hits by the caller's contract.
            _ => unsafe { std::slice::from_raw_parts(hits, count) },
        };
        let mut list = Vec::with_capacity(raw.len());
        for (k, h) in raw.iter().enumerate() {
            let bad = |e: String| Failure::invalid(format!("hit {k}: {e}"));
            // SAFETY: the caller's contract.
            let surface =
                unsafe { DbMesh::get(h.projectile_surface, "projectile_surface") }.map_err(|f| bad(f.message))?;
            let to_world = Affine3A::from_cols_array(&h.projectile_to_world);
            let surface = Surface { mesh: surface.mesh(), to_world };
            let point = Vec3::from_array(h.point);
            let made = hit(
                h.target,
                h.projectile,
                point,
                Vec3::from_array(h.normal),
                &h.target_state,
                &h.projectile_state,
                surface,
            );
            list.push(made.map_err(bad)?);
        }
        damage.step(&list)
    })
}

/// How many dents the last step made (0 for a null or dead context).
///
/// # Safety
/// `damage` is null or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_dent_count(damage: *const DbDamage) -> usize {
    // SAFETY: the caller's contract.
    guarded_value(|| unsafe { DbDamage::get(damage) }.map(|d| d.dents.len())).unwrap_or(0)
}

/// Writes the last step's dent `index` to `out`.
///
/// # Safety
/// `damage` is null or live; `out` is null or points to a writable `DbAppliedDent`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_dent(damage: *const DbDamage, index: usize, out: *mut DbAppliedDent) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let damage = unsafe { DbDamage::get(damage)? };
        let count = damage.dents.len();
        let dent = damage.dents.get(index).ok_or_else(|| Failure::invalid(format!("dent {index} of {count}")))?;
        if out.is_null() {
            return Err(Failure::null("out"));
        }
        let made = DbAppliedDent {
            target: dent.target,
            projectile: dent.projectile,
            point: dent.impact.point.to_array(),
            dent_distance: dent.dent_distance,
            depth_made: dent.depth_made,
            projectile_offset: dent.projectile_offset.to_array(),
            moved_vertices: dent.moved_vertices,
        };
        // SAFETY: not null, writable by the caller's contract.
        unsafe { out.write(made) };
        Ok(())
    })
}

/// Reads one of body `id`'s arrays: its pointer, and its count into `count` (when not null);
/// null and 0 for an unknown body or an empty array.
///
/// # Safety
/// `damage` is null or live; `count` is null or writable.
unsafe fn body_array<T>(
    damage: *const DbDamage,
    id: u64,
    count: *mut usize,
    array: impl FnOnce(&DbDamage) -> Option<(*const T, usize)>,
) -> *const T {
    // SAFETY: the caller's contract.
    let found = guarded_value(|| {
        let damage = unsafe { DbDamage::get(damage)? };
        array(damage).ok_or_else(|| Failure::invalid(format!("body {id} does not dent")))
    });
    // SAFETY: the caller's contract.
    unsafe { hand_out(found, count) }
}

/// Body `id`'s positions (3 floats a vertex, its own coordinates), the vertex count written to
/// `vertex_count`; valid until the next `db_damage_step` (whether or not it succeeds) or
/// other change of the context.
///
/// # Safety
/// `damage` is null or live; `vertex_count` is null or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_positions(damage: *const DbDamage, id: u64, vertex_count: *mut usize) -> *const f32 {
    // SAFETY: the caller's contract.
    unsafe {
        body_array(damage, id, vertex_count, |d| {
            d.targets.mesh(id).map(|m| (m.positions().as_ptr().cast(), m.vertex_count()))
        })
    }
}

/// Body `id`'s vertex normals (its authored ones brought through its dents, when its mesh came
/// with them), as `db_damage_positions`.
///
/// # Safety
/// As `db_damage_positions`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_normals(damage: *const DbDamage, id: u64, vertex_count: *mut usize) -> *const f32 {
    // SAFETY: the caller's contract.
    unsafe {
        body_array(damage, id, vertex_count, |d| {
            let mesh = d.targets.mesh(id)?;
            let normals = d.attributes.normals(id).unwrap_or(mesh.normals());
            Some((normals.as_ptr().cast(), normals.len()))
        })
    }
}

/// Body `id`'s UVs (2 floats a vertex: its mesh's, new vertices interpolated), as
/// `db_damage_positions`; null and 0 for a body whose mesh came without UVs.
///
/// # Safety
/// As `db_damage_positions`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_uvs(damage: *const DbDamage, id: u64, vertex_count: *mut usize) -> *const f32 {
    // SAFETY: the caller's contract.
    unsafe {
        body_array(damage, id, vertex_count, |d| {
            d.targets.mesh(id)?;
            Some(d.attributes.uvs(id).map_or((std::ptr::null(), 0), |uvs| (uvs.as_ptr().cast(), uvs.len())))
        })
    }
}

/// Body `id`'s triangles (3 indices each), the count written to `triangle_count`; a step that
/// refines the body changes them.
///
/// # Safety
/// As `db_damage_positions`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_indices(damage: *const DbDamage, id: u64, triangle_count: *mut usize) -> *const u32 {
    // SAFETY: the caller's contract.
    unsafe {
        body_array(damage, id, triangle_count, |d| {
            d.targets.mesh(id).map(|m| (m.faces().as_ptr().cast(), m.face_count()))
        })
    }
}

/// The vertices of body `id` the last step moved or added (ascending), their count written to
/// `count` (0 when the step left it alone).
///
/// # Safety
/// As `db_damage_positions`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_moved(damage: *const DbDamage, id: u64, count: *mut usize) -> *const u32 {
    // SAFETY: the caller's contract.
    unsafe {
        body_array(damage, id, count, |d| {
            d.targets.mesh(id)?;
            Some(d.moved.get(&id).map_or((std::ptr::null(), 0), |m| (m.as_ptr(), m.len())))
        })
    }
}
