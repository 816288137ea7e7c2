//! Fracture: a body that dents can also break, along a prescored pattern placed at the hit
//! that breaks it; a step's fractures and their pieces are read back for the engine to make
//! bodies of.

use std::collections::HashMap;
use std::ffi::c_int;
use std::sync::Arc;

use dentbend::TriMesh;
use dentbend::damage::{BodyFracture, PieceId, piece_hull_points};
use dentbend::fracture::{FractureCause, FracturePattern, FractureSettings, PatternParams};
use dentbend::glam::{Affine3A, Vec3};
use dentbend::mesh::{Asset, MassProperties};

use crate::damage::DbDamage;
use crate::handles;
use crate::mesh::DbMesh;
use crate::status::{Failure, guarded, guarded_value};

/// `DbFracture::cause`: an impact's energy passed the toughness.
pub const DB_FRACTURE_ENERGY: c_int = 0;
/// `DbFracture::cause`: the body's accumulated dent passed its dent limit.
pub const DB_FRACTURE_DENT: c_int = 1;

/// How a body breaks; start from `db_fracture_settings_default`. A body breaks when one
/// impact's energy passes `toughness`, or its accumulated dent passes `dent_limit`, whichever
/// comes first (at least one of them finite).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct DbFractureSettings {
    /// Voronoi cells of the pattern, 1..=256 (finer near the hit).
    pub cells: u32,
    /// Seed of the pattern's cells: the same seed, cells and radius give the same pattern.
    pub seed: u64,
    /// Radius of the pattern around the hit, m (> 0, at most 1e6): the part within it breaks
    /// off.
    pub radius: f32,
    /// Kinetic energy one impact must remove along its normal to break the body, J (>= 0);
    /// `INFINITY`: impacts alone never break it.
    pub toughness: f32,
    /// Accumulated dent distance that breaks the body, m (>= 0); `INFINITY`: dents never
    /// break it.
    pub dent_limit: f32,
    /// Density of the pieces of a body of mass 0 (static), kg/m^3 (> 0, at most 1e6); a moving
    /// body's pieces take its own density.
    pub density: f32,
    /// Most pieces one break may make, 1..=65536: a break that would make more is refused
    /// (the step fails, nothing changes).
    pub max_pieces: u32,
}

/// Settings that break along a pattern of `cells` cells (seeded with `seed`, `radius` m)
/// when an impact removes `toughness` J or the dents add up to `dent_limit` m (`INFINITY`
/// for either: never for that reason); pieces of a static body at 1000 kg/m^3, at most 1024
/// pieces.
#[unsafe(no_mangle)]
pub extern "C" fn db_fracture_settings_default(
    cells: u32,
    seed: u64,
    radius: f32,
    toughness: f32,
    dent_limit: f32,
) -> DbFractureSettings {
    DbFractureSettings {
        cells,
        seed,
        radius,
        toughness,
        dent_limit,
        density: 1000.0,
        max_pieces: dentbend::fracture::DEFAULT_MAX_PIECES,
    }
}

/// A body a step broke. Its pieces are read with `db_damage_piece`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct DbFracture {
    /// The body that broke: it keeps this id with its rest, unless `whole`.
    pub body: u64,
    /// The body that broke it.
    pub projectile: u64,
    /// The fracture's number (counted by the context from 0): its pieces' `fracture`.
    pub number: u64,
    /// `DB_FRACTURE_ENERGY` or `DB_FRACTURE_DENT`.
    pub cause: c_int,
    /// Non-zero: the pattern took the whole body; the context no longer has it (remove it).
    pub whole: c_int,
    /// The energy the breaking hit removed along its normal, J.
    pub energy: f32,
    /// The body's accumulated dent when it broke, m.
    pub accumulated_dent: f32,
    /// The body's mesh -> world transform when it broke, 3x4 column by column: it places the
    /// rest and the pieces, which are in the body's mesh coordinates.
    pub to_world: [f32; 12],
    /// The rest's mass, kg, at the body's density (0 when `whole`).
    pub rest_mass: f32,
    /// The rest's centre of mass, mesh coordinates, m.
    pub rest_center_of_mass: [f32; 3],
    /// The rest's inertia about its centre of mass, mesh axes, kg*m^2, 3x3 column by column.
    pub rest_inertia: [f32; 9],
    /// How many pieces broke loose.
    pub piece_count: usize,
    /// Non-zero when the projectile takes the velocity below: it went on through the body,
    /// which gave way, with the energy the break used up taken from it.
    pub has_projectile_velocity: c_int,
    /// The projectile's new linear velocity, world, m/s.
    pub projectile_linear_velocity: [f32; 3],
    /// The projectile's new angular velocity, world, rad/s.
    pub projectile_angular_velocity: [f32; 3],
}

