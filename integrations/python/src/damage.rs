//! `dentbend.Damage`: the bodies of a world that dent and break, keyed by the caller's 64-bit
//! ids, one step's hits decided, dented, broken and applied at once, with save and restore and
//! a replication stream (the C API's damage context).

use std::sync::Arc;

use dentbend::TriMesh;
use dentbend::damage::PieceId;
use dentbend::dent::{DentSettings, Surface};
use dentbend::glam::{Affine3A, Mat3, Vec3};
use dentbend::mesh::{Asset, FaceGroup, VertexAttributes};
use dentbend_c::{DbBodyState, DbDamage, DbDentSettings, body_state, hit};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::arrays::{list_out, pose, positions_out, refused, rows_out, uvs_out, vec3};
use crate::fracture::{Fracture, fracture};

/// A triangle mesh made once (checked, its normals computed) and shared by every hit that uses
/// it as a projectile's surface.
#[pyclass(module = "dentbend", frozen)]
pub struct Mesh {
    mesh: Arc<TriMesh>,
}

#[pymethods]
impl Mesh {
    /// A mesh from `(N, 3)` positions (m) and `(M, 3)` triangles (counter-clockwise seen from
    /// outside); both copied.
    #[new]
    fn new(py: Python<'_>, positions: &Bound<'_, PyAny>, faces: &Bound<'_, PyAny>) -> PyResult<Self> {
        let (p, f) = (crate::arrays::positions(positions, "positions")?, crate::arrays::faces(faces, "faces")?);
        let mesh = py.detach(|| TriMesh::new(p, f)).map_err(|e| refused(e.to_string()))?;
        Ok(Self { mesh: Arc::new(mesh) })
    }

    /// Its positions, a new `(N, 3)` float32 array.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        positions_out(py, self.mesh.positions().to_vec())
    }

    /// Its triangles, a new `(M, 3)` uint32 array.
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<u32>> {
        rows_out(py, self.mesh.faces().to_vec())
    }

    fn __repr__(&self) -> String {
        format!("Mesh(vertices={}, faces={})", self.mesh.vertex_count(), self.mesh.face_count())
    }
}

impl Mesh {
    /// The mesh.
    pub(crate) fn mesh(&self) -> &TriMesh {
        &self.mesh
    }
}

/// A body's asset from `(N, 3)` positions, `(M, 3)` faces and optional `(N, 2)` UVs and
/// `(N, 3)` authored normals, checked.
pub(crate) fn asset(
    py: Python<'_>,
    positions: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    uvs: Option<&Bound<'_, PyAny>>,
    normals: Option<&Bound<'_, PyAny>>,
) -> PyResult<Asset> {
    let (p, f) = (crate::arrays::positions(positions, "positions")?, crate::arrays::faces(faces, "faces")?);
    let attributes = VertexAttributes {
        uvs: uvs.map(|u| crate::arrays::uvs(u, "uvs")).transpose()?.into_iter().collect(),
        normals: normals.map(|n| crate::arrays::positions(n, "normals")).transpose()?,
        ..VertexAttributes::default()
    };
    let asset = py.detach(|| {
        let mesh = TriMesh::new(p, f).map_err(|e| e.to_string())?;
        let faces = mesh.face_count();
        Asset::new(mesh, attributes, vec![FaceGroup::default()], vec![0; faces]).map_err(|e| e.to_string())
    });
    asset.map_err(refused)
}

/// Dent settings from `Damage.add_body`'s keywords (`sigma` `None`: automatic smoothing; a
/// given width is checked as `dent`'s is, 0 refused).
pub(crate) fn dent_settings(
    threshold_speed: f32,
    depth_per_speed: f32,
    max_depth: f32,
    sigma: Option<f32>,
    preserve_volume: bool,
    progressive: bool,
) -> PyResult<DentSettings> {
    let mut settings = dentbend_c::dent_settings(&DbDentSettings {
        threshold_speed,
        depth_per_speed,
        max_depth,
        sigma: 0.0,
        preserve_volume: preserve_volume.into(),
        progressive: progressive.into(),
    });
    settings.params.sigma = sigma;
    settings.params.validate().map_err(|e| refused(e.to_string()))?;
    Ok(settings)
}

