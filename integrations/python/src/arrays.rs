//! numpy arrays in and out: positions `(N, 3)` float32 and faces `(M, 3)` uint32 read in place
//! when they already have that layout, converted once otherwise (positions rounded to float32,
//! faces range-checked first); results handed to numpy without a second copy.

use dentbend::glam::{Affine3A, Vec2, Vec3};
use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyAnyMethods;

use crate::DentError;

/// A `DentError` with `message`.
pub fn refused(message: impl Into<String>) -> PyErr {
    DentError::new_err(message.into())
}

/// `value` as a C-contiguous numpy array of `dtype` with `width` columns (`what` names it in
/// errors): in place when it is one already, else converted, where `kinds` (numpy dtype kind
/// letters) lists the dtypes accepted for conversion.
fn contiguous<'py>(
    value: &Bound<'py, PyAny>,
    dtype: &str,
    width: usize,
    kinds: &str,
    what: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let py = value.py();
    let numpy = py.import("numpy")?;
    let array = numpy.call_method1("asarray", (value,)).map_err(|e| refused(format!("{what}: not an array ({e})")))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    let name: String = array.getattr("dtype")?.getattr("name")?.extract()?;
    if !kinds.contains(kind.as_str()) {
        return Err(refused(format!("{what} has dtype {name}: it must be {dtype}, or a float or integer dtype")));
    }
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if !(shape.len() == 2 && shape[1] == width) {
        return Err(refused(format!("{what} has shape {shape:?}: it must be (count, {width})")));
    }
    numpy.call_method1("ascontiguousarray", (array, dtype))
}

/// Vertex positions, m: an `(N, 3)` array of float32 (read in place), or of another float or
/// integer dtype (converted).
pub fn positions(value: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Vec3>> {
    let converted;
    let array = match value.cast::<PyArray2<f32>>() {
        Ok(array) if array.is_c_contiguous() && array.shape()[1] == 3 => array,
        _ => {
            converted = contiguous(value, "float32", 3, "fiu", what)?;
            converted.cast::<PyArray2<f32>>().map_err(|e| refused(format!("{what}: {e}")))?
        }
    };
    let read = array.try_readonly().map_err(|e| refused(format!("{what}: {e}")))?;
    let flat = read.as_slice().map_err(|e| refused(format!("{what}: {e}")))?;
    Ok(flat.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect())
}

/// Texture coordinates: an `(N, 2)` array of float32 (converted from another float or integer
/// dtype).
pub fn uvs(value: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Vec2>> {
    let converted = contiguous(value, "float32", 2, "fiu", what)?;
    let array = converted.cast::<PyArray2<f32>>().map_err(|e| refused(format!("{what}: {e}")))?;
    let read = array.try_readonly().map_err(|e| refused(format!("{what}: {e}")))?;
    let flat = read.as_slice().map_err(|e| refused(format!("{what}: {e}")))?;
    Ok(flat.chunks_exact(2).map(|p| Vec2::new(p[0], p[1])).collect())
}

/// UVs as a new `(N, 2)` float32 array.
pub fn uvs_out<'py>(py: Python<'py>, uvs: &[Vec2]) -> Bound<'py, PyArray2<f32>> {
    let flat: Vec<f32> = uvs.iter().flat_map(|p| p.to_array()).collect();
    Array2::from_shape_vec((uvs.len(), 2), flat).expect("2 values a point").into_pyarray(py)
}