/// One piece that broke loose, for the engine to make a body of: a closed mesh in the broken
/// body's mesh coordinates (place it with the fracture's `to_world`) and its mass properties.
/// The arrays are the library's, valid until the next step (for a context) or message (for a
/// replica).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct DbPiece {
    /// The fracture's number.
    pub fracture: u64,
    /// The piece's index among the fracture's pieces.
    pub index: u32,
    /// Mass, kg.
    pub mass: f32,
    /// Centre of mass, mesh coordinates, m.
    pub center_of_mass: [f32; 3],
    /// Inertia about the centre of mass, mesh axes, kg*m^2, 3x3 column by column.
    pub inertia: [f32; 9],
    /// Velocity of its centre of mass, world, m/s (zero on a replica: velocities are the
    /// game's state to replicate).
    pub linear_velocity: [f32; 3],
    /// Angular velocity, world, rad/s (zero on a replica).
    pub angular_velocity: [f32; 3],
    /// Its vertices, 3 floats each, mesh coordinates.
    pub positions: *const f32,
    /// Its vertex normals, 3 floats each (a body's authored normals carried over, a cut's own
    /// normal on a cut face whose vertices are its own: a mesh split at its hard edges).
    pub normals: *const f32,
    /// Its UVs, 2 floats a vertex, when the body's mesh came with UVs (null otherwise): the
    /// surface's carried over, a cut's projected on its plane at the mesh's texel density.
    pub uvs: *const f32,
    /// Points for its convex collider, 3 floats each, `vertex_count` of them: the vertices
    /// shrunk by 3 % toward the centre of mass, so pieces start clear of the rest and of each
    /// other.
    pub hull_points: *const f32,
    /// How many vertices.
    pub vertex_count: usize,
    /// Its triangles, 3 indices each.
    pub indices: *const u32,
    /// How many triangles.
    pub triangle_count: usize,
}

/// One of a step's fractures as [`DbDamage::fractures`] gives it: the fracture, the body's mesh
/// -> world transform when it broke, its pieces' collider points, and its pieces' assets when
/// the body had attributes.
pub type StepFracture<'a> = (&'a BodyFracture<u64>, Affine3A, &'a [Vec<Vec3>], Option<&'a [Asset]>);

/// A fracture read back: the library's, with each piece's collider points and, for a body with
/// attributes, each piece's asset.
#[derive(Debug)]
pub(crate) struct MadeFracture {
    pub(crate) fracture: BodyFracture<u64>,
    /// The body's mesh -> world transform when it broke.
    pub(crate) to_world: Affine3A,
    /// Each piece's collider points.
    pub(crate) hulls: Vec<Vec<Vec3>>,
    /// Each piece's asset (UVs, normals carried over), when the body had attributes.
    pub(crate) assets: Option<Vec<Asset>>,
}

impl MadeFracture {
    pub(crate) fn new(fracture: BodyFracture<u64>, to_world: Affine3A, assets: Option<Vec<Asset>>) -> Self {
        let hulls = fracture.pieces.iter().map(|p| piece_hull_points(&p.mesh, p.mass.center)).collect();
        Self { fracture, to_world, hulls, assets }
    }

    /// Piece `k`'s asset: its carried attributes, or its mesh alone.
    pub(crate) fn asset(&self, k: usize) -> Asset {
        match &self.assets {
            Some(assets) => assets[k].clone(),
            None => Asset::from_mesh(self.fracture.pieces[k].mesh.clone()),
        }
    }
}

/// The patterns of a context's breakable bodies, by their parameters: bodies that break alike
/// share one. A pattern no body uses any more is dropped when another is kept.
#[derive(Debug, Default)]
pub(crate) struct Patterns(HashMap<(u32, u64, u32), Arc<FracturePattern>>);

impl Patterns {
    /// The pattern of `params`: the one kept, or a new one (kept only once a body takes it).
    fn get(&self, params: PatternParams) -> Result<Arc<FracturePattern>, Failure> {
        if let Some(pattern) = self.0.get(&key(params)) {
            return Ok(pattern.clone());
        }
        Ok(Arc::new(FracturePattern::new(params).map_err(|e| Failure::invalid(e.to_string()))?))
    }

    /// Keeps `pattern`, which a body took, for bodies that break alike; drops the patterns no
    /// body holds.
    fn keep(&mut self, pattern: Option<Arc<FracturePattern>>) {
        self.0.retain(|_, p| Arc::strong_count(p) > 1);
        if let Some(pattern) = pattern {
            self.0.insert(key(pattern.params()), pattern);
        }
    }
}

/// A pattern's parameters as a key (the radius by its bits).
fn key(params: PatternParams) -> (u32, u64, u32) {
    (params.cells, params.seed, params.radius.to_bits())
}

