//! `dentbend.Replica`: a client's copy of the bodies a server's `Damage` carries on its
//! replication stream, following its snapshot and messages bit for bit (the C API's replica).

use dentbend::TriMesh;
use dentbend::damage::PieceId;
use dentbend_c::DbReplica;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::arrays::{list_out, positions_out, refused, rows_out, uvs_out};
use crate::damage::{Mesh, asset, dent_settings};
use crate::fracture::{ReplicaFracture, replica_fracture};

/// A client's copy of the bodies a server's stream carries: add the same base meshes,
/// settings and projectile surfaces as the server, `join` with its snapshot, then `apply` its
/// messages in order. A message out of order, repeated, truncated or for other meshes raises
/// `DentError` and changes nothing.
#[pyclass(module = "dentbend")]
#[derive(Default)]
pub struct Replica {
    inner: DbReplica,
}

#[pymethods]
impl Replica {
    #[new]
    fn new() -> Self {
        Self::default()
    }

    /// Adds the body the server carries as `wire_id`: its base mesh (the server's mesh when it
    /// was carried, with a game asset's `uvs` and authored `normals`, which follow every
    /// message) and the server's dent settings for it (the keywords of `Damage.add_body`).
    #[pyo3(signature = (wire_id, positions, faces, *, threshold_speed = 1.0, depth_per_speed = 0.01, max_depth = 0.1, sigma = None, preserve_volume = false, progressive = false, uvs = None, normals = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_body(
        &mut self,
        py: Python<'_>,
        wire_id: u32,
        positions: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        threshold_speed: f32,
        depth_per_speed: f32,
        max_depth: f32,
        sigma: Option<f32>,
        preserve_volume: bool,
        progressive: bool,
        uvs: Option<&Bound<'_, PyAny>>,
        normals: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let settings = dent_settings(threshold_speed, depth_per_speed, max_depth, sigma, preserve_volume, progressive)?;
        let asset = asset(py, positions, faces, uvs, normals)?;
        self.inner.add_body(wire_id, asset, &settings).map_err(|e| refused(e.message))
    }

    /// Adds projectile surface `shape_id` (the mesh the server named so with
    /// `Damage.add_wire_projectile`).
    fn add_projectile(&mut self, shape_id: u32, mesh: &Mesh) -> PyResult<()> {
        self.inner.add_projectile(shape_id, mesh.mesh().clone()).map_err(|e| refused(e.message))
    }

    /// Starts from a server's snapshot (`Damage.snapshot`), for a client joining late.
    fn join(&mut self, py: Python<'_>, snapshot: &[u8]) -> PyResult<()> {
        let inner = &mut self.inner;
        py.detach(|| inner.join(snapshot)).map_err(|e| refused(e.message))
    }

    /// Applies a server's message (`Damage.message`), in order: the bodies it names get the
    /// server's meshes bit for bit, its fractures the server's pieces (`fractures`).
    fn apply(&mut self, py: Python<'_>, message: &[u8]) -> PyResult<()> {
        let inner = &mut self.inner;
        py.detach(|| inner.apply(message)).map_err(|e| refused(e.message))
    }

    /// The bodies the last message broke. A body keeps its wire id with its rest, unless the
    /// pattern took it whole: then the replica no longer has it.
    fn fractures(&self, py: Python<'_>) -> PyResult<Vec<ReplicaFracture>> {
        self.inner.fractures().iter().map(|f| replica_fracture(py, f)).collect()
    }

    /// Body `wire_id`'s positions (its own coordinates, m), a new `(N, 3)` float32 array.
    fn positions<'py>(&self, py: Python<'py>, wire_id: u32) -> PyResult<Bound<'py, PyArray2<f32>>> {
        Ok(positions_out(py, self.mesh(wire_id)?.positions().to_vec()))
    }

    /// Body `wire_id`'s vertex normals (its authored ones brought along, when it was added
    /// with them), a new `(N, 3)` float32 array.
    fn normals<'py>(&self, py: Python<'py>, wire_id: u32) -> PyResult<Bound<'py, PyArray2<f32>>> {
        self.mesh(wire_id)?;
        Ok(positions_out(py, self.inner.normals(wire_id).unwrap_or_default().to_vec()))
    }

    /// Body `wire_id`'s UVs (new vertices interpolated), a new `(N, 2)` float32 array; `None`
    /// for a body added without UVs.
    fn uvs<'py>(&self, py: Python<'py>, wire_id: u32) -> PyResult<Option<Bound<'py, PyArray2<f32>>>> {
        self.mesh(wire_id)?;
        Ok(self.inner.uvs(wire_id).map(|uvs| uvs_out(py, uvs)))
    }

    /// Body `wire_id`'s triangles, a new `(M, 3)` uint32 array.
    fn faces<'py>(&self, py: Python<'py>, wire_id: u32) -> PyResult<Bound<'py, PyArray2<u32>>> {
        Ok(rows_out(py, self.mesh(wire_id)?.faces().to_vec()))
    }

    /// The vertices of body `wire_id` the last message or snapshot moved or added, ascending
    /// uint32.
    fn moved<'py>(&self, py: Python<'py>, wire_id: u32) -> PyResult<Bound<'py, PyArray1<u32>>> {
        self.mesh(wire_id)?;
        Ok(list_out(py, self.inner.moved(wire_id).to_vec()))
    }

    /// Stops keeping piece `index` of fracture `fracture` (the game removed it).
    fn forget_piece(&mut self, fracture: u64, index: u32) {
        self.inner.forget_piece(PieceId { fracture, index });
    }
}

impl Replica {
    /// Body `wire_id`'s mesh, or the error for a body the replica does not have.
    fn mesh(&self, wire_id: u32) -> PyResult<&TriMesh> {
        self.inner.mesh(wire_id).ok_or_else(|| refused(format!("the replica has no body {wire_id}")))
    }
}