/// Triangles: an `(M, 3)` array of uint32 vertex indices (read in place), or of another
/// integer dtype whose values fit (converted).
pub fn faces(value: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[u32; 3]>> {
    let converted;
    let array = match value.cast::<PyArray2<u32>>() {
        Ok(array) if array.is_c_contiguous() && array.shape()[1] == 3 => array,
        _ => {
            // Unsigned indices are range-checked as uint64, signed ones as int64: no wrapping.
            // One conversion of a list or tuple to an array, read twice below.
            let array = value
                .py()
                .import("numpy")?
                .call_method1("asarray", (value,))
                .map_err(|e| refused(format!("{what}: not an array ({e})")))?;
            let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
            let wide = if kind == "u" { "uint64" } else { "int64" };
            let checked = contiguous(&array, wide, 3, "iu", what)?;
            if checked.getattr("size")?.extract::<usize>()? > 0 {
                let (low, high): (i128, i128) =
                    (checked.call_method0("min")?.extract()?, checked.call_method0("max")?.extract()?);
                if low < 0 || high > i128::from(u32::MAX) {
                    return Err(refused(format!(
                        "{what} has indices from {low} to {high}: vertex indices are from 0 to {}",
                        u32::MAX
                    )));
                }
            }
            converted = checked.call_method1("astype", ("uint32",))?;
            converted.cast::<PyArray2<u32>>().map_err(|e| refused(format!("{what}: {e}")))?
        }
    };
    let read = array.try_readonly().map_err(|e| refused(format!("{what}: {e}")))?;
    let flat = read.as_slice().map_err(|e| refused(format!("{what}: {e}")))?;
    Ok(flat.chunks_exact(3).map(|f| [f[0], f[1], f[2]]).collect())
}

/// Three numbers (a point or a vector).
pub fn vec3(value: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec3> {
    if let Ok([x, y, z]) = value.extract::<[f32; 3]>() {
        return Ok(Vec3::new(x, y, z));
    }
    let numbers = numbers(value, what, 3)?;
    Ok(Vec3::new(numbers[0], numbers[1], numbers[2]))
}

/// `count` numbers from a sequence or array, as float32.
fn numbers(value: &Bound<'_, PyAny>, what: &str, count: usize) -> PyResult<Vec<f32>> {
    let numpy = value.py().import("numpy")?;
    let array = numpy.call_method1("asarray", (value,)).map_err(|e| refused(format!("{what}: {e}")))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    let size: usize = array.getattr("size")?.extract()?;
    if !"fiu".contains(kind.as_str()) || size != count {
        return Err(refused(format!("{what} must be {count} numbers")));
    }
    array.call_method1("reshape", (count,))?.call_method1("astype", ("float32",))?.call_method0("tolist")?.extract()
}

/// A rigid placement, mesh -> world: a 4x4 matrix (the last row 0 0 0 1) or the 3x4 top of
/// one, whose 3x3 part is a rotation (orthonormal within 1e-4, determinant +1: dentbend works
/// in metres, so a scaled body is given scaled positions instead); `None` is the identity.
pub fn pose(value: Option<&Bound<'_, PyAny>>, what: &str) -> PyResult<Affine3A> {
    let Some(value) = value.filter(|v| !v.is_none()) else {
        return Ok(Affine3A::IDENTITY);
    };
    let numpy = value.py().import("numpy")?;
    let array = numpy.call_method1("asarray", (value,)).map_err(|e| refused(format!("{what}: {e}")))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if !"fiu".contains(kind.as_str()) || !(shape == [4, 4] || shape == [3, 4]) {
        return Err(refused(format!("{what} must be a 4x4 (or 3x4) matrix of numbers, got shape {shape:?}")));
    }
    let rows: Vec<Vec<f64>> = array.call_method1("astype", ("float64",))?.call_method0("tolist")?.extract()?;
    if rows.len() == 4 && rows[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(refused(format!("{what}'s last row is {:?}: a rigid placement's is [0, 0, 0, 1]", rows[3])));
    }
    let column = |c: usize| Vec3::new(rows[0][c] as f32, rows[1][c] as f32, rows[2][c] as f32);
    let affine = Affine3A::from_cols(column(0).into(), column(1).into(), column(2).into(), column(3).into());
    if !affine.is_finite() {
        return Err(refused(format!("{what} is not finite")));
    }
    let rotation = dentbend::glam::Mat3::from(affine.matrix3);
    let off = (rotation.transpose() * rotation - dentbend::glam::Mat3::IDENTITY).abs().to_cols_array();
    if off.iter().any(|&e| e > 1e-4) || rotation.determinant() < 0.0 {
        return Err(refused(format!(
            "{what} is not a rotation and translation (scaled, sheared or mirrored): dentbend works in \
             metres, so scale the positions instead"
        )));
    }
    Ok(affine)
}

/// Positions as a new `(N, 3)` float32 array that takes over `points`' memory (no copy).
pub fn positions_out(py: Python<'_>, points: Vec<Vec3>) -> Bound<'_, PyArray2<f32>> {
    let count = points.len();
    let flat: Vec<f32> = bytemuck::allocation::try_cast_vec(points)
        .unwrap_or_else(|(_, points)| points.iter().flat_map(|p| p.to_array()).collect());
    Array2::from_shape_vec((count, 3), flat).expect("3 values a point").into_pyarray(py)
}

/// Rows of `N` values as a new `(count, N)` array that takes over `rows`' memory (no copy).
pub fn rows_out<const N: usize>(py: Python<'_>, rows: Vec<[u32; N]>) -> Bound<'_, PyArray2<u32>> {
    let count = rows.len();
    let flat: Vec<u32> =
        bytemuck::allocation::try_cast_vec(rows).unwrap_or_else(|(_, rows)| rows.as_flattened().to_vec());
    Array2::from_shape_vec((count, N), flat).expect("N values a row").into_pyarray(py)
}

/// A list as a new 1-D array, handed over without a copy.
pub fn list_out<T: numpy::Element>(py: Python<'_>, values: Vec<T>) -> Bound<'_, PyArray1<T>> {
    Array1::from_vec(values).into_pyarray(py)
}
