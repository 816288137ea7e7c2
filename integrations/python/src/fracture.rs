//! Fracture in Python: `Damage.set_fracture`'s settings, and the `Fracture`, `Piece` and
//! `ReplicaFracture` objects a step (or a replica's message) breaks bodies into.

use dentbend::TriMesh;
use dentbend::damage::{BodyFracture, PieceId};
use dentbend::fracture::FractureCause;
use dentbend::glam::{Affine3A, Mat3, Mat4, Vec3};
use dentbend::mesh::{Asset, MassProperties};
use dentbend_c::{DbFractureSettings, ReplicaBreak, db_fracture_settings_default};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;

use crate::arrays::{positions_out, rows_out, uvs_out};

type Triple = (f32, f32, f32);

/// The C API's fracture settings from Python's arguments (`None` limits: never for that
/// cause); the context checks them.
pub fn settings(
    cells: u32,
    seed: u64,
    radius: f32,
    toughness: Option<f32>,
    dent_limit: Option<f32>,
    density: f32,
    max_pieces: u32,
) -> DbFractureSettings {
    let never = |v: Option<f32>| v.unwrap_or(f32::INFINITY);
    // An explicit infinity means what `None` does; NaN is left for the context to refuse.
    DbFractureSettings {
        density,
        max_pieces,
        ..db_fracture_settings_default(cells, seed, radius, never(toughness), never(dent_limit))
    }
}

/// One piece that broke loose: a closed mesh in the broken body's own coordinates (place it
/// with the fracture's `to_world`) and its mass properties.
#[pyclass(module = "dentbend", frozen, get_all)]
pub struct Piece {
    /// The number of the fracture that made it.
    fracture: u64,
    /// Its index among that fracture's pieces.
    index: u32,
    /// Its vertices, `(N, 3)` float32, the body's mesh coordinates, m.
    positions: Py<PyArray2<f32>>,
    /// Its triangles, `(M, 3)` uint32.
    faces: Py<PyArray2<u32>>,
    /// Its vertex normals, `(N, 3)` float32 (the body's authored normals carried over, a cut's
    /// normal on its faces).
    normals: Py<PyArray2<f32>>,
    /// Its UVs, `(N, 2)` float32, when the body had UVs (the surface's carried over, a cut's
    /// projected on its plane at the body's texel density); `None` otherwise.
    uvs: Option<Py<PyArray2<f32>>>,
    /// Points for its convex collider, `(N, 3)` float32: the vertices shrunk 3 % toward the
    /// centre of mass, so that pieces start clear of each other.
    hull_points: Py<PyArray2<f32>>,
    /// Mass, kg.
    mass: f32,
    /// Centre of mass, mesh coordinates, m.
    center_of_mass: Triple,
    /// Inertia about the centre of mass, mesh axes, `(3, 3)` float32, kg m^2.
    inertia: Py<PyArray2<f32>>,
    /// Velocity of its centre of mass, world, m/s (zero on a replica).
    linear_velocity: Triple,
    /// Angular velocity, world, rad/s (zero on a replica).
    angular_velocity: Triple,
}

#[pymethods]
impl Piece {
    fn __repr__(&self, py: Python<'_>) -> String {
        let vertices = self.positions.bind(py).len().unwrap_or(0);
        format!("Piece(fracture={}, index={}, mass={:.3}, vertices={vertices})", self.fracture, self.index, self.mass)
    }
}

/// A matrix as a new `(R, C)` float32 array, row by row.
fn matrix_out<const R: usize, const C: usize>(py: Python<'_>, rows: [[f32; C]; R]) -> Py<PyArray2<f32>> {
    let flat: Vec<f32> = rows.as_flattened().to_vec();
    Array2::from_shape_vec((R, C), flat).expect("R x C values").into_pyarray(py).unbind()
}

/// A 3x3 matrix, row by row.
fn mat3_rows(m: Mat3) -> [[f32; 3]; 3] {
    m.transpose().to_cols_array_2d()
}

/// A piece's Python object.
fn piece(
    py: Python<'_>,
    id: PieceId,
    mesh: &TriMesh,
    asset: Option<&Asset>,
    mass: &MassProperties,
    velocity: (Vec3, Vec3),
    hull: &[Vec3],
) -> PyResult<Py<Piece>> {
    let normals = asset.map_or(mesh.normals(), Asset::shading_normals);
    let uvs = asset.and_then(|a| a.attributes().uvs.first());
    let made = Piece {
        fracture: id.fracture,
        index: id.index,
        positions: positions_out(py, mesh.positions().to_vec()).unbind(),
        faces: rows_out(py, mesh.faces().to_vec()).unbind(),
        normals: positions_out(py, normals.to_vec()).unbind(),
        uvs: uvs.map(|u| uvs_out(py, u).unbind()),
        hull_points: positions_out(py, hull.to_vec()).unbind(),
        mass: mass.mass,
        center_of_mass: mass.center.into(),
        inertia: matrix_out(py, mat3_rows(mass.inertia)),
        linear_velocity: velocity.0.into(),
        angular_velocity: velocity.1.into(),
    };
    Py::new(py, made)
}