/// A limit given as a float: `INFINITY` for none; NaN and negative values refused.
fn limit(value: f32, what: &str, unit: &str) -> Result<Option<f32>, Failure> {
    match value {
        f32::INFINITY => Ok(None),
        v if v.is_finite() && v >= 0.0 => Ok(Some(v)),
        v => Err(Failure::invalid(format!("{what} {v} {unit} must be finite and >= 0, or INFINITY for never"))),
    }
}

impl DbDamage {
    /// Makes body `id` break as `settings` say (`None`: it never breaks). Bodies given the
    /// same pattern parameters share one pattern.
    ///
    /// # Errors
    /// A body that does not dent, settings out of range (both limits infinite among them), or
    /// a mesh that is not closed (it bounds no solid to break). Nothing changes then.
    pub fn set_fracture(&mut self, id: u64, settings: Option<&DbFractureSettings>) -> Result<(), Failure> {
        if self.targets.mesh(id).is_none() {
            return Err(Failure::invalid(format!("body {id} does not dent (add it as a body that dents first)")));
        }
        let made = match settings {
            None => None,
            Some(s) => {
                let params = PatternParams { cells: s.cells, seed: s.seed, radius: s.radius };
                let made = FractureSettings {
                    pattern: self.patterns.get(params)?,
                    toughness: limit(s.toughness, "toughness", "J")?,
                    dent_limit: limit(s.dent_limit, "dent_limit", "m")?,
                    density: s.density,
                    max_pieces: s.max_pieces,
                };
                made.validate().map_err(|e| Failure::invalid(e.to_string()))?;
                Some(made)
            }
        };
        let pattern = made.as_ref().map(|m| m.pattern.clone());
        self.targets.set_fracture(id, made).map_err(|e| Failure::invalid(e.to_string()))?;
        self.patterns.keep(pattern);
        Ok(())
    }

    /// The last step's fractures, each with the body's mesh -> world transform when it broke,
    /// its pieces' collider points and, for a body with attributes, its pieces' assets (UVs and
    /// normals carried over).
    pub fn fractures(&self) -> impl ExactSizeIterator<Item = StepFracture<'_>> {
        self.fractures.iter().map(|f| (&f.fracture, f.to_world, f.hulls.as_slice(), f.assets.as_deref()))
    }

    /// Stops naming piece `id` on the replication stream (the game removed it).
    pub fn forget_piece(&mut self, id: PieceId) {
        self.stream.forget_piece(id);
    }

    /// The last step's fracture `index`, or the failure naming the count.
    fn made_fracture(&self, index: usize) -> Result<&MadeFracture, Failure> {
        let count = self.fractures.len();
        self.fractures.get(index).ok_or_else(|| Failure::invalid(format!("fracture {index} of {count}")))
    }
}

/// A fracture's (or a replica piece's) mass properties in C's layout.
fn mass_parts(mass: &MassProperties) -> (f32, [f32; 3], [f32; 9]) {
    (mass.mass, mass.center.to_array(), mass.inertia.to_cols_array())
}

/// A piece in C's layout: its id, mesh, mass properties, velocities (linear, angular) and
/// collider points, all borrowed.
pub(crate) fn piece_view(
    id: PieceId,
    mesh: &TriMesh,
    asset: Option<&Asset>,
    mass: &MassProperties,
    velocity: (Vec3, Vec3),
    hull: &[Vec3],
) -> DbPiece {
    let (mass, center_of_mass, inertia) = mass_parts(mass);
    let normals = asset.map_or(mesh.normals(), Asset::shading_normals);
    let uvs = asset.and_then(|a| a.attributes().uvs.first()).map_or(std::ptr::null(), |uv| uv.as_ptr().cast());
    DbPiece {
        fracture: id.fracture,
        index: id.index,
        mass,
        center_of_mass,
        inertia,
        linear_velocity: velocity.0.to_array(),
        angular_velocity: velocity.1.to_array(),
        positions: mesh.positions().as_ptr().cast(),
        normals: normals.as_ptr().cast(),
        uvs,
        hull_points: hull.as_ptr().cast(),
        vertex_count: mesh.vertex_count(),
        indices: mesh.faces().as_ptr().cast(),
        triangle_count: mesh.face_count(),
    }
}

/// Writes `value` to `out`.
///
/// # Safety
/// `out` is null or writable.
pub(crate) unsafe fn write_out<T>(out: *mut T, value: T) -> Result<(), Failure> {
    if out.is_null() {
        return Err(Failure::null("out"));
    }
    // SAFETY: not null, writable by the caller's contract.
    unsafe { out.write(value) };
    Ok(())
}

