//! `dentbend.dent`: one projectile dents one target, arrays in and out.

use std::time::Instant;

use dentbend::TriMesh;
use dentbend::dent::{DentJob, DentParams, Impact, Refine, VolumeMode, dent_batch_tracked};
use dentbend::glam::Vec3;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::arrays::{faces, list_out, positions, positions_out, refused, rows_out, vec3};

/// What `dentbend.dent` made: the dented target's arrays and what the dent did.
#[pyclass(module = "dentbend", frozen, get_all)]
pub struct DentResult {
    /// The dented target's positions, `(N, 3)` float32, m: the input's vertices first, then any
    /// the refinement added.
    positions: Py<PyArray2<f32>>,
    /// Its triangles, `(M, 3)` uint32 (split input faces keep their row; pieces are appended).
    faces: Py<PyArray2<u32>>,
    /// Vertices the dent moved or added, ascending uint32.
    moved: Py<PyArray1<u32>>,
    /// Largest displacement of a vertex, m.
    max_displacement: f32,
    /// Fraction of the dent kept by the crossing guard (1.0: all of it).
    kept: f32,
    /// For each added vertex (`N - input count`, in order), the two input-or-earlier vertices
    /// of the edge it split, `(K, 2)` uint32.
    parents: Py<PyArray2<u32>>,
    /// Where along that edge each added vertex lies, `(K,)` float32 in (0, 1): its value of
    /// any per-vertex attribute is `(1 - t) * a + t * b`.
    fractions: Py<PyArray1<f32>>,
    /// For each output face, the input face it is part of, `(M,)` uint32 (copy per-face data
    /// from there).
    face_parents: Py<PyArray1<u32>>,
    /// The library's warnings (a refinement scaled back, ...).
    warnings: Vec<String>,
}

#[pymethods]
impl DentResult {
    fn __repr__(&self, py: Python<'_>) -> String {
        use numpy::PyUntypedArrayMethods;
        format!(
            "DentResult(vertices={}, faces={}, moved={}, max_displacement={:.6}, kept={})",
            self.positions.bind(py).shape()[0],
            self.faces.bind(py).shape()[0],
            self.moved.bind(py).len(),
            self.max_displacement,
            self.kept
        )
    }
}

/// How to refine: "auto" (the default: where the target is too coarse for the dent), "off"
/// (`False` too), or a longest edge in m.
fn refine_setting(value: &Bound<'_, PyAny>) -> PyResult<Refine> {
    if let Ok(text) = value.extract::<String>() {
        return match text.as_str() {
            "auto" => Ok(Refine::default()),
            "off" => Ok(Refine::Off),
            other => Err(refused(format!("refine={other:?}: use \"auto\", \"off\" or a longest edge in m"))),
        };
    }
    if let Ok(flag) = value.cast::<pyo3::types::PyBool>() {
        return Ok(if flag.is_true() { Refine::default() } else { Refine::Off });
    }
    match value.extract::<f32>() {
        Ok(edge) => Ok(Refine::MaxEdge(edge)),
        Err(_) => Err(refused("refine must be \"auto\", \"off\" or a longest edge in m")),
    }
}

/// Everything one dent needs, read from Python before the lock is released.
struct Request {
    target: (Vec<Vec3>, Vec<[u32; 3]>),
    projectile: (Vec<Vec3>, Vec<[u32; 3]>),
    impact: Impact,
    params: DentParams,
}

impl Request {
    #[allow(clippy::too_many_arguments)]
    fn read(
        target_positions: &Bound<'_, PyAny>,
        target_faces: &Bound<'_, PyAny>,
        projectile_positions: &Bound<'_, PyAny>,
        projectile_faces: &Bound<'_, PyAny>,
        point: &Bound<'_, PyAny>,
        normal: &Bound<'_, PyAny>,
        relative_velocity: &Bound<'_, PyAny>,
        dent_distance: f32,
        preserve_volume: bool,
        refine: &Bound<'_, PyAny>,
        sigma: Option<f32>,
        guard_crossings: bool,
    ) -> PyResult<Self> {
        let normal = vec3(normal, "normal")?;
        let impact = Impact {
            point: vec3(point, "point")?,
            normal,
            relative_velocity: match vec3(relative_velocity, "relative_velocity")? {
                v if v == Vec3::ZERO => normal,
                v => v,
            },
        };
        let mut params = DentParams::new(dent_distance);
        params.sigma = sigma;
        params.volume = if preserve_volume { VolumeMode::Preserve } else { VolumeMode::Free };
        params.refine = refine_setting(refine)?;
        params.guard_crossings = guard_crossings;
        params.validate().map_err(|e| refused(e.to_string()))?;
        Ok(Self {
            target: (positions(target_positions, "target_positions")?, faces(target_faces, "target_faces")?),
            projectile: (
                positions(projectile_positions, "projectile_positions")?,
                faces(projectile_faces, "projectile_faces")?,
            ),
            impact,
            params,
        })
    }
}

/// What one dent made, before it goes back to Python.
struct Made {
    mesh: TriMesh,
    moved: Vec<u32>,
    refinement: dentbend::mesh::Refinement,
    report: dentbend::dent::DentReport,
}