/// A body's motion before the step, world coordinates.
#[pyclass(module = "dentbend", frozen)]
#[derive(Clone)]
pub struct BodyState {
    state: DbBodyState,
}

#[pymethods]
impl BodyState {
    /// `mass` kg (0: a body that cannot move, the default), centre of mass (m), linear (m/s)
    /// and angular (rad/s) velocity, and the world inverse inertia (3x3, 1/(kg m^2); `None`:
    /// that of a solid ball of radius 0.5 m).
    #[new]
    #[pyo3(signature = (mass = 0.0, center_of_mass = None, linear_velocity = None, angular_velocity = None, inverse_inertia = None))]
    fn new(
        mass: f32,
        center_of_mass: Option<&Bound<'_, PyAny>>,
        linear_velocity: Option<&Bound<'_, PyAny>>,
        angular_velocity: Option<&Bound<'_, PyAny>>,
        inverse_inertia: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let optional = |v: Option<&Bound<'_, PyAny>>, what| v.map_or(Ok(Vec3::ZERO), |v| vec3(v, what));
        let inverse_inertia = match inverse_inertia {
            Some(m) => matrix3(m)?,
            // A solid ball of radius r: I = 2/5 m r^2.
            None if mass > 0.0 => Mat3::from_diagonal(Vec3::splat(1.0 / (0.4 * mass * 0.25))),
            None => Mat3::ZERO,
        };
        let state = DbBodyState {
            center_of_mass: optional(center_of_mass, "center_of_mass")?.to_array(),
            linear_velocity: optional(linear_velocity, "linear_velocity")?.to_array(),
            angular_velocity: optional(angular_velocity, "angular_velocity")?.to_array(),
            mass,
            inverse_inertia: inverse_inertia.to_cols_array(),
        };
        body_state(&state).map_err(refused)?;
        Ok(Self { state })
    }

    fn __repr__(&self) -> String {
        let s = &self.state;
        format!("BodyState(mass={}, linear_velocity={:?})", s.mass, s.linear_velocity)
    }
}

/// A 3x3 matrix of numbers.
fn matrix3(value: &Bound<'_, PyAny>) -> PyResult<Mat3> {
    let rows: Vec<Vec<f32>> = value
        .py()
        .import("numpy")?
        .call_method1("asarray", (value, "float32"))
        .and_then(|a| a.call_method0("tolist"))
        .and_then(|l| l.extract())
        .map_err(|_| refused("inverse_inertia must be a 3x3 matrix of numbers"))?;
    if rows.len() != 3 || rows.iter().any(|r| r.len() != 3) {
        return Err(refused("inverse_inertia must be a 3x3 matrix of numbers"));
    }
    Ok(Mat3::from_cols_array_2d(&[
        [rows[0][0], rows[1][0], rows[2][0]],
        [rows[0][1], rows[1][1], rows[2][1]],
        [rows[0][2], rows[1][2], rows[2][2]],
    ]))
}

/// One contact of the step, as the engine reported it before resolving it.
#[pyclass(module = "dentbend", frozen)]
pub struct Hit {
    target: u64,
    projectile: u64,
    point: Vec3,
    normal: Vec3,
    surface: Arc<TriMesh>,
    to_world: Affine3A,
    target_state: DbBodyState,
    projectile_state: DbBodyState,
}