/// Makes body `id` breakable with `settings` (copied), or never breakable again when
/// `settings` is null. Its mesh must be closed.
///
/// # Safety
/// `damage` is null or live; `settings` is null or points to a `DbFractureSettings`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_set_fracture(
    damage: *mut DbDamage,
    id: u64,
    settings: *const DbFractureSettings,
) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let damage = unsafe { DbDamage::get_mut(damage)? };
        // SAFETY: null or a `DbFractureSettings` by the caller's contract.
        damage.set_fracture(id, unsafe { settings.as_ref() })
    })
}

/// How many bodies the last step broke (0 for a null or dead context).
///
/// # Safety
/// `damage` is null or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_fracture_count(damage: *const DbDamage) -> usize {
    // SAFETY: the caller's contract.
    guarded_value(|| unsafe { DbDamage::get(damage) }.map(|d| d.fractures.len())).unwrap_or(0)
}

/// Writes the last step's fracture `index` to `out`.
///
/// # Safety
/// `damage` is null or live; `out` is null or points to a writable `DbFracture`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_fracture(damage: *const DbDamage, index: usize, out: *mut DbFracture) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let made = unsafe { DbDamage::get(damage)? }.made_fracture(index)?;
        let f = &made.fracture;
        let (rest_mass, rest_center_of_mass, rest_inertia) =
            f.rest_mass.as_ref().map_or((0.0, [0.0; 3], [0.0; 9]), mass_parts);
        let (linear, angular) = f.projectile_velocity.unwrap_or((Vec3::ZERO, Vec3::ZERO));
        let fracture = DbFracture {
            body: f.body,
            projectile: f.projectile,
            number: f.number,
            cause: match f.cause {
                FractureCause::Energy => DB_FRACTURE_ENERGY,
                FractureCause::Dent => DB_FRACTURE_DENT,
            },
            whole: c_int::from(f.rest.is_none()),
            energy: f.energy,
            accumulated_dent: f.accumulated_dent,
            to_world: made.to_world.to_cols_array(),
            rest_mass,
            rest_center_of_mass,
            rest_inertia,
            piece_count: f.pieces.len(),
            has_projectile_velocity: c_int::from(f.projectile_velocity.is_some()),
            projectile_linear_velocity: linear.to_array(),
            projectile_angular_velocity: angular.to_array(),
        };
        // SAFETY: the caller's contract.
        unsafe { write_out(out, fracture) }
    })
}

/// Writes piece `piece` of the last step's fracture `fracture` to `out`; its arrays are
/// valid until the next step.
///
/// # Safety
/// `damage` is null or live; `out` is null or points to a writable `DbPiece`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_piece(
    damage: *const DbDamage,
    fracture: usize,
    piece: usize,
    out: *mut DbPiece,
) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        let made = unsafe { DbDamage::get(damage)? }.made_fracture(fracture)?;
        let count = made.fracture.pieces.len();
        let p = made.fracture.pieces.get(piece).ok_or_else(|| Failure::invalid(format!("piece {piece} of {count}")))?;
        let asset = made.assets.as_ref().map(|a| &a[piece]);
        let velocity = (p.linear_velocity, p.angular_velocity);
        let view = piece_view(p.id, &p.mesh, asset, &p.mass, velocity, &made.hulls[piece]);
        // SAFETY: the caller's contract.
        unsafe { write_out(out, view) }
    })
}

/// A new mesh, a copy of piece `piece` of the last step's fracture `fracture` with its
/// normals and UVs: to add it as a body that dents (`db_damage_add_body`, placed by the fracture's `to_world`), or to hand
/// it as a projectile's surface. Null on failure. Free it with `db_mesh_free`.
///
/// # Safety
/// `damage` is null or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_piece_mesh(damage: *const DbDamage, fracture: usize, piece: usize) -> *mut DbMesh {
    let mesh = guarded_value(|| {
        // SAFETY: the caller's contract.
        let made = unsafe { DbDamage::get(damage)? }.made_fracture(fracture)?;
        let count = made.fracture.pieces.len();
        if piece >= count {
            return Err(Failure::invalid(format!("piece {piece} of {count}")));
        }
        Ok(made.asset(piece))
    });
    mesh.map_or(std::ptr::null_mut(), |asset| handles::make(DbMesh { asset, moved: Vec::new() }))
}

/// Stops naming piece (`fracture_number`, `index`) on the context's replication stream: call
/// when the game removes the piece (clients call `db_replica_forget_piece`).
///
/// # Safety
/// `damage` is null or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn db_damage_forget_piece(damage: *mut DbDamage, fracture_number: u64, index: u32) -> c_int {
    guarded(|| {
        // SAFETY: the caller's contract.
        unsafe { DbDamage::get_mut(damage)? }.forget_piece(PieceId { fracture: fracture_number, index });
        Ok(())
    })
}