/// Makes the meshes and the dent (no Python object touched: runs without the lock).
fn run(request: Request) -> Result<Made, String> {
    let Request { target, projectile, impact, params } = request;
    let target = TriMesh::new(target.0, target.1).map_err(|e| format!("target: {e}"))?;
    let projectile = TriMesh::new(projectile.0, projectile.1).map_err(|e| format!("projectile: {e}"))?;
    let mut meshes = [target];
    let job = DentJob { target: 0, projectile: &projectile, impact, params };
    let outcome = dent_batch_tracked(&mut meshes, &[job]).map_err(|e| e.error.to_string())?;
    let [mesh] = meshes;
    Ok(Made {
        mesh,
        moved: outcome.moved.into_iter().next().unwrap_or_default(),
        refinement: outcome.refined.into_iter().next().unwrap_or_default(),
        report: outcome.reports.into_iter().next().unwrap_or_default(),
    })
}

/// Dents the target mesh where the projectile mesh hits it (both in world coordinates at the
/// moment of contact), at most `dent_distance` m deep, and returns the dented target as new
/// arrays; the inputs are not modified.
#[pyfunction]
#[pyo3(signature = (
    target_positions, target_faces, projectile_positions, projectile_faces, point, normal,
    relative_velocity, dent_distance, *, preserve_volume = false, refine = None, sigma = None,
    guard_crossings = true
))]
#[allow(clippy::too_many_arguments)]
pub fn dent(
    py: Python<'_>,
    target_positions: &Bound<'_, PyAny>,
    target_faces: &Bound<'_, PyAny>,
    projectile_positions: &Bound<'_, PyAny>,
    projectile_faces: &Bound<'_, PyAny>,
    point: &Bound<'_, PyAny>,
    normal: &Bound<'_, PyAny>,
    relative_velocity: &Bound<'_, PyAny>,
    dent_distance: f32,
    preserve_volume: bool,
    refine: Option<&Bound<'_, PyAny>>,
    sigma: Option<f32>,
    guard_crossings: bool,
) -> PyResult<DentResult> {
    let auto = pyo3::types::PyString::new(py, "auto");
    let request = Request::read(
        target_positions,
        target_faces,
        projectile_positions,
        projectile_faces,
        point,
        normal,
        relative_velocity,
        dent_distance,
        preserve_volume,
        refine.unwrap_or(auto.as_any()),
        sigma,
        guard_crossings,
    )?;
    let made = py.detach(|| run(request)).map_err(refused)?;
    Ok(result(py, made))
}

/// The Python result of a dent.
fn result(py: Python<'_>, made: Made) -> DentResult {
    let Made { mesh, moved, refinement, report } = made;
    let base_faces = if refinement.is_empty() { mesh.face_count() } else { refinement.base_face_count };
    let (positions, faces, _) = mesh.into_parts();
    let face_parents: Vec<u32> = (0..base_faces as u32).chain(refinement.face_parents.iter().copied()).collect();
    let parents: Vec<[u32; 2]> = refinement.vertices.iter().map(|v| v.parents).collect();
    let fractions: Vec<f32> = refinement.vertices.iter().map(|v| v.fraction).collect();
    DentResult {
        positions: positions_out(py, positions).unbind(),
        faces: rows_out(py, faces).unbind(),
        moved: list_out(py, moved).unbind(),
        max_displacement: report.max_displacement,
        kept: report.limited_to.unwrap_or(1.0),
        parents: rows_out(py, parents).unbind(),
        fractions: list_out(py, fractions).unbind(),
        face_parents: list_out(py, face_parents).unbind(),
        warnings: report.warnings,
    }
}

/// The median time of the Rust call `dentbend.dent(*arguments)` makes (the meshes made from
/// the arrays and the dent, no Python object involved), s, over `repeats` runs: the baseline
/// of the Python overhead benchmark. `arguments` are `dent`'s eight positional arguments.
#[pyfunction]
pub fn rust_dent_seconds(py: Python<'_>, arguments: &Bound<'_, PyTuple>, repeats: usize) -> PyResult<f64> {
    let items: Vec<Bound<'_, PyAny>> = arguments.iter().collect();
    let [tp, tf, pp, pf, point, normal, velocity, distance] = items.as_slice() else {
        return Err(refused(format!("dent takes 8 positional arguments, got {}", items.len())));
    };
    let distance: f32 = distance.extract()?;
    let auto = pyo3::types::PyString::new(py, "auto");
    let read = || Request::read(tp, tf, pp, pf, point, normal, velocity, distance, false, auto.as_any(), None, true);
    let mut times = Vec::with_capacity(repeats.max(1));
    for _ in 0..repeats.max(1) {
        let request = read()?;
        let seconds = py.detach(|| {
            let start = Instant::now();
            let made = run(request);
            let elapsed = start.elapsed().as_secs_f64();
            made.map(|made| (elapsed, made))
        });
        let (elapsed, made) = seconds.map_err(refused)?;
        drop(made);
        times.push(elapsed);
    }
    times.sort_by(f64::total_cmp);
    Ok(times[times.len() / 2])
}