#[pymethods]
impl Hit {
    /// Body `target` hit by body `projectile` at `point` (world, m), `normal` pointing into the
    /// target; the projectile's surface is `projectile_surface` (its own coordinates) placed by
    /// `projectile_to_world` (4x4; `None`: identity); the bodies' states before the step
    /// (`None`: a body that cannot move).
    #[new]
    #[pyo3(signature = (target, projectile, point, normal, projectile_surface, *, projectile_to_world = None, target_state = None, projectile_state = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        target: u64,
        projectile: u64,
        point: &Bound<'_, PyAny>,
        normal: &Bound<'_, PyAny>,
        projectile_surface: &Mesh,
        projectile_to_world: Option<&Bound<'_, PyAny>>,
        target_state: Option<&BodyState>,
        projectile_state: Option<&BodyState>,
    ) -> PyResult<Self> {
        let fixed = BodyState::new(0.0, None, None, None, None)?;
        Ok(Self {
            target,
            projectile,
            point: vec3(point, "point")?,
            normal: vec3(normal, "normal")?,
            surface: projectile_surface.mesh.clone(),
            to_world: pose(projectile_to_world, "projectile_to_world")?,
            target_state: target_state.unwrap_or(&fixed).state,
            projectile_state: projectile_state.unwrap_or(&fixed).state,
        })
    }
}

/// One dent a step made.
#[pyclass(module = "dentbend", frozen, get_all)]
pub struct AppliedDent {
    /// The dented body.
    target: u64,
    /// The body that dented it.
    projectile: u64,
    /// Contact point, world, m.
    point: (f32, f32, f32),
    /// Dent distance the hit earned, m.
    dent_distance: f32,
    /// Largest displacement the dent made, m.
    depth_made: f32,
    /// Vertices the dent moved.
    moved_vertices: usize,
}

#[pymethods]
impl AppliedDent {
    fn __repr__(&self) -> String {
        format!(
            "AppliedDent(target={}, projectile={}, dent_distance={:.6}, depth_made={:.6}, moved_vertices={})",
            self.target, self.projectile, self.dent_distance, self.depth_made, self.moved_vertices
        )
    }
}

/// The bodies of a world that dent and break, keyed by your 64-bit ids: each `step` decides,
/// makes and applies one step's dents and fractures at once (all of them or none).
#[pyclass(module = "dentbend")]
#[derive(Default)]
pub struct Damage {
    inner: DbDamage,
}

#[pymethods]
impl Damage {
    #[new]
    fn new() -> Self {
        Self::default()
    }