/// A body a step broke.
#[pyclass(module = "dentbend", frozen, get_all)]
pub struct Fracture {
    /// The body that broke: it keeps this id with its rest, unless `whole`.
    body: u64,
    /// The body that broke it.
    projectile: u64,
    /// The fracture's number (counted by the context from 0): its pieces' `fracture`.
    number: u64,
    /// Why it broke: `"energy"` (an impact passed the toughness) or `"dent"` (the dents passed
    /// the dent limit).
    cause: &'static str,
    /// Whether the pattern took the whole body (the context no longer has it).
    whole: bool,
    /// The energy the breaking hit removed along its normal, J.
    energy: f32,
    /// The body's accumulated dent when it broke, m.
    accumulated_dent: f32,
    /// The body's mesh -> world transform when it broke, `(4, 4)` float32: it places the rest
    /// and the pieces.
    to_world: Py<PyArray2<f32>>,
    /// The rest's mass, kg (`None` when `whole`).
    rest_mass: Option<f32>,
    /// The rest's centre of mass, mesh coordinates, m (`None` when `whole`).
    rest_center_of_mass: Option<Triple>,
    /// The rest's inertia about its centre of mass, mesh axes, `(3, 3)` float32, kg m^2 (`None`
    /// when `whole`).
    rest_inertia: Option<Py<PyArray2<f32>>>,
    /// The pieces that broke loose.
    pieces: Vec<Py<Piece>>,
    /// The projectile's new (linear m/s, angular rad/s) velocity, world, when it went on
    /// through the body that gave way; `None` for a projectile that takes no impulse.
    projectile_velocity: Option<(Triple, Triple)>,
}

#[pymethods]
impl Fracture {
    fn __repr__(&self) -> String {
        format!(
            "Fracture(body={}, projectile={}, number={}, cause={:?}, whole={}, pieces={})",
            self.body,
            self.projectile,
            self.number,
            self.cause,
            if self.whole { "True" } else { "False" },
            self.pieces.len()
        )
    }
}

/// A fracture's Python object.
pub fn fracture(
    py: Python<'_>,
    f: &BodyFracture<u64>,
    to_world: Affine3A,
    hulls: &[Vec<Vec3>],
    assets: Option<&[Asset]>,
) -> PyResult<Fracture> {
    let pieces = f
        .pieces
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let asset = assets.map(|a| &a[k]);
            piece(py, p.id, &p.mesh, asset, &p.mass, (p.linear_velocity, p.angular_velocity), &hulls[k])
        })
        .collect::<PyResult<_>>()?;
    Ok(Fracture {
        body: f.body,
        projectile: f.projectile,
        number: f.number,
        cause: match f.cause {
            FractureCause::Energy => "energy",
            FractureCause::Dent => "dent",
        },
        whole: f.rest.is_none(),
        energy: f.energy,
        accumulated_dent: f.accumulated_dent,
        to_world: matrix_out(py, Mat4::from(to_world).transpose().to_cols_array_2d()),
        rest_mass: f.rest_mass.map(|m| m.mass),
        rest_center_of_mass: f.rest_mass.map(|m| m.center.into()),
        rest_inertia: f.rest_mass.map(|m| matrix_out(py, mat3_rows(m.inertia))),
        pieces,
        projectile_velocity: f.projectile_velocity.map(|(l, a)| (l.into(), a.into())),
    })
}

/// A fracture a replica's message replayed: the server's pieces, bit for bit.
#[pyclass(module = "dentbend", frozen, get_all)]
pub struct ReplicaFracture {
    /// The wire id of the body that broke: it keeps this id with its rest, unless `whole`.
    body: u32,
    /// Whether the pattern took the whole body (the replica no longer has it).
    whole: bool,
    /// The server's fracture number.
    number: u64,
    /// The pieces (their velocities zero: they are the game's state to replicate).
    pieces: Vec<Py<Piece>>,
}

#[pymethods]
impl ReplicaFracture {
    fn __repr__(&self) -> String {
        let whole = if self.whole { "True" } else { "False" };
        format!(
            "ReplicaFracture(body={}, number={}, whole={whole}, pieces={})",
            self.body,
            self.number,
            self.pieces.len()
        )
    }
}

/// A replica's fracture's Python object.
pub fn replica_fracture(py: Python<'_>, made: &ReplicaBreak) -> PyResult<ReplicaFracture> {
    let still = (Vec3::ZERO, Vec3::ZERO);
    let pieces = made
        .fracture
        .pieces
        .iter()
        .enumerate()
        .map(|(k, (id, p))| {
            piece(py, *id, &p.mesh, made.assets.as_ref().map(|a| &a[k]), &p.mass, still, &made.hulls[k])
        })
        .collect::<PyResult<_>>()?;
    Ok(ReplicaFracture { body: made.body, whole: made.whole, number: made.fracture.number, pieces })
}