    /// Adds body `id` (replacing one of that id, with its fracture settings), which dents:
    /// `positions` `(N, 3)` and `faces` `(M, 3)` in its own coordinates (m), placed by
    /// `to_world` (4x4), denting `depth_per_speed` m per m/s of normal impact speed above
    /// `threshold_speed` m/s, at most `max_depth` m. A game asset's `uvs` `(N, 2)` and authored
    /// `normals` `(N, 3)` (vertices split at its seams and hard edges) follow every dent and
    /// fracture: new vertices interpolate them.
    #[pyo3(signature = (id, positions, faces, *, to_world = None, threshold_speed = 1.0, depth_per_speed = 0.01, max_depth = 0.1, sigma = None, preserve_volume = false, progressive = false, uvs = None, normals = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_body(
        &mut self,
        py: Python<'_>,
        id: u64,
        positions: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        to_world: Option<&Bound<'_, PyAny>>,
        threshold_speed: f32,
        depth_per_speed: f32,
        max_depth: f32,
        sigma: Option<f32>,
        preserve_volume: bool,
        progressive: bool,
        uvs: Option<&Bound<'_, PyAny>>,
        normals: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let to_world = pose(to_world, "to_world")?;
        let settings = dent_settings(threshold_speed, depth_per_speed, max_depth, sigma, preserve_volume, progressive)?;
        let asset = asset(py, positions, faces, uvs, normals)?;
        let inner = &mut self.inner;
        py.detach(|| inner.add_body(id, asset, to_world, settings)).map_err(|e| refused(e.message))
    }

    /// Adds body `id`, which hits others but does not dent (its surface comes with each hit).
    fn add_projectile(&mut self, id: u64) {
        self.inner.add_projectile(id);
    }

    /// Moves body `id` to `to_world` (4x4), as the engine moved it.
    fn set_pose(&mut self, id: u64, to_world: &Bound<'_, PyAny>) -> PyResult<()> {
        let to_world = pose(Some(to_world), "to_world")?;
        self.inner.set_pose(id, to_world).map_err(|e| refused(e.message))
    }

    /// Decides, makes and applies the dents of one step's `hits` (all of them or none: on an
    /// error no body changes); returns the dents made.
    fn step(&mut self, py: Python<'_>, hits: Vec<PyRef<'_, Hit>>) -> PyResult<Vec<AppliedDent>> {
        let mut list = Vec::with_capacity(hits.len());
        for (k, h) in hits.iter().enumerate() {
            let bad = |e: String| refused(format!("hit {k}: {e}"));
            let surface = Surface { mesh: &h.surface, to_world: h.to_world };
            let made = hit(h.target, h.projectile, h.point, h.normal, &h.target_state, &h.projectile_state, surface);
            list.push(made.map_err(bad)?);
        }
        let inner = &mut self.inner;
        py.detach(|| inner.step(&list)).map_err(|e| refused(e.message))?;
        Ok(self
            .inner
            .dents()
            .iter()
            .map(|d| AppliedDent {
                target: d.target,
                projectile: d.projectile,
                point: d.impact.point.into(),
                dent_distance: d.dent_distance,
                depth_made: d.depth_made,
                moved_vertices: d.moved_vertices,
            })
            .collect())
    }

    /// Body `id`'s positions (its own coordinates, m), a new `(N, 3)` float32 array.
    fn positions<'py>(&self, py: Python<'py>, id: u64) -> PyResult<Bound<'py, PyArray2<f32>>> {
        Ok(positions_out(py, self.mesh(id)?.positions().to_vec()))
    }

    /// Body `id`'s vertex normals (its authored ones brought through its dents, when it was
    /// added with them), a new `(N, 3)` float32 array.
    fn normals<'py>(&self, py: Python<'py>, id: u64) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let mesh = self.mesh(id)?;
        let normals = self.inner.shading_normals(id).unwrap_or(mesh.normals());
        Ok(positions_out(py, normals.to_vec()))
    }

    /// Body `id`'s UVs (new vertices interpolated), a new `(N, 2)` float32 array; `None` for a
    /// body added without UVs.
    fn uvs<'py>(&self, py: Python<'py>, id: u64) -> PyResult<Option<Bound<'py, PyArray2<f32>>>> {
        self.mesh(id)?;
        Ok(self.inner.uvs(id).map(|uvs| uvs_out(py, uvs)))
    }

    /// Body `id`'s triangles, a new `(M, 3)` uint32 array (a step that refines it changes them).
    fn faces<'py>(&self, py: Python<'py>, id: u64) -> PyResult<Bound<'py, PyArray2<u32>>> {
        Ok(rows_out(py, self.mesh(id)?.faces().to_vec()))
    }

    /// The vertices of body `id` the last step (or restore) moved or added, ascending uint32.
    fn moved<'py>(&self, py: Python<'py>, id: u64) -> PyResult<Bound<'py, PyArray1<u32>>> {
        self.mesh(id)?;
        Ok(list_out(py, self.inner.moved(id).to_vec()))
    }

    /// Makes body `id` break, as well as dent, along a prescored pattern of `cells` Voronoi
    /// cells (1..=256, seeded with `seed`) within `radius` m of the hit that breaks it: when one
    /// impact removes `toughness` J along its normal, or its dents add up to `dent_limit` m
    /// (at least one given). Pieces of a body of mass 0 get `density` kg/m^3; a break that would
    /// make more than `max_pieces` pieces fails its step. Its mesh must be closed.
    #[pyo3(signature = (id, *, cells, radius, seed = 0, toughness = None, dent_limit = None, density = 1000.0, max_pieces = 1024))]
    #[allow(clippy::too_many_arguments)]
    fn set_fracture(
        &mut self,
        py: Python<'_>,
        id: u64,
        cells: u32,
        radius: f32,
        seed: u64,
        toughness: Option<f32>,
        dent_limit: Option<f32>,
        density: f32,
        max_pieces: u32,
    ) -> PyResult<()> {
        let settings = crate::fracture::settings(cells, seed, radius, toughness, dent_limit, density, max_pieces);
        let inner = &mut self.inner;
        py.detach(|| inner.set_fracture(id, Some(&settings))).map_err(|e| refused(e.message))
    }

    /// Makes body `id` never break again.
    fn clear_fracture(&mut self, id: u64) -> PyResult<()> {
        self.inner.set_fracture(id, None).map_err(|e| refused(e.message))
    }

    /// The bodies the last step broke. A body keeps its id with its rest (its mesh, all of its
    /// vertices `moved`), unless the pattern took it whole: then the context no longer has it.
    fn fractures(&self, py: Python<'_>) -> PyResult<Vec<Fracture>> {
        self.inner.fractures().map(|(f, to_world, hulls, assets)| fracture(py, f, to_world, hulls, assets)).collect()
    }

    /// Stops naming piece `index` of fracture `fracture` on the replication stream (the game
    /// removed it).
    fn forget_piece(&mut self, fracture: u64, index: u32) {
        self.inner.forget_piece(PieceId { fracture, index });
    }

    /// Carries body `id` on the replication stream as `wire_id`: its mesh now is the base
    /// every `Replica` adds, with the same settings.
    fn replicate(&mut self, id: u64, wire_id: u32) -> PyResult<()> {
        self.inner.replicate(id, wire_id).map_err(|e| refused(e.message))
    }

    /// Names a projectile's surface `shape_id` on the stream: dents made by bodies with this
    /// mesh name it by id, and replicas add the same mesh under it.
    fn add_wire_projectile(&mut self, shape_id: u32, mesh: &Mesh) -> PyResult<()> {
        self.inner.add_wire_projectile(shape_id, &mesh.mesh).map_err(|e| refused(e.message))
    }

    /// The last step's message for the replicas (bytes; empty when the step changed no carried
    /// body, which `Replica.apply` takes as no change).
    fn message<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, self.inner.message())
    }

    /// A late joiner's start (bytes): every carried body's mesh now. Take it after the last
    /// step's message was sent.
    fn snapshot<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let snapshot = self.inner.snapshot().map_err(|e| refused(e.message))?;
        Ok(PyBytes::new(py, snapshot))
    }

    /// Records body `id`'s damage from now on, as the body `name` of the saved file.
    fn record(&mut self, id: u64, name: &str) -> PyResult<()> {
        self.inner.record(id, name).map_err(|e| refused(e.message))
    }

    /// The recorded bodies' damage as a damage file (JSON bytes).
    fn save<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let saved = self.inner.save().map_err(|e| refused(e.message))?;
        Ok(PyBytes::new(py, saved))
    }

    /// Gives body `id` the damage that the damage file `data`'s body `name` recorded (saved from
    /// a body with the mesh this one has now), with no simulation.
    fn restore(&mut self, py: Python<'_>, id: u64, data: &[u8], name: &str) -> PyResult<()> {
        let inner = &mut self.inner;
        py.detach(|| inner.restore(id, data, name)).map_err(|e| refused(e.message))
    }
}

impl Damage {
    /// Body `id`'s mesh, or the error for a body that does not dent.
    fn mesh(&self, id: u64) -> PyResult<&TriMesh> {
        self.inner.mesh(id).ok_or_else(|| refused(format!("body {id} does not dent")))
    }
}
